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
  s.substeps_since_touchdown = 2;
  s.beta = s.beta_start = options.beta_initial;
  const int K = (system.contacts.empty() || !system.contact_model) ? 0 : system.contact_model->vertexCount();
  s.w.setZero(static_cast<Eigen::Index>(system.contacts.size()) * K);
  return s;
}

}  // namespace nmdp
