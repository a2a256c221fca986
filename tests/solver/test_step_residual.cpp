// StepResidual (src/solver/step_residual.hpp) against independent computations and central finite
// differences, in both forms, on random penetrating contact states:
//  * G's value: NE = RNEA(θ, θ̇, θ̈) − τ(θ) − f_ext − B w; PBD (w = 0) = FD of an energy assembled here
//    from the multibody building blocks (I + U + P + armature − f_extᵀθ);
//  * ∂G/∂θ, first order: FD of G in θ;
//  * ∂Ḡ/∂θ, zeroth order: FD of θ ↦ G(θ, 0) − Σ_c J_c(θ)ᵀ V_c(θ₀) w_c (vertices frozen at θ₀), and the
//    difference first − zeroth order against −Σ_c J_cᵀ (∂V_c/∂θ) w_c built from FDs of B(θ) w;
//  * B = −∂G/∂w (G is affine in w: the difference quotient is exact up to round-off);
//  * NE: K = ½ θ̇ᵀ H θ̇ with H from crba, ∇K = H θ̇/h, ∇²K = H/h² (Gauss–Newton); ∇K equals the FD of K
//    minus the dropped ½ θ̇ᵀ(∂H/∂θ)θ̇ term (itself an FD of H);
//  * PBD: ∇K = FD(K), ∇²K = FD(∇K) (exact);
//  * PBD → NE as h → 0 at θ = q_n + h q̇_n + h² a (first order in h);
//  * all of the above with armature (UrdfOptions::default_armature > 0).
// Contacts: the feet of detectFeet(), CoulombModel on a flat and on a tilted plane, feet penetrating
// by a few millimetres (so the d^p term and its derivative are active), random feasible weights,
// default PD gains with a random target and feed-forward, and a random external force.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "contact_models/coulomb_model.hpp"
#include "control/stable_pd.hpp"
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

struct Case {
  std::string name;
  std::string path;
  UrdfOptions options;
  bool shared = false;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const test::RobotCase& r : test::derivativeRobots()) {
    if (r.options.base == BaseType::Fixed) continue;  // no feet on the ground to speak of
    out.push_back({r.name, r.path, r.options, r.shared});
  }
  UrdfOptions armature;
  armature.default_armature = 0.02;  // kg m², about the size of the leg links' own inertia
  out.push_back({"quadruped_armature", test::quadrupedUrdf(), armature, false});
  UrdfOptions armature_planar = armature;
  armature_planar.base = BaseType::Planar;
  out.push_back({"quadruped_planar_armature", test::quadrupedUrdf(), armature_planar, false});
  return out;
}

// A robot with its four (or however many) feet on a plane whose normal is tilted by `tilt` about y.
struct Scene {
  Model model;
  CoulombModel contact_model;
  PlaneTerrain terrain;
  System system;
  Vec3 normal;
  double tilt;
  Mat3 chart = Mat3::Identity();

  Scene(const Case& c, double tilt_)
      : model(loadUrdf(c.path, c.options)),
        terrain(Vec3(std::sin(tilt_), 0.0, std::cos(tilt_)), -0.05),
        normal(std::sin(tilt_), 0.0, std::cos(tilt_)),
        tilt(tilt_) {
    system = systemOnFeet(model, contact_model, terrain, massScaledPdGains(model));
  }

  // Signed foot clearance φ(c) − r (negative: penetration depth) of every contact at q.
  Vec clearances(const Vec& q) const {
    Data data(model);
    data.base_chart = chart;
    forwardKinematics(model, data, q);
    Vec out(system.contacts.size());
    for (size_t c = 0; c < system.contacts.size(); ++c) {
      const ContactPoint& cp = system.contacts[c];
      TerrainQuery tq;
      terrain.query(linkPoint(model, data, cp.link, cp.offset), tq, false);
      out[c] = tq.distance - cp.radius;
    }
    return out;
  }

  // A random configuration with the trunk parallel to the plane, small random joint and base angle
  // perturbations, shifted along z so that every foot either penetrates by 1–12 mm or clears the
  // ground by more than 1 mm, and at least two feet penetrate. Sets `chart` (floating base: a random
  // yaw composed with the tilt, so the base angles stay small).
  Vec penetratingState(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int n = model.nq;
    const int iz = model.dofIndex("base_z");
    for (int attempt = 0; attempt < 500; ++attempt) {
      Vec q = Vec::Zero(n);
      for (int j = 0; j < n; ++j)
        if (!model.bodies[j].is_base) q[j] = 0.02 * u(rng);
      if (model.base == BaseType::Floating) {
        chart = rotationAbout(Vec3::UnitY(), tilt) * rotationAbout(Vec3::UnitZ(), M_PI * u(rng));
        for (int j = 3; j < 6; ++j) q[j] = 0.01 * u(rng);
        q[0] = 0.1 * u(rng);
        q[1] = 0.1 * u(rng);
      } else {
        chart.setIdentity();
        q[model.dofIndex("base_pitch")] = tilt + 0.01 * u(rng);
        q[model.dofIndex("base_x")] = 0.1 * u(rng);
      }
      // Base z moves every foot by normal.z() · Δz along the plane's distance: one shift is exact.
      const Vec clear = clearances(q);
      const double target = -0.004 + 0.002 * u(rng);
      q[iz] += (target - clear.mean()) / normal.z();
      const Vec cl = clearances(q);
      int in = 0;
      bool ok = true;
      for (int c = 0; c < cl.size(); ++c) {
        if (cl[c] < -0.012 || (cl[c] > -0.001 && cl[c] < 0.001)) ok = false;
        if (cl[c] < 0) ++in;
      }
      if (ok && in >= std::min<int>(2, cl.size())) return q;
    }
    ADD_FAILURE() << "no penetrating state found";
    return Vec::Zero(n);
  }
};

// Random feasible weights: w ≥ 0, each contact's sum in [0.2, 0.95].
Vec randomWeights(std::mt19937& rng, int C, int K) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Vec w(C * K);
  for (int c = 0; c < C; ++c) {
    for (int i = 0; i < K; ++i) w[c * K + i] = u(rng);
    w.segment(c * K, K) *= (0.2 + 0.75 * u(rng)) / w.segment(c * K, K).sum();
  }
  return w;
}

class StepResidualTest : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    if (GetParam().shared && !std::filesystem::exists(GetParam().path))
      GTEST_SKIP() << "../shared is absent (" << GetParam().path << "): skipping";
  }

  // The random data of one step from the penetrating configuration θ₀.
  struct StepData {
    Vec theta, w, q_n, qd_n, q_prev;
    double h = 0.02, h_prev = 0.03;
    PdTarget target;
  };

  StepData randomStep(Scene& s, std::mt19937& rng) {
    const int n = s.model.nq;
    StepData d;
    d.theta = s.penetratingState(rng);
    d.q_n = d.theta - d.h * test::randomVector(rng, n, 0.3);
    d.qd_n = test::randomVector(rng, n, 0.5);
    d.q_prev = d.q_n - d.h_prev * test::randomVector(rng, n, 0.3);
    d.w = randomWeights(rng, static_cast<int>(s.system.contacts.size()), s.contact_model.vertexCount());
    d.target.position = d.theta + test::randomVector(rng, n, 0.1);
    d.target.velocity = test::randomVector(rng, n, 0.5);
    // Feed-forward on actuated coordinates, and a push on everything.
    s.system.gains.tau_ff = test::randomVector(rng, n, 2.0);
    for (int j = 0; j < n; ++j)
      if (s.model.bodies[j].is_base) s.system.gains.tau_ff[j] = 0.0;
    s.system.external_force = test::randomVector(rng, n, 5.0);
    return d;
  }

  void prepare(Scene& s, StepResidual& r, Form form, const StepData& d) {
    r.prepare(s.system, form, d.h, d.q_n, d.qd_n, d.q_prev, d.h_prev, d.target, s.chart);
  }

  // Every θ-derivative check of one form on one scene.
  void checkForm(Form form, double tilt, unsigned seed) {
    Scene s(GetParam(), tilt);
    ASSERT_FALSE(s.system.contacts.empty());
    if (GetParam().options.default_armature > 0) {
      double total = 0;
      for (const Body& b : s.model.bodies) total += b.armature;
      ASSERT_GT(total, 0.0) << "the armature case must load armature";
    }
    std::mt19937 rng(seed);
    const StepData d = randomStep(s, rng);
    const int n = s.model.nq;
    StepResidual r(s.system), fd(s.system);
    prepare(s, r, form, d);
    prepare(s, fd, form, d);
    const Vec depths = -s.clearances(d.theta);
    const double eps = 1e-6;

    // The contact forces are nonzero and penetration-dependent (d^p term active).
    r.evaluate(s.system, d.theta, d.w, ContactDerivative::Model);
    int active = 0;
    for (size_t c = 0; c < s.system.contacts.size(); ++c) {
      const Vec6 f = r.wrenches[c].V * d.w.segment(c * s.contact_model.vertexCount(), s.contact_model.vertexCount());
      double dV = 0;
      for (const Mat6X& m : r.wrenches[c].dV) dV = std::max(dV, m.cwiseAbs().maxCoeff());
      // Every vertex has the normal component k (d^p + ζ): n·f = k (d^p + ζ) Σ w_c.
      const int K = s.contact_model.vertexCount();
      const double expected_normal = s.contact_model.normalForce(std::max(depths[c], 0.0)) * d.w.segment(c * K, K).sum();
      EXPECT_NEAR(s.normal.dot(f.tail<3>()), expected_normal, 1e-9 * expected_normal) << "contact " << c;
      if (depths[c] > 0) {
        ++active;
        // The penetration term dominates the air force k ζ.
        EXPECT_GT(s.contact_model.normalForce(depths[c]), 5 * s.contact_model.normalForce(0.0));
        EXPECT_GT(dV, 1e3) << "contact " << c << ": dV/dξ should be active at depth " << depths[c];
      }
    }
    ASSERT_GE(active, 1);
    const Vec G0 = r.G;
    const Mat dG_first = r.dG_dtheta;
    const Mat B0 = r.B;
    std::vector<Mat6X> V0(s.system.contacts.size());
    for (size_t c = 0; c < V0.size(); ++c) V0[c] = r.wrenches[c].V;
    r.evaluate(s.system, d.theta, d.w, ContactDerivative::Dropped);
    const Mat dG_zero = r.dG_dtheta;
    EXPECT_EQ((r.G - G0).cwiseAbs().maxCoeff(), 0.0) << "G must not depend on the contact derivative";
    EXPECT_EQ((r.B - B0).cwiseAbs().maxCoeff(), 0.0) << "B must not depend on the contact derivative";
    // Zeroth order by central differences of V: the first-order Jacobian without the model's dV/dξ.
    r.evaluate(s.system, d.theta, d.w, ContactDerivative::FiniteDifference);
    EXPECT_EQ((r.G - G0).cwiseAbs().maxCoeff(), 0.0);
    const double e_finite_difference = relativeError(r.dG_dtheta, dG_first);
    EXPECT_LT(e_finite_difference, 1e-6) << "finite-difference ∂G/∂θ against the exact one";

    // --- value of G: G(θ, w) = G(θ, 0) − B w, and G(θ, 0) independently.
    fd.evaluate(s.system, d.theta, Vec::Zero(d.w.size()), ContactDerivative::Dropped);
    const Vec G_free = fd.G;
    EXPECT_LT(relativeError(G0, G_free - B0 * d.w), 1e-12);
    // B's columns are J_cᵀ V_c.
    for (size_t c = 0; c < V0.size(); ++c) {
      const int K = s.contact_model.vertexCount();
      EXPECT_LT(relativeError(B0.middleCols(c * K, K), r.jacobians[c].transpose() * V0[c]), 1e-12);
    }
    if (form == Form::NewtonEuler) {
      Data data(s.model);
      data.base_chart = s.chart;
      const Vec thd = (d.theta - d.q_n) / d.h;
      const Vec thdd = (thd - d.qd_n) / d.h;
      rnea(s.model, data, d.theta, thd, thdd);
      Vec tau(n);
      pdTorque(s.system.gains, d.target, d.theta, d.q_n, d.h, tau);
      const Vec expected = data.tau - tau - s.system.external_force;
      const double e = relativeError(G_free, expected);
      std::printf("  NE G value vs RNEA − τ − f_ext: %.2e\n", e);
      EXPECT_LT(e, 1e-12);
    } else {
      // E(θ) = I(θ) + U(θ) + P(θ) + Σ_j ½ a_j (θ_j − (1+α) q_n,j + α q_prev,j)²/h² − f_extᵀ θ.
      const double alpha = d.h / d.h_prev;
      Data data(s.model);
      data.base_chart = s.chart;
      BodyTransforms Tn, Tp, C;
      forwardKinematics(s.model, data, d.q_n);
      bodyTransforms(s.model, data, Tn);
      forwardKinematics(s.model, data, d.q_prev);
      bodyTransforms(s.model, data, Tp);
      inertialTargets(Tn, Tp, alpha, C);
      auto energy = [&](const Vec& th) {
        forwardKinematics(s.model, data, th);
        double E = transformEnergy(s.model, data, C, d.h, nullptr, nullptr) + gravityPotential(s.model, data, nullptr, nullptr) +
                   pdPotential(s.system.gains, d.target, th, d.q_n, d.h) - s.system.external_force.dot(th);
        for (int j = 0; j < n; ++j) {
          const double a = s.model.bodies[j].armature;
          const double x = th[j] - (1 + alpha) * d.q_n[j] + alpha * d.q_prev[j];
          E += 0.5 * a * x * x / (d.h * d.h);
        }
        Vec out(1);
        out[0] = E;
        return out;
      };
      const Vec grad = centralDifference(energy, d.theta, 1e-6).transpose();
      const double e = relativeError(G_free, grad);
      std::printf("  PBD G(θ,0) vs FD of the energy: %.2e\n", e);
      EXPECT_LT(e, 1e-6);
    }

    // --- first order: exact θ-Jacobian.
    auto G_of = [&](const Vec& th) {
      fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
      return Vec(fd.G);
    };
    const Mat dG_fd = centralDifference(G_of, d.theta, eps);
    const double e_first = relativeError(dG_first, dG_fd);

    // --- zeroth order: vertices frozen at θ₀.
    auto G_frozen = [&](const Vec& th) {
      fd.evaluate(s.system, th, Vec::Zero(d.w.size()), ContactDerivative::Dropped);
      Vec g = fd.G;
      const int K = s.contact_model.vertexCount();
      for (size_t c = 0; c < V0.size(); ++c) g -= fd.jacobians[c].transpose() * (V0[c] * d.w.segment(c * K, K));
      return g;
    };
    const Mat dG_frozen_fd = centralDifference(G_frozen, d.theta, eps);
    const double e_zero = relativeError(dG_zero, dG_frozen_fd);

    // --- the dropped term alone, on its own scale: first − zeroth = −Σ J_cᵀ (∂V_c/∂θ) w_c
    //     = FD(G) − FD(G with frozen vertices).
    const Mat dropped_fd = dG_fd - dG_frozen_fd;
    const double dropped_scale = dropped_fd.cwiseAbs().maxCoeff();
    const double e_dropped = relativeError(dG_first - dG_zero, dropped_fd);
    EXPECT_GT(dropped_scale, 1e-3 * dG_fd.cwiseAbs().maxCoeff()) << "the contact-model derivative term must matter";

    // --- B = −∂G/∂w, exact in w (G is affine in w).
    auto G_w = [&](const Vec& w) {
      fd.evaluate(s.system, d.theta, w, ContactDerivative::Dropped);
      return Vec(fd.G);
    };
    const double e_B = relativeError(-centralDifference(G_w, d.w, 0.1), B0);

    std::printf("  %s tilt %.2f depths [%s] |dG| %.2e: first %.2e zeroth %.2e dropped(|.|=%.2e) %.2e B %.2e"
                " finite-difference vs exact %.2e\n",
                form == Form::NewtonEuler ? "NE" : "PBD", tilt,
                [&] {
                  static char buf[256];
                  int k = 0;
                  for (int c = 0; c < depths.size(); ++c) k += std::snprintf(buf + k, sizeof buf - k, "%.1fmm ", 1e3 * depths[c]);
                  return buf;
                }(),
                dG_fd.cwiseAbs().maxCoeff(), e_first, e_zero, dropped_scale, e_dropped, e_B, e_finite_difference);
    EXPECT_LT(e_first, 1e-6);
    EXPECT_LT(e_zero, 1e-6);
    EXPECT_LT(e_dropped, 1e-5);
    EXPECT_LT(e_B, 1e-10);

    // --- K and its derivatives.
    r.evaluate(s.system, d.theta, d.w, ContactDerivative::Model);
    const double K0 = r.K;
    const Vec gradK = r.grad_K;
    const Mat hessK = r.hess_K;
    auto K_of = [&](const Vec& th) {
      fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
      Vec out(1);
      out[0] = fd.K;
      return out;
    };
    const Vec gradK_fd = centralDifference(K_of, d.theta, eps).transpose();
    if (form == Form::NewtonEuler) {
      Data data(s.model);
      data.base_chart = s.chart;
      crba(s.model, data, d.theta);
      const Mat H = data.H;
      const Vec thd = (d.theta - d.q_n) / d.h;
      EXPECT_NEAR(K0, 0.5 * thd.dot(H * thd), 1e-12 * std::max(1.0, K0));
      EXPECT_LT(relativeError(hessK, H / (d.h * d.h)), 1e-12);
      // ∇K is exact: H θ̇ / h plus ∂T/∂q = ½ θ̇ᵀ (∂H/∂θ) θ̇, the FD of θ ↦ ½ θ̇₀ᵀ H(θ) θ̇₀ (a check
      // independent of the solver's composite-momentum formula), and so equals FD(K).
      auto dH_term = [&](const Vec& th) {
        crba(s.model, data, th);
        Vec out(1);
        out[0] = 0.5 * thd.dot(data.H * thd);
        return out;
      };
      const Vec dH_fd = centralDifference(dH_term, d.theta, eps).transpose();
      const double e_parts = relativeError(gradK, H * thd / d.h + dH_fd);
      const double e = relativeError(gradK, gradK_fd);
      std::printf("  NE ∇K vs Hθ̇/h + FD(½θ̇ᵀHθ̇): %.2e, vs FD(K): %.2e (|∇K| %.2e, ∂T/∂q %.2e)\n", e_parts, e,
                  gradK.cwiseAbs().maxCoeff(), dH_fd.cwiseAbs().maxCoeff());
      EXPECT_GT(dH_fd.cwiseAbs().maxCoeff(), 1e-6 * gradK.cwiseAbs().maxCoeff());  // the term is there
      EXPECT_LT(e_parts, 1e-6);
      EXPECT_LT(e, 1e-6);
    } else {
      auto gradK_of = [&](const Vec& th) {
        fd.evaluate(s.system, th, d.w, ContactDerivative::Dropped);
        return Vec(fd.grad_K);
      };
      const Mat hessK_fd = centralDifference(gradK_of, d.theta, eps);
      const double eg = relativeError(gradK, gradK_fd), eh = relativeError(hessK, hessK_fd);
      std::printf("  PBD ∇K vs FD %.2e, ∇²K vs FD %.2e (K %.3e)\n", eg, eh, K0);
      EXPECT_LT(eg, 1e-6);
      EXPECT_LT(eh, 1e-6);
      EXPECT_LT(relativeError(hessK, hessK.transpose()), 1e-12);
    }
  }
};

TEST_P(StepResidualTest, NewtonEulerFlat) {
  for (unsigned seed : {1u, 2u}) checkForm(Form::NewtonEuler, 0.0, seed);
}
TEST_P(StepResidualTest, NewtonEulerTilted) { checkForm(Form::NewtonEuler, 0.2, 3u); }
TEST_P(StepResidualTest, PositionBasedFlat) {
  for (unsigned seed : {4u, 5u}) checkForm(Form::PositionBased, 0.0, seed);
}
TEST_P(StepResidualTest, PositionBasedTilted) { checkForm(Form::PositionBased, 0.2, 6u); }

// PBD → NE as h → 0: with q_prev = q_n − h q̇_n, h_prev = h and θ = q_n + h q̇_n + h² a, both residuals
// approximate H a + C + g − τ − Σ Jᵀ f − f_ext, and their difference is O(h).
TEST_P(StepResidualTest, PositionBasedApproachesNewtonEuler) {
  Scene s(GetParam(), 0.1);
  std::mt19937 rng(11);
  const int n = s.model.nq;
  const Vec theta0 = s.penetratingState(rng);
  const Vec qd_n = test::randomVector(rng, n, 0.5);
  const Vec a = test::randomVector(rng, n, 2.0);
  const Vec w = randomWeights(rng, static_cast<int>(s.system.contacts.size()), s.contact_model.vertexCount());
  PdTarget target{theta0 + test::randomVector(rng, n, 0.1), test::randomVector(rng, n, 0.5)};
  s.system.external_force = test::randomVector(rng, n, 5.0);
  StepResidual ne(s.system), pbd(s.system);
  std::vector<double> diffs;
  double scale = 0;
  for (double h : {1e-2, 1e-3, 1e-4}) {
    // θ is the penetrating state; q_n is placed so that θ = q_n + h q̇_n + h² a.
    const Vec q_n = theta0 - h * qd_n - h * h * a;
    const Vec q_prev = q_n - h * qd_n;
    ne.prepare(s.system, Form::NewtonEuler, h, q_n, qd_n, q_prev, h, target, s.chart);
    pbd.prepare(s.system, Form::PositionBased, h, q_n, qd_n, q_prev, h, target, s.chart);
    ne.evaluate(s.system, theta0, w, ContactDerivative::Dropped);
    pbd.evaluate(s.system, theta0, w, ContactDerivative::Dropped);
    scale = ne.G.cwiseAbs().maxCoeff();
    diffs.push_back((ne.G - pbd.G).cwiseAbs().maxCoeff());
    std::printf("  h %.0e: |G_ne| %.3e |G_ne − G_pbd| %.3e\n", h, scale, diffs.back());
  }
  // First order: each tenfold reduction of h reduces the difference about tenfold.
  EXPECT_GT(diffs[0] / diffs[1], 5.0);
  EXPECT_GT(diffs[1] / diffs[2], 5.0);
  EXPECT_LT(diffs[2], 1e-2 * scale);
}

// Contact-point kinetic energy (KineticEnergyMeasure::ContactPoints): K = ½ Σ‖u_c‖² of unit point
// masses at the sphere centres. PBD: u_c = (p_c(θ) − p_c(q_n))/h, so ∇K = Σ J_cᵀu_c/h is exact
// and NE: u_c = J_c(θ) θ̇ (which moves with θ through J_c too): ∇K is exact in both forms (checked
// against FD of K), and ∇²K = Σ J_cᵀJ_c/h² is Gauss–Newton (checked against that sum).
// A penetrating θ, a q_n a centimetre away, a random q̇_n and random feasible weights: the inputs
// of the kinetic-energy tests.
struct EnergyInputs {
  Vec theta, q_n, qd_n, w;
  EnergyInputs(Scene& s, std::mt19937& rng) {
    const int n = s.model.nq;
    theta = s.penetratingState(rng);
    q_n = theta - test::randomVector(rng, n, 0.01);
    qd_n = test::randomVector(rng, n, 0.5);
    w = randomWeights(rng, static_cast<int>(s.system.contacts.size()), s.contact_model.vertexCount());
  }
};

TEST_P(StepResidualTest, ContactPointKineticEnergy) {
  Scene s(GetParam(), 0.1);
  std::mt19937 rng(21);
  const int n = s.model.nq;
  const EnergyInputs in(s, rng);
  const Vec &theta = in.theta, &q_n = in.q_n, &qd_n = in.qd_n, &w = in.w;
  const PdTarget target{theta, Vec::Zero(n)};
  const double h = 0.02, eps = 1e-6;
  for (Form form : {Form::NewtonEuler, Form::PositionBased}) {
    StepResidual r(s.system), fd(s.system);
    r.prepare(s.system, form, h, q_n, qd_n, q_n - h * qd_n, h, target, s.chart, KineticEnergyMeasure::ContactPoints);
    fd.prepare(s.system, form, h, q_n, qd_n, q_n - h * qd_n, h, target, s.chart, KineticEnergyMeasure::ContactPoints);
    r.evaluate(s.system, theta, w, ContactDerivative::Dropped);
    // K from the contact points' own positions and Jacobians.
    double K = 0;
    std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> J0;
    Data data(s.model), data_n(s.model);
    data.base_chart = data_n.base_chart = s.chart;
    forwardKinematics(s.model, data, theta);
    forwardKinematics(s.model, data_n, q_n);
    for (const ContactPoint& cp : s.system.contacts) {
      Eigen::Matrix<double, 3, Eigen::Dynamic> J(3, n);
      const Vec3 p = linkPoint(s.model, data, cp.link, cp.offset);
      pointJacobian(s.model, data, s.model.links[cp.link].body, p, J);
      J0.push_back(J);
      const Vec3 u = form == Form::NewtonEuler ? Vec3(J * ((theta - q_n) / h))
                                               : Vec3((p - linkPoint(s.model, data_n, cp.link, cp.offset)) / h);
      K += 0.5 * u.squaredNorm();
    }
    EXPECT_NEAR(r.K, K, 1e-12 * std::max(1.0, K));
    const Vec gradK_fd = centralDifference([&](const Vec& th) {
      fd.evaluate(s.system, th, w, ContactDerivative::Dropped);
      return Vec::Constant(1, fd.K);
    }, theta, eps).transpose();
    const double e_grad = relativeError(r.grad_K, gradK_fd);
    Mat gn = Mat::Zero(n, n);
    for (const auto& J : J0) gn += J.transpose() * J / (h * h);
    const double e_hess = relativeError(r.hess_K, gn);
    std::printf("  %s contact-point K %.4e: ∇K vs FD %.2e, ∇²K vs Σ JᵀJ/h² %.2e\n",
                form == Form::NewtonEuler ? "NE " : "PBD", r.K, e_grad, e_hess);
    EXPECT_GT(r.K, 0.0);
    EXPECT_LT(e_grad, 1e-6);
    EXPECT_LT(e_hess, 1e-12);
  }
}

// Full-body-pd kinetic energy (KineticEnergyMeasure::FullBodyPd): the full-body K plus
// ½ Σ_j (k_p,j + k_d,j/h)(θ_j − q_n,j)², so that its Hessian is the part of ∂G/∂θ the implicit PD
// adds. Checked in both forms: the added value, gradient and Hessian against the full-body K's, and
// ∇K against FD of K (exact in PBD, and in NE with its ∂T/∂q term).
TEST_P(StepResidualTest, FullBodyPdKineticEnergy) {
  Scene s(GetParam(), 0.1);
  std::mt19937 rng(22);
  const int n = s.model.nq;
  const EnergyInputs in(s, rng);
  const Vec &theta = in.theta, &q_n = in.q_n, &qd_n = in.qd_n, &w = in.w;
  const PdTarget target{theta + test::randomVector(rng, n, 0.1), test::randomVector(rng, n, 0.5)};
  const double h = 0.02, eps = 1e-6;
  Vec stiffness(n);
  for (int j = 0; j < n; ++j) stiffness[j] = s.system.gains.kp[j] + s.system.gains.kd[j] / h;
  ASSERT_GT(stiffness.maxCoeff(), 0.0) << "the robot needs PD gains for this test to mean anything";
  for (Form form : {Form::NewtonEuler, Form::PositionBased}) {
    StepResidual pd(s.system), full(s.system), fd(s.system);
    pd.prepare(s.system, form, h, q_n, qd_n, q_n - h * qd_n, h, target, s.chart, KineticEnergyMeasure::FullBodyPd);
    full.prepare(s.system, form, h, q_n, qd_n, q_n - h * qd_n, h, target, s.chart, KineticEnergyMeasure::FullBody);
    fd.prepare(s.system, form, h, q_n, qd_n, q_n - h * qd_n, h, target, s.chart, KineticEnergyMeasure::FullBodyPd);
    pd.evaluate(s.system, theta, w, ContactDerivative::Model);
    full.evaluate(s.system, theta, w, ContactDerivative::Model);
    const Vec d = theta - q_n;
    const double added = 0.5 * d.dot(stiffness.cwiseProduct(d));
    EXPECT_GT(added, 1e-3 * full.K);
    EXPECT_NEAR(pd.K, full.K + added, 1e-12 * pd.K);
    EXPECT_LT(relativeError(pd.grad_K, Vec(full.grad_K + stiffness.cwiseProduct(d))), 1e-12);
    EXPECT_LT(relativeError(pd.hess_K, Mat(full.hess_K + Mat(stiffness.asDiagonal()))), 1e-12);
    EXPECT_EQ(pd.G, full.G);  // the measure changes K only
    const Vec gradK_fd = centralDifference([&](const Vec& th) {
      fd.evaluate(s.system, th, w, ContactDerivative::Dropped);
      return Vec::Constant(1, fd.K);
    }, theta, eps).transpose();
    const double e_grad = relativeError(pd.grad_K, gradK_fd);
    std::printf("  %s full-body-pd K %.4e (PD share %.2e): ∇K vs FD %.2e\n", form == Form::NewtonEuler ? "NE " : "PBD",
                pd.K, added, e_grad);
    EXPECT_LT(e_grad, 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, StepResidualTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace nmdp
