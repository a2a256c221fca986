#include "solver/system.hpp"

#include "multibody/feet.hpp"

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace nmdp {

System systemOnFeet(const Model& model, const ContactModel& contact_model, const Terrain& terrain, PdGains gains) {
  System system;
  system.model = &model;
  system.contacts = footContactPoints(model);
  system.contact_model = &contact_model;
  system.terrain = &terrain;
  system.gains = std::move(gains);
  return system;
}

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
  validateIntegratorOptions(options);
}

}  // namespace nmdp
