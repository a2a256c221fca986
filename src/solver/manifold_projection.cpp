#include "solver/manifold_projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nmdp {

void ManifoldProjection::resize(int n, double weight_scale, double mass_scale) {
  lu_.resize(n);
  anderson_.resize(n, kAndersonMemory);
  step_.setZero(n);
  theta_trial_.setZero(n);
  weight_scale_ = weight_scale;
  mass_scale_ = mass_scale;
}

bool ManifoldProjection::factor(const Eigen::MatrixXd& dG_dtheta) {
  factorization_valid_ = lu_.compute(dG_dtheta) == dG_dtheta.cols();
  return factorization_valid_;
}

bool ManifoldProjection::project(StepResidual& residual, const System& system, const IntegratorOptions& options,
                                 Eigen::VectorXd& theta, const Eigen::VectorXd& w, ContactDerivative derivative,
                                 StepStats& counts, double loose) {
  ++counts.projections;
  const int n = static_cast<int>(theta.size());
  // Round-off in G: the inertial term divides θ's round-off by h².
  const double h = residual.h();
  const double lever = 1.0 + theta.lpNorm<Eigen::Infinity>();
  const double tolerance = options.projection_tolerance * weight_scale_ +
                           1e3 * std::numeric_limits<double>::epsilon() * mass_scale_ * lever * lever / (h * h);
  tolerance_ = tolerance;
  const double stop = std::max(tolerance, loose);
  bool fresh = false, refresh = !factorization_valid_;
  if (refresh)
    residual.evaluate(system, theta, w, derivative);
  else
    residual.evaluateValue(system, theta, w);
  ++counts.g_evaluations;
  if (!residual.G.allFinite()) return false;
  // Converged on ‖G‖∞; a step must decrease ‖G‖₂, the merit function Newton's direction descends.
  double norm = residual.G.lpNorm<Eigen::Infinity>(), merit = residual.G.norm();
  // The factorization of ∂G/∂θ at a nearby iterate (at first the current PGM iterate's, which D
  // used) is kept while its steps contract ‖G‖₂ by kRefreshContraction (chord steps: values of G
  // only, a fifth of the cost); it is refreshed at the current θ when they do not or fail, and only
  // a fresh factorization whose step fails is divergence. Anderson acceleration combines the steps
  // taken with one factorization, which undoes most of its staleness.
  bool evaluated_with_derivatives = refresh;
  bool values_at_theta = true;  // the residual's last evaluation is at θ (to be completed, not redone)
  anderson_.reset();
  for (int it = 0;; ++it) {
    if (norm <= stop) return true;
    if (it == options.projection_max_iterations) return false;
    if (refresh) {
      if (!evaluated_with_derivatives) {
        if (values_at_theta)
          residual.addDerivatives(system, theta, w, derivative);
        else
          residual.evaluate(system, theta, w, derivative);
        ++counts.g_evaluations;
      }
      factorization_valid_ = lu_.compute(residual.dG_dtheta) == n;
      if (!factorization_valid_) return false;
      fresh = true;
      refresh = evaluated_with_derivatives = false;
      anderson_.reset();
    }
    step_ = -residual.G;
    lu_.solveInPlace(step_);
    anderson_.accelerate(theta, step_);
    ++counts.newton_iterations;
    double trial_merit = 0.0;
    bool decreased = false;
    for (int k = 0;; ++k) {
      theta_trial_ = theta + step_;
      residual.evaluateValue(system, theta_trial_, w);
      ++counts.g_evaluations;
      trial_merit = residual.G.norm();
      if (trial_merit < merit) {  // false for NaN
        decreased = true;
        break;
      }
      // An old factorization is refreshed rather than its step shortened.
      if (!fresh || k == options.projection_backtracking) break;
      step_ *= 0.5;
    }
    if (!decreased) {
      if (fresh) return false;  // divergence (also catches NaN)
      refresh = true;  // at θ (the residual holds the trial's values until then)
      values_at_theta = false;
      continue;
    }
    theta.swap(theta_trial_);
    values_at_theta = true;
    refresh = trial_merit > kRefreshContraction * merit;
    fresh = false;
    merit = trial_merit;
    norm = residual.G.lpNorm<Eigen::Infinity>();
  }
}

}  // namespace nmdp
