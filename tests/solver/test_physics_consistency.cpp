// Physics with known answers for the articulated-body core:
// - a free multibody without gravity conserves kinetic energy and spatial momentum under a fine
//   reference integration (RK4 on forward dynamics q̈ = H⁻¹(τ − C q̇), re-centring the base chart);
// - the NE and PBD residuals of the same smooth trajectory agree as h → 0 (first order).
#include "multibody/crba.hpp"
#include "multibody/base_chart.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/pbd_terms.hpp"
#include "multibody/rnea.hpp"
#include "solver/ne_residual.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

Eigen::VectorXd forwardDynamics(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nq);
  rnea(model, data, q, qd, zero);
  const Eigen::VectorXd bias = data.tau;
  crba(model, data, q);
  return data.H.llt().solve(-bias);
}

Vec6 spatialMomentum(const Model& model, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  forwardKinematics(model, data, q);
  kineticEnergy(model, data, qd);  // fills data.v
  Vec6 h = Vec6::Zero();
  for (int i = 0; i < model.nq; ++i) h += data.Iw[i] * data.v[i];
  return h;
}

TEST(FreeMultibody, ConservesEnergyAndMomentumUnderFineIntegration) {
  UrdfOptions options;
  options.gravity.setZero();
  const Model model = loadUrdf(quadrupedUrdf(), options);
  Data data(model);
  std::mt19937 rng(31);
  Eigen::VectorXd q = randomVector(rng, model.nq, 0.5);
  Eigen::VectorXd qd = randomVector(rng, model.nq, 2.0);
  forwardKinematics(model, data, q);
  const double T0 = kineticEnergy(model, data, qd);
  const Vec6 h0 = spatialMomentum(model, data, q, qd);
  const double dt = 1e-3;
  double max_energy_error = 0, max_momentum_error = 0;
  for (int step = 0; step < 1000; ++step) {
    const Eigen::VectorXd k1q = qd, k1v = forwardDynamics(model, data, q, qd);
    const Eigen::VectorXd k2q = qd + 0.5 * dt * k1v, k2v = forwardDynamics(model, data, q + 0.5 * dt * k1q, k2q);
    const Eigen::VectorXd k3q = qd + 0.5 * dt * k2v, k3v = forwardDynamics(model, data, q + 0.5 * dt * k2q, k3q);
    const Eigen::VectorXd k4q = qd + dt * k3v, k4v = forwardDynamics(model, data, q + dt * k3q, k4q);
    q += dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    qd += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    rebaseFloatingChart(model, data, q, qd);
    forwardKinematics(model, data, q);
    max_energy_error = std::max(max_energy_error, std::abs(kineticEnergy(model, data, qd) - T0) / T0);
    max_momentum_error = std::max(max_momentum_error, (spatialMomentum(model, data, q, qd) - h0).norm() / h0.norm());
  }
  EXPECT_LT(max_energy_error, 1e-8);
  EXPECT_LT(max_momentum_error, 1e-8);
  // The robot really moved: a conservation test on a motionless body would prove nothing.
  EXPECT_GT(T0, 1.0);
}

class NeVersusPbd : public RobotTest {};

TEST_P(NeVersusPbd, ResidualsAgreeAsStepShrinks) {
  std::mt19937 rng(41);
  const Eigen::VectorXd q0 = randomVector(rng, model.nq, 0.5);
  const Eigen::VectorXd v0 = randomVector(rng, model.nq, 1.0);
  const Eigen::VectorXd amp = randomVector(rng, model.nq, 0.3);
  auto trajectory = [&](double t) { return Eigen::VectorXd(q0 + v0 * t + amp * std::sin(3.0 * t) + 0.2 * amp.cwiseAbs() * t * t); };
  const double t = 0.3;
  Data data(model);
  std::vector<double> errors;
  for (double h : {1e-2, 1e-3, 1e-4}) {
    const Eigen::VectorXd theta = trajectory(t + h), q_n = trajectory(t), q_prev = trajectory(t - h);
    Eigen::VectorXd G_ne(model.nq);
    neInertialResidual(model, data, theta, q_n, (q_n - q_prev) / h, h, G_ne, nullptr);

    BodyTransforms Tn, Tprev, targets;
    forwardKinematics(model, data, q_n);
    bodyTransforms(model, data, Tn);
    forwardKinematics(model, data, q_prev);
    bodyTransforms(model, data, Tprev);
    inertialTargets(Tn, Tprev, 1.0, targets);
    forwardKinematics(model, data, theta);
    Eigen::VectorXd gradI(model.nq), gradU(model.nq);
    transformEnergy(model, data, targets, h, &gradI, nullptr);
    gravityPotential(model, data, &gradU, nullptr);
    const Eigen::VectorXd G_pbd = gradI + gradU;
    errors.push_back((G_ne - G_pbd).cwiseAbs().maxCoeff() / G_ne.cwiseAbs().maxCoeff());
  }
  // First order: each tenfold smaller step cuts the disagreement about tenfold.
  EXPECT_LT(errors[1], errors[0] / 5);
  EXPECT_LT(errors[2], errors[1] / 5);
  EXPECT_LT(errors[2], 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Robots, NeVersusPbd, ::testing::ValuesIn(derivativeRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp::test
