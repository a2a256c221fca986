// PBD terms (DESIGN.md 2.2): gradients and exact Hessians against central differences, and their
// links to the NE quantities: ∇²K at θ = q_n is H/h², ∇U is the gravity torque of RNEA.
#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/pbd_terms.hpp"
#include "multibody/rnea.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

class PbdTerms : public RobotTest {
 protected:
  BodyTransforms transformsAt(const Eigen::VectorXd& q) {
    Data d(model);
    forwardKinematics(model, d, q);
    BodyTransforms T;
    bodyTransforms(model, d, T);
    return T;
  }
};

TEST_P(PbdTerms, InertiaTermGradientAndHessianMatchFiniteDifferences) {
  std::mt19937 rng(21);
  const Eigen::VectorXd q_prev = randomVector(rng, model.nq, 1.0);
  const Eigen::VectorXd q_n = q_prev + randomVector(rng, model.nq, 0.1);
  const Eigen::VectorXd theta = q_n + randomVector(rng, model.nq, 0.1);
  const double h = 0.03, alpha = 0.5;
  BodyTransforms targets;
  inertialTargets(transformsAt(q_n), transformsAt(q_prev), alpha, targets);

  Data data(model), fd(model);
  Eigen::VectorXd grad(model.nq);
  Eigen::MatrixXd hess(model.nq, model.nq);
  forwardKinematics(model, data, theta);
  const double E = transformEnergy(model, data, targets, h, &grad, &hess);
  auto energy = [&](const Eigen::VectorXd& x) {
    forwardKinematics(model, fd, x);
    return Eigen::VectorXd::Constant(1, transformEnergy(model, fd, targets, h, nullptr, nullptr)).eval();
  };
  auto gradient = [&](const Eigen::VectorXd& x) {
    forwardKinematics(model, fd, x);
    Eigen::VectorXd g(model.nq);
    transformEnergy(model, fd, targets, h, &g, nullptr);
    return g;
  };
  EXPECT_NEAR(E, energy(theta)[0], 1e-12 * std::abs(E));
  EXPECT_LT(relativeError(grad.transpose(), centralDifference(energy, theta, 1e-6)), 1e-7);
  EXPECT_LT(relativeError(hess, centralDifference(gradient, theta, 1e-6)), 1e-7);
  EXPECT_LT(relativeError(hess, hess.transpose()), 1e-14);
}

TEST_P(PbdTerms, KineticHessianAtCurrentStateIsMassMatrixOverH2) {
  // Armature is a joint-space term that no body carries, so it is left out of this identity.
  std::mt19937 rng(22);
  const Eigen::VectorXd q_n = randomVector(rng, model.nq, 1.0);
  const double h = 0.05;
  const BodyTransforms targets = transformsAt(q_n);
  Data data(model);
  forwardKinematics(model, data, q_n);
  Eigen::VectorXd grad(model.nq);
  Eigen::MatrixXd hess(model.nq, model.nq);
  EXPECT_EQ(transformEnergy(model, data, targets, h, &grad, &hess), 0.0);
  EXPECT_LT(grad.cwiseAbs().maxCoeff(), 1e-15);
  crba(model, data, q_n);
  EXPECT_LT(relativeError(hess * h * h, data.H), 1e-12);
}

TEST_P(PbdTerms, GravityPotentialDerivatives) {
  std::mt19937 rng(23);
  const Eigen::VectorXd q = randomVector(rng, model.nq, 1.0);
  Data data(model), fd(model);
  Eigen::VectorXd grad(model.nq);
  Eigen::MatrixXd hess(model.nq, model.nq);
  forwardKinematics(model, data, q);
  gravityPotential(model, data, &grad, &hess);
  auto potential = [&](const Eigen::VectorXd& x) {
    forwardKinematics(model, fd, x);
    return Eigen::VectorXd::Constant(1, gravityPotential(model, fd, nullptr, nullptr)).eval();
  };
  auto gradient = [&](const Eigen::VectorXd& x) {
    forwardKinematics(model, fd, x);
    Eigen::VectorXd g(model.nq);
    gravityPotential(model, fd, &g, nullptr);
    return g;
  };
  EXPECT_LT(relativeError(grad.transpose(), centralDifference(potential, q, 1e-6)), 1e-7);
  EXPECT_LT(relativeError(hess, centralDifference(gradient, q, 1e-6)), 1e-7);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nq);
  rnea(model, fd, q, zero, zero);
  EXPECT_LT(relativeError(grad, fd.tau), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Robots, PbdTerms, ::testing::ValuesIn(derivativeRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp::test
