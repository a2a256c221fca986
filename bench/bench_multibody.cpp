// Cost of the multibody kernels the step solvers call every Newton iteration (DESIGN.md 2, 12),
// at one fixed random state per robot, single-threaded:
//   ForwardKinematics, Rnea, Crba, RneaDerivatives (∂τ/∂q, ∂τ/∂q̇, H);
//   NeResidual (G only), NeResidualWithJacobian (G and ∂G/∂θ, inertial part);
//   NeResidualWithContactsAndJacobian: the whole NE residual of DESIGN 2.1 with its θ-Jacobian for
//     four foot contacts at a fixed wrench, G −= J_cᵀ f_c and ∂G/∂θ −= (∂J_cᵀ/∂θ) f_c
//     (the 20 µs one-core target of docs/BENCHMARKS.md refers to this one on the quadruped);
//   ContactJacobianTerms: the contact part of the previous one alone;
//   TransformEnergyGradHess, GravityPotentialGradHess, PbdEnergyGradHess (forward kinematics plus
//     the full PBD ∇E and exact ∇²E: inertial transform energy + gravity potential);
//   the measured comparison for the derivatives: RneaDerivativesFiniteDifference (∂τ/∂q and ∂τ/∂q̇
//     by central differences, 4n RNEA calls) and NeResidualJacobianFiniteDifference (∂G/∂θ by
//     central differences, 2n RNEA calls).
// Robots: the project's 18-DOF quadruped (floating base), and, when ../shared is present, Unitree
// A1, RoboSimian (all 32 joints active, floating base) and RoboSimian in the paper's planar
// configuration (15 DOF).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "multibody/crba.hpp"
#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/pbd_terms.hpp"
#include "multibody/rnea.hpp"
#include "multibody/rnea_derivatives.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/ne_residual.hpp"

namespace {

using namespace nmdp;

Eigen::VectorXd randomVector(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

// The foot links of a robot: FL/FR/RL/RR_foot when all four exist, otherwise every leaf link that
// moves with a body (RoboSimian: limb{1..4}_link7).
std::vector<int> footLinks(const Model& model) {
  std::vector<int> feet;
  for (const char* name : {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}) {
    const int l = model.linkIndex(name);
    if (l >= 0) feet.push_back(l);
  }
  if (feet.size() == 4) return feet;
  feet.clear();
  for (int l = 0; l < static_cast<int>(model.links.size()); ++l)
    if (model.links[l].child_links.empty() && model.links[l].body >= 0) feet.push_back(l);
  return feet;
}

// One robot at one fixed random state, with every output preallocated.
struct Scene {
  Scene(const std::string& path, const UrdfOptions& options) : model(loadUrdf(path, options)), data(model), fd(model) {
    const int n = model.nq;
    std::mt19937 rng(20240611);
    q = randomVector(rng, n, 1.0);
    qd = randomVector(rng, n, 2.0);
    qdd = randomVector(rng, n, 5.0);
    h = 0.01;
    q_n = randomVector(rng, n, 1.0);
    qd_n = randomVector(rng, n, 1.0);
    theta = q_n + h * qd_n + randomVector(rng, n, 0.01);
    const Eigen::VectorXd q_prev = q_n - h * qd_n;

    for (Eigen::VectorXd* x : {&G, &grad, &grad_g, &x_work, &tau_plus}) x->setZero(n);
    for (Eigen::MatrixXd* x : {&dG, &hess, &hess_g, &fd_dq, &fd_dv}) x->setZero(n, n);
    J.setZero(6, n);

    // PBD inertial targets C_k = (1+α) T_k(q_n) − α T_k(q_{n−1}), α = 1.
    BodyTransforms current, previous;
    forwardKinematics(model, data, q_prev);
    bodyTransforms(model, data, previous);
    forwardKinematics(model, data, q_n);
    bodyTransforms(model, data, current);
    inertialTargets(current, previous, 1.0, targets);

    // Four foot contacts with a fixed wrench each: a pushing normal force plus some friction and a
    // small torque, so that every term of (∂J_cᵀ/∂θ) f_c is exercised.
    feet = footLinks(model);
    for (size_t c = 0; c < feet.size(); ++c) {
      Vec6 f;
      f << 0.1 * randomVector(rng, 3, 1.0), randomVector(rng, 3, 20.0);
      f[5] = 0.25 * model.total_mass * 9.81;
      neg_wrenches.push_back(-f);  // G = RNEA − Σ J_cᵀ f_c
    }
  }

  Model model;
  Data data, fd;  // fd: workspace of the finite-difference comparison
  Eigen::VectorXd q, qd, qdd, theta, q_n, qd_n, G, grad, grad_g, x_work, tau_plus;
  Eigen::MatrixXd dG, hess, hess_g, fd_dq, fd_dv;
  Mat6X J;
  double h = 0.01;
  BodyTransforms targets;
  std::vector<int> feet;
  std::vector<Vec6> neg_wrenches;
};

// --- the kernels -------------------------------------------------------------------------------

void ForwardKinematics(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    forwardKinematics(s->model, s->data, s->q);
    benchmark::DoNotOptimize(s->data.p.back().data());
    benchmark::ClobberMemory();
  }
}

void Rnea(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    rnea(s->model, s->data, s->q, s->qd, s->qdd);
    benchmark::DoNotOptimize(s->data.tau.data());
    benchmark::ClobberMemory();
  }
}

void Crba(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    crba(s->model, s->data, s->q);
    benchmark::DoNotOptimize(s->data.H.data());
    benchmark::ClobberMemory();
  }
}

void RneaDerivatives(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    rneaDerivatives(s->model, s->data, s->q, s->qd, s->qdd);
    benchmark::DoNotOptimize(s->data.dtau_dq.data());
    benchmark::DoNotOptimize(s->data.dtau_dv.data());
    benchmark::DoNotOptimize(s->data.H.data());
    benchmark::ClobberMemory();
  }
}

void NeResidual(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    neInertialResidual(s->model, s->data, s->theta, s->q_n, s->qd_n, s->h, s->G, nullptr);
    benchmark::DoNotOptimize(s->G.data());
    benchmark::ClobberMemory();
  }
}

void NeResidualWithJacobian(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    neInertialResidual(s->model, s->data, s->theta, s->q_n, s->qd_n, s->h, s->G, &s->dG);
    benchmark::DoNotOptimize(s->G.data());
    benchmark::DoNotOptimize(s->dG.data());
    benchmark::ClobberMemory();
  }
}

// G −= J_cᵀ f_c and ∂G/∂θ −= (∂J_cᵀ/∂θ) f_c of every foot at the kinematics in s->data.
void addContactTerms(Scene* s) {
  const Model& m = s->model;
  for (size_t c = 0; c < s->feet.size(); ++c) {
    const int link = s->feet[c];
    const int body = m.links[link].body;
    const Vec3 point = linkPoint(m, s->data, link, Vec3::Zero());
    spatialJacobian(m, s->data, body, point, s->J);
    s->G.noalias() += s->J.transpose() * s->neg_wrenches[c];
    addJacobianTransposeWrenchDerivative(m, s->data, body, point, s->neg_wrenches[c], s->dG);
  }
  benchmark::DoNotOptimize(s->G.data());
  benchmark::DoNotOptimize(s->dG.data());
  benchmark::ClobberMemory();
}

// G(θ) = RNEA(θ, θ̇, θ̈) − Σ_c J_cᵀ f_c and ∂G/∂θ = ∂RNEA/∂q + ∂RNEA/∂q̇ / h + H / h² − Σ_c (∂J_cᵀ/∂θ) f_c.
void NeResidualWithContactsAndJacobian(benchmark::State& state, Scene* s) {
  const Model& m = s->model;
  for (auto _ : state) {
    neInertialResidual(m, s->data, s->theta, s->q_n, s->qd_n, s->h, s->G, &s->dG);
    addContactTerms(s);
  }
}

// The contact part of the above alone (kinematics at θ already computed): 4 × (foot point,
// spatialJacobian, G −= J_cᵀ f_c, addJacobianTransposeWrenchDerivative).
void ContactJacobianTerms(benchmark::State& state, Scene* s) {
  const Model& m = s->model;
  forwardKinematics(m, s->data, s->theta);
  for (auto _ : state) {
    addContactTerms(s);
  }
}

void TransformEnergyGradHess(benchmark::State& state, Scene* s) {
  forwardKinematics(s->model, s->data, s->theta);
  for (auto _ : state) {
    double E = transformEnergy(s->model, s->data, s->targets, s->h, &s->grad, &s->hess);
    benchmark::DoNotOptimize(E);
    benchmark::DoNotOptimize(s->grad.data());
    benchmark::DoNotOptimize(s->hess.data());
    benchmark::ClobberMemory();
  }
}

void GravityPotentialGradHess(benchmark::State& state, Scene* s) {
  forwardKinematics(s->model, s->data, s->theta);
  for (auto _ : state) {
    double U = gravityPotential(s->model, s->data, &s->grad_g, &s->hess_g);
    benchmark::DoNotOptimize(U);
    benchmark::DoNotOptimize(s->grad_g.data());
    benchmark::DoNotOptimize(s->hess_g.data());
    benchmark::ClobberMemory();
  }
}

// The full PBD ∇E, ∇²E at θ (inertial + gravity; the PD potential is the controller's business):
// forward kinematics, both terms, and their sum.
void PbdEnergyGradHess(benchmark::State& state, Scene* s) {
  for (auto _ : state) {
    forwardKinematics(s->model, s->data, s->theta);
    double E = transformEnergy(s->model, s->data, s->targets, s->h, &s->grad, &s->hess);
    E += gravityPotential(s->model, s->data, &s->grad_g, &s->hess_g);
    s->grad += s->grad_g;
    s->hess += s->hess_g;
    benchmark::DoNotOptimize(E);
    benchmark::DoNotOptimize(s->grad.data());
    benchmark::DoNotOptimize(s->hess.data());
    benchmark::ClobberMemory();
  }
}

// Column j of `out` = (f(x0 + eps e_j) − f(x0 − eps e_j)) / 2 eps, where `evaluate(x)` leaves f(x)
// in `value`; `x` and `plus` are work vectors.
template <class Evaluate>
void centralColumns(Eigen::VectorXd& x, const Eigen::VectorXd& x0, double eps, Eigen::VectorXd& plus,
                    const Eigen::VectorXd& value, Eigen::MatrixXd& out, Evaluate evaluate) {
  const double inv = 1.0 / (2 * eps);
  x = x0;
  for (Eigen::Index j = 0; j < x0.size(); ++j) {
    x[j] = x0[j] + eps;
    evaluate(x);
    plus = value;
    x[j] = x0[j] - eps;
    evaluate(x);
    out.col(j) = (plus - value) * inv;
    x[j] = x0[j];
  }
}

// ∂τ/∂q and ∂τ/∂q̇ by central differences: 4n RNEA calls (H would cost n more; not counted).
void RneaDerivativesFiniteDifference(benchmark::State& state, Scene* s) {
  const Model& m = s->model;
  const double eps = 1e-6;
  for (auto _ : state) {
    centralColumns(s->x_work, s->q, eps, s->tau_plus, s->fd.tau, s->fd_dq, [&](const Eigen::VectorXd& x) {
      rnea(m, s->fd, x, s->qd, s->qdd);
    });
    centralColumns(s->x_work, s->qd, eps, s->tau_plus, s->fd.tau, s->fd_dv, [&](const Eigen::VectorXd& x) {
      rnea(m, s->fd, s->q, x, s->qdd);
    });
    benchmark::DoNotOptimize(s->fd_dq.data());
    benchmark::DoNotOptimize(s->fd_dv.data());
    benchmark::ClobberMemory();
  }
}

// ∂G/∂θ of the inertial NE residual by central differences: 2n RNEA calls (what the analytic
// NeResidualWithJacobian replaces inside the Newton loop).
void NeResidualJacobianFiniteDifference(benchmark::State& state, Scene* s) {
  const Model& m = s->model;
  const double eps = 1e-6;
  for (auto _ : state) {
    centralColumns(s->x_work, s->theta, eps, s->tau_plus, s->G, s->dG, [&](const Eigen::VectorXd& x) {
      neInertialResidual(m, s->fd, x, s->q_n, s->qd_n, s->h, s->G, nullptr);
    });
    benchmark::DoNotOptimize(s->dG.data());
    benchmark::ClobberMemory();
  }
}

// --- registration ------------------------------------------------------------------------------

struct RobotEntry {
  std::string name;
  std::string path;
  UrdfOptions options;
};

std::vector<RobotEntry> robots() {
  const std::string shared = NMDP_SHARED_DIR;
  std::vector<RobotEntry> out;
  out.push_back({"quadruped", std::string(NMDP_SOURCE_DIR) + "/models/quadruped/quadruped.urdf", {}});
  out.push_back({"a1", shared + "/robots/a1/urdf/a1.urdf", {}});
  out.push_back({"robosimian", shared + "/robots/robosimian/robosimian_caesar_new_all_active.urdf", {}});
  UrdfOptions paper;  // the paper's configuration: planar base, joints 2, 4, 6 of each limb active
  paper.base = BaseType::Planar;
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {0, 1, 3, 5, 7}) paper.locked_joints["limb" + std::to_string(limb) + "_joint" + std::to_string(j)] = 0.0;
  out.push_back({"robosimian_paper_planar", shared + "/robots/robosimian/robosimian_caesar_new_all_active.urdf", paper});
  return out;
}

std::vector<std::unique_ptr<Scene>>& scenes() {
  static std::vector<std::unique_ptr<Scene>> all;
  return all;
}

double minimum(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

void registerAll() {
  using Fn = void (*)(benchmark::State&, Scene*);
  const std::vector<std::pair<const char*, Fn>> kernels = {
      {"ForwardKinematics", ForwardKinematics},
      {"Rnea", Rnea},
      {"Crba", Crba},
      {"RneaDerivatives", RneaDerivatives},
      {"RneaDerivativesFiniteDifference", RneaDerivativesFiniteDifference},
      {"NeResidual", NeResidual},
      {"NeResidualWithJacobian", NeResidualWithJacobian},
      {"NeResidualJacobianFiniteDifference", NeResidualJacobianFiniteDifference},
      {"NeResidualWithContactsAndJacobian", NeResidualWithContactsAndJacobian},
      {"ContactJacobianTerms", ContactJacobianTerms},
      {"TransformEnergyGradHess", TransformEnergyGradHess},
      {"GravityPotentialGradHess", GravityPotentialGradHess},
      {"PbdEnergyGradHess", PbdEnergyGradHess},
  };
  for (const RobotEntry& robot : robots()) {
    if (!std::filesystem::exists(robot.path)) {
      std::cerr << "bench_multibody: " << robot.path << " is absent; not registering the " << robot.name
                << " benchmarks\n";
      continue;
    }
    scenes().push_back(std::make_unique<Scene>(robot.path, robot.options));
    Scene* s = scenes().back().get();
    const std::string suffix = "/" + robot.name + "/nq:" + std::to_string(s->model.nq);
    for (const auto& [name, fn] : kernels) {
      if (fn == NeResidualWithContactsAndJacobian && s->feet.size() != 4)
        std::cerr << "bench_multibody: " << robot.name << " has " << s->feet.size() << " feet, not 4\n";
      benchmark::RegisterBenchmark((name + suffix).c_str(), fn, s)
          ->Unit(benchmark::kNanosecond)
          ->ComputeStatistics("min", minimum);  // the least disturbed repetition on a shared machine
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
