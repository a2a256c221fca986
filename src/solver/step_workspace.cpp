#include "solver/step_workspace.hpp"

#include <limits>

namespace nmdp {

StepWorkspace::StepWorkspace(const System& system, const IntegratorOptions& options)
    : solver((validateSystem(system, options), system)), energy_data(*system.model), local_error(*system.model) {
  const int n = system.model->nq;
  contact_wrench.assign(system.contacts.size(), Vec6::Zero());
  impulse.assign(system.contacts.size(), Vec6::Zero());
  // Enough for any split down to 2⁻¹⁰ of a step; deeper splits grow the buffers once.
  substep_sizes.reserve(1024);
  substep_in_contact.reserve(1024);
  target.position.setZero(n);
  target.velocity.setZero(n);
  zero_weights.setZero(solver.residual().weightCount());
  state_energy_q.setConstant(n, std::numeric_limits<double>::quiet_NaN());  // matches no state
  state_energy_qd.setZero(n);
}

}  // namespace nmdp
