#include "solver/system.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace nmdp {

void validateSystem(const System& system, const IntegratorOptions& options) {
  if (!system.model) throw std::invalid_argument("integrator: no robot model");
  const Model& model = *system.model;
  validatePdGains(model, system.gains);
  if (system.external_force.size() != 0 && system.external_force.size() != model.nq)
    throw std::invalid_argument("integrator: external_force has " + std::to_string(system.external_force.size()) +
                                " entries, the robot has " + std::to_string(model.nq) + " coordinates");
  if (!system.contacts.empty() && (!system.contact_model || !system.terrain))
    throw std::invalid_argument("integrator: contacts need a contact model and a terrain");
  for (const ContactPoint& c : system.contacts)
    if (c.link < 0 || c.link >= static_cast<int>(model.links.size()))
      throw std::invalid_argument("integrator: contact '" + c.name + "' has no valid link");
  if (!system.contacts.empty() && needsContactDerivative(options.method) &&
      system.contact_model->derivative() == DerivativeSupport::None) {
    const Method twin = options.method == Method::NePgm ? Method::NeZopgm : Method::PbdZopgm;
    throw std::invalid_argument(std::string("integrator: method ") + methodName(options.method) +
                                " needs the contact model's derivative, and " + system.contact_model->describe() +
                                " has none; use " + methodName(twin) + " (zeroth order) instead");
  }
  if (options.order != 1 && options.order != 2)
    throw std::invalid_argument("integrator: order " + std::to_string(options.order) +
                                " is not available; use 1 (backward Euler) or 2 (BDF2)");
  if (options.order == 2 && options.method == Method::NeMdp)
    throw std::invalid_argument("integrator: ne-mdp is first order only (order 1); order 2 needs an NMDP method "
                                "(ne-pgm, ne-zopgm, pbd-pgm, pbd-zopgm)");
  if (!(options.min_substep > 0) || !(options.eta > 1) || !(options.eta_reject > 1) || !(options.eta_limited > 1) ||
      !(options.beta_min > 0) || !(options.beta_max >= options.beta_min) || !(options.tol_w > 0) ||
      !(options.epsilon > 0) || options.max_outer_iterations < 1 || options.projection_max_iterations < 1 ||
      !(options.projection_tolerance > 0) || !(options.energy_tolerance >= 0) ||
      !(options.accuracy >= 0 && options.accuracy < std::numeric_limits<double>::infinity()))
    throw std::invalid_argument("integrator: options out of range (need min_substep, tol_w, epsilon, beta_min, "
                                "projection_tolerance > 0, energy_tolerance >= 0, accuracy finite and >= 0, eta, eta_reject, eta_limited > 1, "
                                "beta_max >= beta_min, iteration limits >= 1)");
}

}  // namespace nmdp
