// RNEA, CRBA and their derivatives against central finite differences and against each other,
// at random states of every test robot.
#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/rnea.hpp"
#include "multibody/rnea_derivatives.hpp"
#include "solver/ne_residual.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

class DynamicsDerivatives : public RobotTest {};

TEST_P(DynamicsDerivatives, RneaPartialsMatchFiniteDifferences) {
  Data data(model);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd q = randomVector(rng, model.nq, 1.0);
    const Eigen::VectorXd qd = randomVector(rng, model.nq, 2.0);
    const Eigen::VectorXd qdd = randomVector(rng, model.nq, 5.0);
    rneaDerivatives(model, data, q, qd, qdd);
    const Eigen::MatrixXd dq = data.dtau_dq, dv = data.dtau_dv, H = data.H;
    const Eigen::VectorXd tau = data.tau;

    Data fd(model);
    auto tau_of_q = [&](const Eigen::VectorXd& x) { rnea(model, fd, x, qd, qdd); return Eigen::VectorXd(fd.tau); };
    auto tau_of_v = [&](const Eigen::VectorXd& x) { rnea(model, fd, q, x, qdd); return Eigen::VectorXd(fd.tau); };
    auto tau_of_a = [&](const Eigen::VectorXd& x) { rnea(model, fd, q, qd, x); return Eigen::VectorXd(fd.tau); };
    EXPECT_LT(relativeError(tau, tau_of_q(q)), 1e-14);
    EXPECT_LT(relativeError(dq, centralDifference(tau_of_q, q, 1e-6)), 1e-7) << "trial " << trial;
    EXPECT_LT(relativeError(dv, centralDifference(tau_of_v, qd, 1e-6)), 1e-7) << "trial " << trial;
    EXPECT_LT(relativeError(H, centralDifference(tau_of_a, qdd, 1e-3)), 1e-9) << "trial " << trial;
  }
}

TEST_P(DynamicsDerivatives, CrbaEqualsRneaColumns) {
  Data data(model);
  std::mt19937 rng(11);
  const Eigen::VectorXd q = randomVector(rng, model.nq, 1.0);
  crba(model, data, q);
  const Eigen::MatrixXd H = data.H;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nq);
  Model no_gravity = model;
  no_gravity.gravity.setZero();
  Data d2(no_gravity);
  Eigen::MatrixXd columns(model.nq, model.nq);
  for (int j = 0; j < model.nq; ++j) {
    rnea(no_gravity, d2, q, zero, Eigen::VectorXd::Unit(model.nq, j));
    columns.col(j) = d2.tau;
  }
  EXPECT_LT(relativeError(H, columns), 1e-13);
  EXPECT_LT(relativeError(H, H.transpose()), 1e-15);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff(), 0.0);
}

TEST_P(DynamicsDerivatives, NeResidualJacobianMatchesFiniteDifferences) {
  Data data(model);
  std::mt19937 rng(5);
  const Eigen::VectorXd q_n = randomVector(rng, model.nq, 1.0);
  const Eigen::VectorXd qd_n = randomVector(rng, model.nq, 1.0);
  const double h = 0.02;
  const Eigen::VectorXd theta = q_n + h * qd_n + randomVector(rng, model.nq, 0.01);
  Eigen::VectorXd G(model.nq);
  Eigen::MatrixXd dG(model.nq, model.nq);
  neInertialResidual(model, data, theta, q_n, qd_n, h, G, &dG);
  Data fd(model);
  auto residual = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd g(model.nq);
    neInertialResidual(model, fd, x, q_n, qd_n, h, g, nullptr);
    return g;
  };
  EXPECT_LT(relativeError(G, residual(theta)), 1e-14);
  EXPECT_LT(relativeError(dG, centralDifference(residual, theta, 1e-6)), 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Robots, DynamicsDerivatives, ::testing::ValuesIn(derivativeRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp::test
