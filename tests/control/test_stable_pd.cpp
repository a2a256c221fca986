// Stable PD at the new state (DESIGN.md 2.1, 2.2, 5): the NE torque, its Jacobian, the PBD potential
// with gradient and Hessian against finite differences, ∇P == −τ exactly, zero torque on base
// coordinates, mass-scaled default gains, and the point of stable PD — a 1-DOF joint integrated by
// backward Euler is stable for any step, where explicit PD diverges.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "control/stable_pd.hpp"
#include "test_support.hpp"

// Allocation counting: on glibc the malloc family is interposed (Eigen and operator new both go
// through it).
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"

namespace nmdp::test {
namespace {

Model loadQuadruped(BaseType base) {
  UrdfOptions options;
  options.base = base;
  return loadUrdf(quadrupedUrdf(), options);
}

// Random positive gains on actuated coordinates (zero on the base), random target and states.
struct PdCase {
  PdGains gains;
  PdTarget target;
  Eigen::VectorXd theta, q_n;
};

PdCase randomCase(const Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.1, 2.0);
  PdCase c;
  const int n = model.nq;
  c.gains.kp = Eigen::VectorXd::Zero(n);
  c.gains.kd = Eigen::VectorXd::Zero(n);
  c.gains.tau_ff = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd ff = randomVector(rng, n, 5.0);
  for (int i = 0; i < n; ++i) {
    if (model.bodies[i].is_base) continue;
    c.gains.kp[i] = 100.0 * u(rng);
    c.gains.kd[i] = u(rng);
    c.gains.tau_ff[i] = ff[i];
  }
  c.target.position = randomVector(rng, n, 1.0);
  c.target.velocity = randomVector(rng, n, 2.0);
  c.q_n = randomVector(rng, n, 1.0);
  c.theta = c.q_n + randomVector(rng, n, 0.05);
  return c;
}

class StablePdRobots : public ::testing::TestWithParam<BaseType> {};

TEST_P(StablePdRobots, GradientAndHessianMatchFiniteDifferences) {
  const Model model = loadQuadruped(GetParam());
  std::mt19937 rng(7);
  for (double h : {1e-3, 1e-2, 0.1}) {
    const PdCase c = randomCase(model, rng);
    Eigen::VectorXd grad(model.nq), hess(model.nq);
    pdPotentialGradient(c.gains, c.target, c.theta, c.q_n, h, grad);
    pdPotentialHessianDiagonal(c.gains, h, hess);

    const double eps = 1e-6;
    Eigen::VectorXd fd_grad(model.nq);
    for (int j = 0; j < model.nq; ++j) {
      Eigen::VectorXd tp = c.theta, tm = c.theta;
      tp[j] += eps;
      tm[j] -= eps;
      fd_grad[j] = (pdPotential(c.gains, c.target, tp, c.q_n, h) - pdPotential(c.gains, c.target, tm, c.q_n, h)) /
                   (2 * eps);
    }
    EXPECT_LT(relativeError(grad, fd_grad), 1e-6) << "h = " << h;

    const auto gradient = [&](const Eigen::VectorXd& x) {
      Eigen::VectorXd g(model.nq);
      pdPotentialGradient(c.gains, c.target, x, c.q_n, h, g);
      return g;
    };
    const Eigen::MatrixXd fd_hess = centralDifference(gradient, c.theta, 1e-5);
    const Eigen::MatrixXd H = hess.asDiagonal();
    EXPECT_LT(relativeError(H, fd_hess), 1e-6) << "h = " << h;

    // The NE Jacobian is the negated Hessian, and matches finite differences of τ.
    Eigen::VectorXd jac(model.nq);
    pdTorqueJacobianDiagonal(c.gains, h, jac);
    EXPECT_EQ(jac, -hess);
    const auto torque = [&](const Eigen::VectorXd& x) {
      Eigen::VectorXd t(model.nq);
      pdTorque(c.gains, c.target, x, c.q_n, h, t);
      return t;
    };
    const Eigen::MatrixXd J = jac.asDiagonal();
    EXPECT_LT(relativeError(J, centralDifference(torque, c.theta, 1e-5)), 1e-6) << "h = " << h;
    // ... and is −(K_p + K_d/h) on actuated coordinates.
    for (int i = 0; i < model.nq; ++i) EXPECT_DOUBLE_EQ(jac[i], -(c.gains.kp[i] + c.gains.kd[i] / h));
  }
}

TEST_P(StablePdRobots, PotentialGradientIsExactlyMinusTorque) {
  const Model model = loadQuadruped(GetParam());
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const double h = std::pow(10.0, -3.0 + 3.0 * trial / 19.0);  // 1 ms .. 1 s
    const PdCase c = randomCase(model, rng);
    Eigen::VectorXd grad(model.nq), tau(model.nq);
    pdPotentialGradient(c.gains, c.target, c.theta, c.q_n, h, grad);
    pdTorque(c.gains, c.target, c.theta, c.q_n, h, tau);
    for (int i = 0; i < model.nq; ++i) EXPECT_EQ(grad[i], -tau[i]) << "coordinate " << i << ", h = " << h;  // bitwise

    // τ matches the NE formula written out independently.
    const Eigen::VectorXd theta_dot = (c.theta - c.q_n) / h;
    const Eigen::VectorXd expected = -c.gains.kp.cwiseProduct(c.theta - c.target.position) -
                                     c.gains.kd.cwiseProduct(theta_dot - c.target.velocity) + c.gains.tau_ff;
    EXPECT_LT((tau - expected).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  }
}

TEST_P(StablePdRobots, BaseCoordinatesGetZeroTorque) {
  const Model model = loadQuadruped(GetParam());
  std::mt19937 rng(3);
  PdCase c = randomCase(model, rng);
  c.gains = massScaledPdGains(model);
  c.gains.tau_ff.setConstant(0.0);
  for (int i = 0; i < model.nq; ++i)
    if (!model.bodies[i].is_base) c.gains.tau_ff[i] = 0.5;
  // Base target entries are ignored, even if they are garbage.
  int nbase = 0;
  for (int i = 0; i < model.nq; ++i) {
    if (!model.bodies[i].is_base) continue;
    ++nbase;
    c.target.position[i] = std::numeric_limits<double>::quiet_NaN();
    c.target.velocity[i] = std::numeric_limits<double>::infinity();
  }
  EXPECT_EQ(nbase, GetParam() == BaseType::Floating ? 6 : GetParam() == BaseType::Planar ? 3 : 0);
  const double h = 0.01;
  Eigen::VectorXd tau(model.nq), grad(model.nq), jac(model.nq), hess(model.nq);
  pdTorque(c.gains, c.target, c.theta, c.q_n, h, tau);
  pdPotentialGradient(c.gains, c.target, c.theta, c.q_n, h, grad);
  pdTorqueJacobianDiagonal(c.gains, h, jac);
  pdPotentialHessianDiagonal(c.gains, h, hess);
  EXPECT_TRUE(std::isfinite(pdPotential(c.gains, c.target, c.theta, c.q_n, h)));
  for (int i = 0; i < model.nq; ++i) {
    ASSERT_TRUE(std::isfinite(tau[i])) << i;
    if (model.bodies[i].is_base) {
      EXPECT_EQ(tau[i], 0.0) << model.bodies[i].joint_name;
      EXPECT_EQ(grad[i], 0.0);
      EXPECT_EQ(jac[i], 0.0);
      EXPECT_EQ(hess[i], 0.0);
    } else {
      EXPECT_NE(tau[i], 0.0) << model.bodies[i].joint_name;
      EXPECT_LT(jac[i], 0.0);
    }
  }
  EXPECT_NO_THROW(validatePdGains(model, c.gains));
}

TEST_P(StablePdRobots, MassScaledGainsScaleLinearlyWithMass) {
  const Model model = loadQuadruped(GetParam());
  // The project's quadruped: 9 + 0.01 + 4·(0.7 + 1.1 + 0.25 + 0.05) = 17.41 kg (whatever the base).
  ASSERT_NEAR(model.total_mass, 17.41, 1e-9);
  const PdGains g = massScaledPdGains(model);
  ASSERT_EQ(g.kp.size(), model.nq);
  ASSERT_EQ(g.kd.size(), model.nq);
  ASSERT_EQ(g.tau_ff.size(), model.nq);
  int actuated = 0;
  for (int i = 0; i < model.nq; ++i) {
    EXPECT_EQ(g.tau_ff[i], 0.0);
    if (model.bodies[i].is_base) {
      EXPECT_EQ(g.kp[i], 0.0);
      EXPECT_EQ(g.kd[i], 0.0);
    } else {
      ++actuated;
      EXPECT_NEAR(g.kp[i], 174.1, 1e-12);
      EXPECT_NEAR(g.kd[i], 0.1741, 1e-15);
    }
  }
  EXPECT_EQ(actuated, 12);
  EXPECT_NO_THROW(validatePdGains(model, g));

  // Linear in mass: the DESIGN reference robot (100 kg) gets exactly K_p = 1000, K_d = 1, and
  // doubling the mass doubles the gains.
  Model scaled = model;
  scaled.total_mass = 100.0;
  const PdGains ref = massScaledPdGains(scaled);
  scaled.total_mass = 200.0;
  const PdGains twice = massScaledPdGains(scaled);
  for (int i = 0; i < model.nq; ++i) {
    if (model.bodies[i].is_base) continue;
    EXPECT_DOUBLE_EQ(ref.kp[i], 1000.0);
    EXPECT_DOUBLE_EQ(ref.kd[i], 1.0);
    EXPECT_DOUBLE_EQ(twice.kp[i], 2000.0);
    EXPECT_DOUBLE_EQ(twice.kd[i], 2.0);
  }
  scaled.total_mass = 0.0;
  EXPECT_THROW(massScaledPdGains(scaled), std::invalid_argument);
}

TEST_P(StablePdRobots, ValidateRejectsBadGains) {
  const Model model = loadQuadruped(GetParam());
  const PdGains good = massScaledPdGains(model);
  PdGains bad = good;
  bad.kp.resize(model.nq - 1);
  EXPECT_THROW(validatePdGains(model, bad), std::invalid_argument);
  bad = good;
  bad.kd[model.nq - 1] = -1.0;
  EXPECT_THROW(validatePdGains(model, bad), std::invalid_argument);
  bad = good;
  bad.tau_ff[model.nq - 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validatePdGains(model, bad), std::invalid_argument);
  if (model.bodies[0].is_base) {
    bad = good;
    bad.kp[0] = 1.0;
    EXPECT_THROW(validatePdGains(model, bad), std::invalid_argument);
  }
}

TEST_P(StablePdRobots, AllocatesNothing) {
  const Model model = loadQuadruped(GetParam());
  std::mt19937 rng(5);
  const PdCase c = randomCase(model, rng);
  Eigen::VectorXd tau(model.nq), grad(model.nq), jac(model.nq), hess(model.nq);
  const double* data[4] = {tau.data(), grad.data(), jac.data(), hess.data()};
  double sum = 0.0;
  const AllocationCount count = countAllocations([&] {
    pdTorque(c.gains, c.target, c.theta, c.q_n, 0.01, tau);
    pdPotentialGradient(c.gains, c.target, c.theta, c.q_n, 0.01, grad);
    pdTorqueJacobianDiagonal(c.gains, 0.01, jac);
    pdPotentialHessianDiagonal(c.gains, 0.01, hess);
    sum += pdPotential(c.gains, c.target, c.theta, c.q_n, 0.01);
  });
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_EQ(count.mallocs, 0);
  EXPECT_EQ(data[0], tau.data());
  EXPECT_EQ(data[1], grad.data());
  EXPECT_EQ(data[2], jac.data());
  EXPECT_EQ(data[3], hess.data());
  // Negative control: an unsized output is resized once, and the counter sees it.
  Eigen::VectorXd unsized;
  const AllocationCount resized = countAllocations([&] { pdTorque(c.gains, c.target, c.theta, c.q_n, 0.01, unsized); });
  EXPECT_EQ(unsized.size(), model.nq);
  if (NMDP_COUNTS_MALLOC) {
    EXPECT_GE(resized.mallocs, 1);
  }
  if (!NMDP_COUNTS_MALLOC) GTEST_SKIP() << "malloc is not interposed here; only output buffers were checked";
}

INSTANTIATE_TEST_SUITE_P(Bases, StablePdRobots,
                         ::testing::Values(BaseType::Floating, BaseType::Planar, BaseType::Fixed),
                         [](const ::testing::TestParamInfo<BaseType>& info) {
                           return std::string(baseTypeName(info.param));
                         });

// --- 1 DOF: fixed-base single revolute joint with inertia I, no gravity ------------------------

struct OneDof {
  double inertia = 0.01;  // kg·m²
  PdGains gains;
  PdTarget target;
  OneDof(double kp, double kd, double tau_ff, double target_position) {
    gains.kp = Eigen::VectorXd::Constant(1, kp);
    gains.kd = Eigen::VectorXd::Constant(1, kd);
    gains.tau_ff = Eigen::VectorXd::Constant(1, tau_ff);
    target.position = Eigen::VectorXd::Constant(1, target_position);
    target.velocity = Eigen::VectorXd::Zero(1);
  }
};

// One backward-Euler step with stable PD: θ solves r(θ) = I(θ − q_n)/h² − I q̇_n/h − τ(θ) = 0.
// r is linear in θ, so one Newton step from q_n with r' = I/h² − ∂τ/∂θ (from the API) is exact;
// it is checked against the closed form
//   θ = (I q_n/h² + I q̇_n/h + K_p θ̄ + K_d (q_n/h + θ̄̇) + τ_ff) / (I/h² + K_p + K_d/h).
void stablePdStep(const OneDof& s, double h, double& q, double& qd) {
  Eigen::VectorXd q_n = Eigen::VectorXd::Constant(1, q), tau(1), jac(1);
  pdTorque(s.gains, s.target, q_n, q_n, h, tau);
  pdTorqueJacobianDiagonal(s.gains, h, jac);
  const double I = s.inertia;
  const double r0 = -I * qd / h - tau[0];
  const double theta = q - r0 / (I / (h * h) - jac[0]);

  const double kp = s.gains.kp[0], kd = s.gains.kd[0];
  const double closed = (I * q / (h * h) + I * qd / h + kp * s.target.position[0] +
                         kd * (q / h + s.target.velocity[0]) + s.gains.tau_ff[0]) /
                        (I / (h * h) + kp + kd / h);
  EXPECT_NEAR(theta, closed, 1e-9 * std::max(1.0, std::abs(closed)));
  // The residual vanishes at the new state.
  Eigen::VectorXd th = Eigen::VectorXd::Constant(1, theta);
  pdTorque(s.gains, s.target, th, q_n, h, tau);
  const double residual = I * (theta - q) / (h * h) - I * qd / h - tau[0];
  EXPECT_LT(std::abs(residual), 1e-7 * (I / (h * h) + kp + kd / h) * std::max(1.0, std::abs(theta)));

  qd = (theta - q) / h;
  q = theta;
}

// Explicit PD at (q_n, q̇_n) with semi-implicit Euler (the NE-MDP baseline of DESIGN.md 6).
void explicitPdStep(const OneDof& s, double h, double& q, double& qd) {
  const double tau = -s.gains.kp[0] * (q - s.target.position[0]) - s.gains.kd[0] * (qd - s.target.velocity[0]) +
                     s.gains.tau_ff[0];
  qd += h * tau / s.inertia;
  q += h * qd;
}

TEST(StablePdOneDof, UnconditionallyStableAndConvergesWithoutOvershootGrowth) {
  // ω = √(K_p/I) ≈ 31.6 rad/s, damping ratio K_d/(2√(K_p I)) ≈ 0.16: a lightly damped servo.
  const OneDof s(10.0, 0.1, 0.0, 1.0);
  const double I = s.inertia, kp = s.gains.kp[0];
  for (double h : {1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    double q = 0.0, qd = 0.0;
    const double e0 = std::abs(q - s.target.position[0]);
    // With a constant target the discrete energy V = ½ I q̇² + ½ K_p e² never increases under
    // backward Euler (V_{n+1} − V_n = −h K_d q̇²_{n+1} − ½‖Δx‖²_P ≤ 0): no overshoot growth, and
    // |e| ≤ |e_0| always.
    double energy = 0.5 * kp * e0 * e0;
    const int steps = static_cast<int>(std::ceil(20.0 / h));
    double max_error = 0.0;
    for (int n = 0; n < steps; ++n) {
      stablePdStep(s, h, q, qd);
      const double e = q - s.target.position[0];
      const double v = 0.5 * I * qd * qd + 0.5 * kp * e * e;
      ASSERT_LE(v, energy * (1 + 1e-12) + 1e-26) << "energy grew at step " << n;
      energy = v;
      max_error = std::max(max_error, std::abs(e));
    }
    EXPECT_LE(max_error, e0 * (1 + 1e-12));
    EXPECT_LT(std::abs(q - s.target.position[0]), 1e-6);  // converged to the target
    EXPECT_LT(std::abs(qd), 1e-5);
  }
}

TEST(StablePdOneDof, FeedForwardShiftsTheEquilibrium) {
  const OneDof s(10.0, 0.1, 2.0, 0.5);  // equilibrium θ* = θ̄ + τ_ff/K_p = 0.7
  for (double h : {1e-3, 0.1, 1.0}) {
    double q = 0.0, qd = 0.0;
    for (int n = 0; n < static_cast<int>(std::ceil(20.0 / h)); ++n) stablePdStep(s, h, q, qd);
    EXPECT_NEAR(q, 0.7, 1e-6) << "h = " << h;
  }
}

TEST(StablePdOneDof, ExplicitPdDivergesAtLargeStepsWhereStablePdDoesNot) {
  const OneDof s(10.0, 0.1, 0.0, 1.0);
  const double omega = std::sqrt(s.gains.kp[0] / s.inertia);
  // Small step (ω h ≈ 0.03): both converge.
  {
    double q = 0.0, qd = 0.0;
    for (int n = 0; n < 20000; ++n) explicitPdStep(s, 1e-3, q, qd);
    EXPECT_NEAR(q, 1.0, 1e-6);
  }
  // Large steps (ω h ≈ 3.2 and 31.6, beyond the explicit limit ω h < 2): explicit PD blows up
  // within a few dozen steps, stable PD converges.
  for (double h : {0.1, 1.0}) {
    ASSERT_GT(omega * h, 2.0);
    double qe = 0.0, qde = 0.0, qs = 0.0, qds = 0.0;
    for (int n = 0; n < 50; ++n) {
      explicitPdStep(s, h, qe, qde);
      stablePdStep(s, h, qs, qds);
    }
    EXPECT_GT(std::abs(qe - 1.0), 1e6) << "explicit PD at h = " << h;
    EXPECT_LT(std::abs(qs - 1.0), 1e-3) << "stable PD at h = " << h;
  }
}

}  // namespace
}  // namespace nmdp::test
