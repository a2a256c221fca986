// sim.contacts: where each contact sphere is, how deep in the terrain, and the wrench it carried
// over the last step; computed when asked, from the current state.
#include "contact_models/contact_model.hpp"
#include "multibody/kinematics.hpp"
#include "py_simulation.hpp"
#include "solver/contact_kinematics.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace nmdp::python {

namespace {

py::list contacts(PySimulation& s) {
  const Simulation& sim = s.sim;
  const Model& model = sim.model();
  const SimulationState& state = sim.state();
  s.kinematics.base_chart = state.base_chart;
  forwardKinematics(model, s.kinematics, state.q);
  const std::vector<Vec6>& wrenches = sim.contactWrenches();
  py::list out;
  ContactFrame frame;
  TerrainQuery ground;
  for (size_t i = 0; i < sim.system().contacts.size(); ++i) {
    const ContactPoint& contact = sim.system().contacts[i];
    contactFrame(model, s.kinematics, contact, frame);
    sim.terrain().query(frame.position, ground, false);
    const Vec6 wrench = i < wrenches.size() ? wrenches[i] : Vec6::Zero();
    out.append(py::dict("name"_a = contact.name, "point"_a = py::array(3, frame.position.data()),
                        "radius"_a = contact.radius, "depth"_a = contact.radius - ground.distance,
                        "normal"_a = py::array(3, ground.normal.data()), "wrench"_a = py::array(6, wrench.data())));
  }
  return out;
}

const char* const kContactsDoc = R"(One dict per contact sphere, in the order of the output file's /contacts/names:
  name    the contact's name
  point   the sphere's centre, world frame (m), at the current state
  radius  the sphere's radius (m)
  depth   how far the sphere's lowest point is below the terrain: radius − φ(point), φ the terrain's
          signed distance (m); positive in the ground, negative above it
  normal  the terrain's normal at point (unit, world)
  wrench  [torque about the sphere centre (3); force (3)], world (N·m, N): the last step's,
          averaged over its sub-steps by their duration, as /contacts/wrench; zero before the first
          step and after set_state.
Copies, not views.)";

}  // namespace

void bindContacts(py::class_<PySimulation>& c) {
  c.def_property_readonly("contacts", [](PySimulation& s) {
    ExclusiveUse use(s);  // the kinematics buffer is the object's own
    return contacts(s);
  }, kContactsDoc);
}

}  // namespace nmdp::python
