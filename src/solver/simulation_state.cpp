#include "solver/simulation_state.hpp"

namespace nmdp {

SimulationState initialState(const System& system, const IntegratorOptions& options, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& qd, double h) {
  SimulationState s;
  s.q = q;
  s.qd = qd;
  s.q_prev = q - h * qd;
  s.qd_prev = qd;
  s.h_prev = h;
  s.contact_active.assign(system.contacts.size(), 0);
  s.substeps_since_touchdown = kTouchdownRestartSubsteps;
  s.beta = s.beta_start = options.beta_initial;
  const int K = (system.contacts.empty() || !system.contact_model) ? 0 : system.contact_model->vertexCount();
  s.w.setZero(static_cast<Eigen::Index>(system.contacts.size()) * K);
  s.qp_warm.at_bound.assign(system.contacts.size() * static_cast<size_t>(K), 0);
  s.qp_warm.cap.assign(system.contacts.size(), 0);
  s.qp_warm_valid = false;
  return s;
}

}  // namespace nmdp
