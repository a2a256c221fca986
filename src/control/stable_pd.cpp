#include "control/stable_pd.hpp"

#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace nmdp {

namespace {

// A coordinate with no gain and no feed-forward is unactuated (base, passive): skip it entirely.
inline bool inactive(const PdGains& g, Eigen::Index i) { return g.kp[i] == 0.0 && g.kd[i] == 0.0 && g.tau_ff[i] == 0.0; }

inline void checkSizes(const PdGains& g, const PdTarget& t, const Eigen::VectorXd& theta, const Eigen::VectorXd& q_n,
                       double h) {
  (void)g, (void)t, (void)theta, (void)q_n, (void)h;
  assert(h > 0.0);
  assert(g.kd.size() == g.kp.size() && g.tau_ff.size() == g.kp.size());
  assert(t.position.size() == g.kp.size() && t.velocity.size() == g.kp.size());
  assert(theta.size() == g.kp.size() && q_n.size() == g.kp.size());
}

}  // namespace

PdGains massScaledPdGains(const Model& model) {
  if (!(model.total_mass > 0.0) || !std::isfinite(model.total_mass))
    throw std::invalid_argument("massScaledPdGains: robot total mass must be positive and finite (got " +
                                std::to_string(model.total_mass) + " kg)");
  const double scale = model.total_mass / kReferencePdMass;  // linear in mass
  return actuatedPdGains(model, [&](int) { return std::pair(kReferenceKp * scale, kReferenceKd * scale); });
}

void validatePdGains(const Model& model, const PdGains& gains) {
  const auto checkVector = [&](const Eigen::VectorXd& v, const char* name, bool nonnegative) {
    if (v.size() != model.nq)
      throw std::invalid_argument(std::string("PD gains: ") + name + " has " + std::to_string(v.size()) +
                                  " entries, the robot has " + std::to_string(model.nq) + " coordinates");
    for (int i = 0; i < model.nq; ++i) {
      const std::string where = std::string("PD gains: ") + name + "[" + std::to_string(i) + "] (" +
                                model.bodies[i].joint_name + ")";
      if (!std::isfinite(v[i])) throw std::invalid_argument(where + " is not finite");
      if (nonnegative && v[i] < 0.0) throw std::invalid_argument(where + " is negative");
      if (model.bodies[i].is_base && v[i] != 0.0)
        throw std::invalid_argument(where + " is nonzero on an unactuated base coordinate");
    }
  };
  checkVector(gains.kp, "kp", true);
  checkVector(gains.kd, "kd", true);
  checkVector(gains.tau_ff, "tau_ff", false);
}

void pdPotentialGradient(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta,
                         const Eigen::VectorXd& q_n, double h, Eigen::VectorXd& grad_out) {
  checkSizes(gains, target, theta, q_n, h);
  const Eigen::Index n = gains.kp.size();
  if (grad_out.size() != n) grad_out.resize(n);
  const double inv_h = 1.0 / h;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (inactive(gains, i)) {
      grad_out[i] = 0.0;
      continue;
    }
    const double e = theta[i] - target.position[i];
    const double ed = (theta[i] - q_n[i]) * inv_h - target.velocity[i];
    grad_out[i] = gains.kp[i] * e + gains.kd[i] * ed - gains.tau_ff[i];
  }
}

void pdTorque(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta, const Eigen::VectorXd& q_n,
              double h, Eigen::VectorXd& tau_out) {
  // τ = −∇P, computed as the exact negation of the gradient (see the header).
  pdPotentialGradient(gains, target, theta, q_n, h, tau_out);
  for (Eigen::Index i = 0; i < tau_out.size(); ++i) tau_out[i] = -tau_out[i];
}

void pdPotentialHessianDiagonal(const PdGains& gains, double h, Eigen::VectorXd& out) {
  assert(h > 0.0);
  const Eigen::Index n = gains.kp.size();
  if (out.size() != n) out.resize(n);
  const double inv_h = 1.0 / h;
  for (Eigen::Index i = 0; i < n; ++i) out[i] = gains.kp[i] + gains.kd[i] * inv_h;
}

void pdTorqueJacobianDiagonal(const PdGains& gains, double h, Eigen::VectorXd& out) {
  pdPotentialHessianDiagonal(gains, h, out);
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] = -out[i];
}

double pdPotential(const PdGains& gains, const PdTarget& target, const Eigen::VectorXd& theta,
                   const Eigen::VectorXd& q_n, double h) {
  checkSizes(gains, target, theta, q_n, h);
  const double inv_h = 1.0 / h;
  double p = 0.0;
  for (Eigen::Index i = 0; i < gains.kp.size(); ++i) {
    if (inactive(gains, i)) continue;
    const double e = theta[i] - target.position[i];
    const double ed = (theta[i] - q_n[i]) * inv_h - target.velocity[i];
    p += 0.5 * gains.kp[i] * e * e + 0.5 * h * gains.kd[i] * ed * ed - gains.tau_ff[i] * theta[i];
  }
  return p;
}

}  // namespace nmdp
