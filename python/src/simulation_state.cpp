// sim.get_state() / sim.set_state(x): the whole state as one flat vector (sim/state_vector.hpp),
// so that a run restored from it repeats bit for bit; and sim.set_feedforward(tau).
#include "array_arguments.hpp"
#include "py_simulation.hpp"
#include "sim/state_vector.hpp"

namespace py = pybind11;

namespace nmdp::python {

namespace {

py::array getState(PySimulation& s) {
  ExclusiveUse use(s);  // the flat buffer is the object's own
  flattenState(s.layout, s.sim.state(), s.flat);
  return py::array(s.flat.size(), s.flat.data());  // a copy: the state moves on, this does not
}

void setState(PySimulation& s, py::handle state) {
  const Eigen::VectorXd x = vectorArgument(state, "state", s.layout.size());
  ExclusiveUse use(s);
  SimulationState restored = s.sim.state();  // sized as the simulation's; unflattenState overwrites every part
  unflattenState(s.layout, x, restored);
  s.sim.setState(restored);
  s.last.reset();
}

py::dict stateLayout(const PySimulation& s) {
  py::dict parts;
  for (const StateLayout::Part& part : s.layout.parts())
    parts[py::str(part.name)] = py::slice(part.offset, part.offset + part.length, 1);
  return parts;
}

void setFeedforward(PySimulation& s, py::handle tau) {
  const Eigen::VectorXd torque = vectorArgument(tau, "tau", s.sim.model().nq);
  ExclusiveUse use(s);
  s.sim.setFeedforward(torque);
}

const char* const kGetStateDoc = R"(The whole state as a new flat float64 array (nx = len(get_state())): time, q, qdot, then
everything else a step carries to the next (state_layout names the parts). set_state(x) restores it:
the steps that follow then repeat the steps that followed get_state() bit for bit, in this
Simulation or another built from the same scene.)";

const char* const kSetStateDoc = R"(Restores a state from get_state() (of this Simulation or one built from the same scene).
ValueError naming the part and entry for a wrong size, a non-finite number, a flag that is not 0 or
1, or a base chart that is not a rotation. The views sim.q and sim.qdot show the restored state;
contacts' wrenches read zero and stats None until the next step.)";

const char* const kFeedforwardDoc = R"(The feed-forward torque τ_ff (nq, N·m or N, joint_names order) of the PD law from the next
step on, in place of the scene's controller.tau_ff; held until set again. Base coordinates are
unactuated: their entries must be 0. ValueError for a wrong size, a non-finite entry or a base
entry that is not 0.)";

}  // namespace

void bindState(py::class_<PySimulation>& c) {
  c.def("get_state", &getState, kGetStateDoc)
      .def("set_state", &setState, py::arg("state"), kSetStateDoc)
      .def_property_readonly("state_layout", &stateLayout,
                             "{part name: slice} of the flat state: \"time\", \"q\", \"qdot\", \"q_prev\", ... in order.")
      .def("set_feedforward", &setFeedforward, py::arg("tau"), kFeedforwardDoc);
}

}  // namespace nmdp::python
