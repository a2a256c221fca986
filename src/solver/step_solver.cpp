#include "solver/step_solver.hpp"

#include <cmath>
#include <limits>

namespace nmdp {

bool StepSolver::stepIsWorthTaking(const IntegratorOptions& options, double K, double least_decrease) {
  if (dw_.size() == 0) return false;
  // Δw has no scale of its own (a deep foot's vertices carry 1e9 N, and a weight of 1e-8 on them
  // matters), so tol_w bounds the change of the generalized contact force relative to the weight.
  generalized_force_change_.noalias() = B_theta_ * dw_;
  if (generalized_force_change_.lpNorm<Eigen::Infinity>() < options.tol_w * weight_scale_) return false;
  Qdw_.noalias() = Q_ * dw_;
  const double predicted = -(g_.dot(dw_) + 0.5 * dw_.dot(Qdw_));
  predicted_decrease_ = predicted;
  const double theta_accuracy = projection_.tolerance() * residual_.h() * residual_.h() / mass_scale_;
  const double resolvable =
      64 * std::numeric_limits<double>::epsilon() * std::abs(K) + residual_.grad_K.lpNorm<1>() * theta_accuracy;
  return predicted > std::max(resolvable, least_decrease);
}

void StepSolver::scaleFromQ() {
  // β is relative to each weight's own curvature Q_ii (Marquardt's scaling): a foot in the air has
  // vertices of 0.1 N and a loaded foot of hundreds of N, so their Q_ii differ by 1e6, and one
  // scalar penalty either freezes the light ones or does not restrain the heavy ones.
  const double largest = Q_.size() ? Q_.diagonal().maxCoeff() : 0.0;
  const double floor = largest > 0 ? 1e-12 * largest : 1.0;
  penalty_scale_ = Q_.diagonal().cwiseMax(floor);
}

bool StepSolver::solveQp(double beta) {
  Q_penalized_ = Q_;
  Q_penalized_.diagonal() += beta * penalty_scale_;
  const QpResult qp = qp_.solve(Q_penalized_, 0.0, g_, w_, dw_, warm_valid_ ? &warm_ : nullptr);
  if (qp.status != QpStatus::Converged) return false;
  warm_ = qp_.activeSet();
  warm_valid_ = true;
  return true;
}

void StepSolver::takeWarmStart(const QpActiveSet& set, bool valid) {
  warm_valid_ = valid && set.at_bound.size() == warm_.at_bound.size() && set.cap.size() == warm_.cap.size();
  if (!warm_valid_) return;
  warm_.at_bound = set.at_bound;
  warm_.cap = set.cap;
}

void StepSolver::returnWarmStart(QpActiveSet& set, bool& valid) const {
  set.at_bound = warm_.at_bound;
  set.cap = warm_.cap;
  valid = warm_valid_;
}

StepSolver::StepSolver(const System& system)
    : residual_(system), llt_(system.model->nq) {
  const Model& model = *system.model;
  const int n = model.nq;
  const int C = static_cast<int>(system.contacts.size());
  const int m = residual_.weightCount();
  K_vertices_ = C > 0 ? m / C : 0;
  qp_.resize(std::vector<int>(C, K_vertices_));
  warm_.at_bound.assign(m, 0);
  warm_.cap.assign(C, 0);
  theta_.setZero(n);
  theta_candidate_.setZero(n);
  adjoint_.setZero(n);
  velocity_.setZero(n);
  zero_acceleration_.setZero(n);
  tau_.setZero(n);
  w_.setZero(m);
  w_trial_.setZero(m);
  dw_.setZero(m);
  g_.setZero(m);
  D_.setZero(n, m);
  Qdw_.setZero(m);
  penalty_scale_.setZero(m);
  Q_penalized_.setZero(m, m);
  B_theta_.setZero(n, m);
  generalized_force_change_.setZero(n);
  Q_.setZero(m, m);
  HD_.setZero(n, m);
  mass_scale_ = model.total_mass > 0 ? model.total_mass : 1.0;
  weight_scale_ = mass_scale_ * std::max(model.gravity.norm(), 1.0);
  projection_.resize(n, weight_scale_, mass_scale_);
}

Vec6 StepSolver::contactWrench(int c) const {
  const ContactWrenches& cw = residual_.wrenches[c];
  return cw.V * w_.segment(c * K_vertices_, K_vertices_);
}

StepAttempt StepSolver::attempt(const System& system, const IntegratorOptions& options, const SimulationState& state,
                                double h, const PdTarget& target, const Eigen::VectorXd& w_start, double& beta,
                                CancelFlag cancel) {
  if (options.method == Method::NeMdp) return neMdp(system, state, h, target, w_start);
  return pgm(system, options, state, h, target, w_start, beta, cancel);
}

}  // namespace nmdp
