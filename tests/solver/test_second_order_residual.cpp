// StepResidual::prepareSecondOrder (variable-step BDF2, solver/bdf2.hpp) against independent
// computations and central finite differences, in both forms and for every K measure, on the
// quadruped with its feet in the ground (floating and planar base, with armature):
//  * NE: G = RNEA(θ, θ̇, θ̈) − τ − f_ext − B w with θ̇ = (α0θ + α1q_n + α2q_{n−1})/h and
//    θ̈ = (α0θ̇ + α1q̇_n + α2q̇_{n−1})/h written with the α coefficients;
//  * PBD: G(θ, 0) = FD of an energy assembled here, whose inertial targets are the BDF2 combination
//    of T(q_n), T(q_{n−1}) and their rates, the rates taken by central differences of T along q̇;
//  * ∂G/∂θ and ∇K against FD; ∇²K against FD (PBD, full-body and full-body-pd) or against its
//    Gauss–Newton form (NE: H/ĥ² (+ K_p + K_d/ĥ); contact points: Σ J_cᵀJ_c/ĥ²).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "contact_models/coulomb_model.hpp"
#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/pbd_terms.hpp"
#include "multibody/rnea.hpp"
#include "solver/step_residual.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"

namespace nmdp {
namespace {

using test::centralDifference;
using test::relativeError;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

struct Scene {
  Model model;
  CoulombModel contact_model;
  PlaneTerrain terrain;
  System system;
  explicit Scene(BaseType base) : model(loadUrdf(test::quadrupedUrdf(), [&] {
    UrdfOptions o;
    o.base = base;
    o.default_armature = 0.02;
    return o;
  }())) {
    system = systemOnFeet(model, contact_model, terrain, massScaledPdGains(model));
  }
  double deepest(const Vec& q) const {
    Data data(model);
    forwardKinematics(model, data, q);
    double d = 0;
    for (const ContactPoint& c : system.contacts) d = std::max(d, c.radius - linkPoint(model, data, c.link, c.offset).z());
    return d;
  }
};

struct Step {
  Vec theta, q_n, qd_n, q_prev, qd_prev, w;
  double h = 0.02, h_prev = 0.03;  // ω = 2/3
  PdTarget target;
};

Step randomStep(Scene& s, std::mt19937& rng) {
  const int n = s.model.nq;
  Step d;
  d.theta = Vec::Zero(n);
  for (int j = 0; j < n; ++j)
    if (!s.model.bodies[j].is_base) d.theta[j] = 0.02 * std::uniform_real_distribution<double>(-1, 1)(rng);
  d.theta[s.model.dofIndex("base_z")] -= s.deepest(d.theta) - 0.005;  // the deepest foot 5 mm in
  d.q_n = d.theta - d.h * test::randomVector(rng, n, 0.3);
  d.qd_n = test::randomVector(rng, n, 0.5);
  d.q_prev = d.q_n - d.h_prev * test::randomVector(rng, n, 0.3);
  d.qd_prev = test::randomVector(rng, n, 0.5);
  const int K = s.contact_model.vertexCount(), C = static_cast<int>(s.system.contacts.size());
  d.w = Vec::Zero(C * K);
  for (int c = 0; c < C; ++c) {
    for (int i = 0; i < K; ++i) d.w[c * K + i] = std::uniform_real_distribution<double>(0, 1)(rng);
    d.w.segment(c * K, K) *= 0.6 / d.w.segment(c * K, K).sum();
  }
  d.target.position = d.theta + test::randomVector(rng, n, 0.1);
  d.target.velocity = test::randomVector(rng, n, 0.5);
  s.system.gains.tau_ff = test::randomVector(rng, n, 2.0);
  for (int j = 0; j < n; ++j)
    if (s.model.bodies[j].is_base) s.system.gains.tau_ff[j] = 0.0;
  s.system.external_force = test::randomVector(rng, n, 5.0);
  return d;
}

// The α coefficients of variable-step BDF2.
struct Alpha {
  double a0, a1, a2;
  explicit Alpha(double w) : a0((1 + 2 * w) / (1 + w)), a1(-(1 + w)), a2(w * w / (1 + w)) {}
};

void prepare(Scene& s, StepResidual& r, Form form, const Step& d, KineticEnergyMeasure k) {
  r.prepareSecondOrder(s.system, form, bdf2Coefficients(d.h, d.h_prev), d.q_n, d.qd_n, d.q_prev, d.qd_prev, d.target,
                       Mat3::Identity(), k);
}

void checkSecondOrderResidual(BaseType base, Form form, KineticEnergyMeasure k, unsigned seed) {
  Scene s(base);
  std::mt19937 rng(seed);
  const Step d = randomStep(s, rng);
  const int n = s.model.nq;
  const Alpha al(d.h / d.h_prev);
  const double h_hat = d.h / al.a0;
  StepResidual r(s.system), fd(s.system);
  prepare(s, r, form, d, k);
  prepare(s, fd, form, d, k);
  EXPECT_NEAR(r.h(), h_hat, 1e-15);
  r.evaluate(s.system, d.theta, d.w, ContactDerivative::Model);
  const Vec G = r.G, gradK = r.grad_K;
  const Mat dG = r.dG_dtheta, hessK = r.hess_K, B = r.B;
  EXPECT_GT(B.cwiseAbs().maxCoeff(), 0.0);

  // --- G's value.
  double e_value = 0;
  if (form == Form::NewtonEuler) {
    Data data(s.model);
    const Vec thd = (al.a0 * d.theta + al.a1 * d.q_n + al.a2 * d.q_prev) / d.h;
    const Vec thdd = (al.a0 * thd + al.a1 * d.qd_n + al.a2 * d.qd_prev) / d.h;
    rnea(s.model, data, d.theta, thd, thdd);
    Vec tau = Vec::Zero(n);
    for (int j = 0; j < n; ++j)
      tau[j] = -s.system.gains.kp[j] * (d.theta[j] - d.target.position[j]) -
               s.system.gains.kd[j] * (thd[j] - d.target.velocity[j]) + s.system.gains.tau_ff[j];
    e_value = relativeError(G, Vec(data.tau - tau - s.system.external_force - B * d.w));
    EXPECT_LT(e_value, 1e-9);
  } else {
    // Targets: T̂ + ĥ V̂ with T̂ = −(α1 T_n + α2 T_{n−1})/α0, V̂ likewise from the rates, the rates
    // Ṫ = dT(q + t q̇)/dt by central differences.
    Data data(s.model);
    auto transforms = [&](const Vec& q, BodyTransforms& T) {
      forwardKinematics(s.model, data, q);
      bodyTransforms(s.model, data, T);
    };
    auto rates = [&](const Vec& q, const Vec& qd, BodyTransforms& out) {
      const double e = 1e-6;
      BodyTransforms plus, minus;
      transforms(q + e * qd, plus);
      transforms(q - e * qd, minus);
      out.resize(plus.size());
      for (size_t b = 0; b < plus.size(); ++b) out[b] = (plus[b] - minus[b]) / (2 * e);
    };
    BodyTransforms Tn, Tp, Vn, Vp, C;
    transforms(d.q_n, Tn);
    transforms(d.q_prev, Tp);
    rates(d.q_n, d.qd_n, Vn);
    rates(d.q_prev, d.qd_prev, Vp);
    C.resize(Tn.size());
    for (size_t b = 0; b < Tn.size(); ++b)
      C[b] = -(al.a1 * Tn[b] + al.a2 * Tp[b]) / al.a0 - h_hat * (al.a1 * Vn[b] + al.a2 * Vp[b]) / al.a0;
    const Vec q_hat = -(al.a1 * d.q_n + al.a2 * d.q_prev) / al.a0, v_hat = -(al.a1 * d.qd_n + al.a2 * d.qd_prev) / al.a0;
    auto energy = [&](const Vec& th) {
      forwardKinematics(s.model, data, th);
      double E = transformEnergy(s.model, data, C, h_hat, nullptr, nullptr) + gravityPotential(s.model, data, nullptr, nullptr) +
                 pdPotential(s.system.gains, d.target, th, q_hat, h_hat) - s.system.external_force.dot(th);
      for (int j = 0; j < n; ++j) {
        const double x = th[j] - q_hat[j] - h_hat * v_hat[j];
        E += 0.5 * s.model.bodies[j].armature * x * x / (h_hat * h_hat);
      }
      return Vec::Constant(1, E);
    };
    fd.evaluate(s.system, d.theta, Vec::Zero(d.w.size()), ContactDerivative::Dropped);
    e_value = relativeError(fd.G, Vec(centralDifference(energy, d.theta, 1e-6).transpose()));
    EXPECT_LT(e_value, 1e-6);
  }

  // --- ∂G/∂θ and ∇K against central differences.
  const double eps = 1e-6;
  const Mat dG_fd = centralDifference([&](const Vec& th) {
    fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
    return Vec(fd.G);
  }, d.theta, eps);
  const Vec gradK_fd = centralDifference([&](const Vec& th) {
    fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
    return Vec::Constant(1, fd.K);
  }, d.theta, eps).transpose();
  const double e_dG = relativeError(dG, dG_fd), e_gradK = relativeError(gradK, gradK_fd);
  EXPECT_LT(e_dG, 1e-6);
  EXPECT_LT(e_gradK, 1e-6);

  // --- ∇²K: exact in PBD (but for contact points), Gauss–Newton otherwise.
  double e_hessK = 0;
  Vec pd(n);
  for (int j = 0; j < n; ++j) pd[j] = s.system.gains.kp[j] + s.system.gains.kd[j] / h_hat;
  if (k == KineticEnergyMeasure::ContactPoints) {
    Data data(s.model);
    forwardKinematics(s.model, data, d.theta);
    Mat gn = Mat::Zero(n, n);
    for (const ContactPoint& c : s.system.contacts) {
      Eigen::Matrix<double, 3, Eigen::Dynamic> J(3, n);
      pointJacobian(s.model, data, s.model.links[c.link].body, linkPoint(s.model, data, c.link, c.offset), J);
      gn += J.transpose() * J / (h_hat * h_hat);
    }
    e_hessK = relativeError(hessK, gn);
    EXPECT_LT(e_hessK, 1e-12);
  } else if (form == Form::NewtonEuler) {
    Data data(s.model);
    crba(s.model, data, d.theta);
    Mat expected = data.H / (h_hat * h_hat);
    if (k == KineticEnergyMeasure::FullBodyPd) expected.diagonal() += pd;
    e_hessK = relativeError(hessK, expected);
    EXPECT_LT(e_hessK, 1e-12);
  } else {
    const Mat hessK_fd = centralDifference([&](const Vec& th) {
      fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
      return Vec(fd.grad_K);
    }, d.theta, eps);
    e_hessK = relativeError(hessK, hessK_fd);
    EXPECT_LT(e_hessK, 1e-6);
  }
  std::printf("  order 2 %s %-7s %-14s: G value %.2e, dG/dθ vs FD %.2e, ∇K vs FD %.2e, ∇²K %.2e (K %.3e)\n",
              form == Form::NewtonEuler ? "NE " : "PBD", base == BaseType::Floating ? "floating" : "planar",
              kineticEnergyName(k), e_value, e_dG, e_gradK, e_hessK, r.K);
}

TEST(SecondOrderResidual, DerivativesAgainstCentralDifferences) {
  unsigned seed = 1;
  for (BaseType base : {BaseType::Floating, BaseType::Planar})
    for (Form form : {Form::NewtonEuler, Form::PositionBased})
      for (KineticEnergyMeasure k :
           {KineticEnergyMeasure::FullBody, KineticEnergyMeasure::ContactPoints, KineticEnergyMeasure::FullBodyPd}) {
        SCOPED_TRACE(std::string(form == Form::NewtonEuler ? "NE " : "PBD ") + kineticEnergyName(k));
        checkSecondOrderResidual(base, form, k, seed++);
      }
}

// With ĥ = h and no extrapolation (backward Euler's coefficients, what the second-order mode takes
// without a history) the NE residual is the first-order one bit for bit: one code path.
TEST(SecondOrderResidual, BackwardEulerCoefficientsGiveTheFirstOrderNeResidual) {
  Scene s(BaseType::Floating);
  std::mt19937 rng(3);
  const Step d = randomStep(s, rng);
  StepResidual first(s.system), second(s.system);
  first.prepare(s.system, Form::NewtonEuler, d.h, d.q_n, d.qd_n, d.q_prev, d.h_prev, d.target, Mat3::Identity());
  second.prepareSecondOrder(s.system, Form::NewtonEuler, Bdf2Coefficients{d.h, 0.0}, d.q_n, d.qd_n, d.q_prev, d.qd_prev,
                            d.target, Mat3::Identity());
  first.evaluate(s.system, d.theta, d.w, ContactDerivative::Model);
  second.evaluate(s.system, d.theta, d.w, ContactDerivative::Model);
  EXPECT_EQ(first.G, second.G);
  EXPECT_EQ(first.dG_dtheta, second.dG_dtheta);
  EXPECT_EQ(first.K, second.K);
  EXPECT_EQ(first.grad_K, second.grad_K);
}

}  // namespace
}  // namespace nmdp
