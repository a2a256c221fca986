// nmdp.Simulation: one run of a scene stepped from Python, with numpy views of its state and
// control from Python (targets and feed-forward torques in place of the scene's gait).
#include <pybind11/stl.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "array_arguments.hpp"
#include "bindings.hpp"
#include "contact_models/registry.hpp"
#include "py_json.hpp"
#include "py_simulation.hpp"
#include "sim/trajectory_layout.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace nmdp::python {

PySimulation::PySimulation(const PyScene& scene_)
    : scene(scene_), sim(buildSimulation(*scene_.config, ContactModelRegistry::withBuiltins())),
      kinematics(sim.model()),
      layout(stateLayout(sim.system())) {
  *scene.known_nq = sim.model().nq;
}

py::array readOnlyView(const double* data, py::ssize_t size, py::handle owner) {
  py::array view(py::dtype::of<double>(), {size}, {static_cast<py::ssize_t>(sizeof(double))}, data, owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

namespace {

// Steps until n steps are done or one does not converge, without the GIL. A pending signal
// (Ctrl-C) is looked at about every 50 ms between steps and raises its exception there, the state
// being that of the last completed step.
StepStats stepMany(PySimulation& s, long n) {
  if (n < 1) throw std::invalid_argument("n: expected a positive number of steps, got " + std::to_string(n));
  ExclusiveUse use(s);
  StepStats stats;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    using Clock = std::chrono::steady_clock;
    Clock::time_point checked = Clock::now();
    for (long i = 0; i < n; ++i) {
      stats = s.sim.step();
      s.last = stats;
      if (!stats.converged || i + 1 == n) break;
      if (Clock::now() - checked > std::chrono::milliseconds(50)) {
        py::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) {
          interrupted = true;
          break;
        }
        checked = Clock::now();
      }
    }
  }
  if (interrupted) throw py::error_already_set();
  return stats;
}

std::vector<bool> baseCoordinates(const Model& model) {
  std::vector<bool> base(static_cast<size_t>(model.nq));
  for (int j = 0; j < model.nq; ++j) base[static_cast<size_t>(j)] = model.bodies[static_cast<size_t>(j)].is_base;
  return base;
}

void setTargets(PySimulation& s, py::handle q_target, py::handle qdot_target) {
  const Model& model = s.sim.model();
  const std::vector<bool> base = baseCoordinates(model);
  Eigen::VectorXd position = vectorArgument(q_target, "q_target", model.nq);
  Eigen::VectorXd velocity =
      qdot_target.is_none() ? Eigen::VectorXd::Zero(model.nq) : vectorArgument(qdot_target, "qdot_target", model.nq);
  requireFinite(position, "q_target", model.dof_names, base);
  requireFinite(velocity, "qdot_target", model.dof_names, base);
  for (int j = 0; j < model.nq; ++j)  // never read by the PD law (zero gains); 0 keeps NaN out of sight
    if (base[static_cast<size_t>(j)]) position[j] = velocity[j] = 0.0;
  ExclusiveUse use(s);
  s.sim.setTargets(std::make_unique<HeldPdTarget>(std::move(position), std::move(velocity)));
}

py::tuple basePose(const PySimulation& s) {
  Vec3 position, rpy;
  s.sim.basePose(position, rpy);
  return py::make_tuple(py::array(3, position.data()), py::array(3, rpy.data()));
}

const char* const kStepDoc = R"(Takes n steps of dt (the scene's integrator.dt) without holding the GIL.

Stops early at a step that does not converge (failed or diverged): the state is then where the
integrator left it, as in `nmdp simulate`, and the returned StepStats say why (stats.converged is
False). Returns the StepStats of the last step taken. Ctrl-C is honoured between steps.)";

const char* const kTargetsDoc = R"(Holds the PD targets q_target (position) and qdot_target (velocity, default 0) from the
next step on, in place of the scene's gait: the stable-PD law stays implicit. Both are full vectors
of nq entries in the order of joint_names; base coordinates' entries are ignored (any value).)";

void bindStateViews(py::class_<PySimulation>& c) {
  c.def_property_readonly("q", [](py::object self) {
     const PySimulation& s = self.cast<const PySimulation&>();
     return readOnlyView(s.sim.state().q.data(), s.sim.model().nq, self);
   }, "Configuration (nq, joint_names order): a read-only view of the state, not a copy; it shows\n"
      "every later step and keeps the Simulation alive. Copy it (sim.q.copy()) to keep a value.")
      .def_property_readonly("qdot", [](py::object self) {
        const PySimulation& s = self.cast<const PySimulation&>();
        return readOnlyView(s.sim.state().qd.data(), s.sim.model().nq, self);
      }, "Velocity (nq): a read-only view of the state, as q.")
      .def_property_readonly("time", [](const PySimulation& s) { return s.sim.time(); },
                             "Simulated time, s (a number, not a view: a variable holding it keeps its value).")
      .def_property_readonly("dt", [](const PySimulation& s) { return s.sim.dt(); }, "One step, s (integrator.dt).")
      .def_property_readonly("nq", [](const PySimulation& s) { return s.sim.model().nq; }, "Coordinates of q.")
      .def_property_readonly("joint_names", [](const PySimulation& s) { return outputCoordinateNames(s.sim.model()); },
                             "The names of q's entries, as /joint_names of the output file (base coordinates first).")
      .def_property_readonly("actuated", [](const PySimulation& s) {
        std::vector<bool> base = baseCoordinates(s.sim.model());
        py::array_t<bool> mask(static_cast<py::ssize_t>(base.size()));
        for (size_t j = 0; j < base.size(); ++j) mask.mutable_at(static_cast<py::ssize_t>(j)) = !base[j];
        return mask;
      }, "Per entry of q: False for a base coordinate (unactuated), True for a joint.")
      .def("base_pose", &basePose, "The trunk's world pose: (position (3), roll-pitch-yaw ZYX (3)), as /base/position and /base/rpy.");
}

}  // namespace

void bindSimulation(py::module_& m) {
  py::class_<PySimulation> c(m, "Simulation", "One run of a scene, stepped from Python (see docs/PYTHON.md).");
  c.def(py::init<const PyScene&>(), py::arg("scene"),
        "Builds the run the scene describes, as `nmdp simulate` does; ValueError with the CLI's message on bad input.")
      .def("step", &stepMany, py::arg("n") = 1, kStepDoc)
      .def_property_readonly("stats", [](const PySimulation& s) { return s.last; }, "The StepStats of the last step (None before the first).")
      .def_property_readonly("scheduled_steps", [](const PySimulation& s) { return s.sim.scheduledSteps(); },
                             "Steps of dt the scene's duration takes, as `nmdp simulate` runs.")
      .def_property_readonly("scene", [](const PySimulation& s) { return s.scene; }, "The Scene it was built from.")
      .def_property_readonly("config", [](const PySimulation& s) { return toPython(s.sim.resolvedScene()); },
                             "The scene with every default filled in, the robot's included: the output file's `config`.")
      .def("set_targets", &setTargets, py::arg("q_target"), py::arg("qdot_target") = py::none(), kTargetsDoc);
  bindStateViews(c);
  bindContacts(c);
  bindState(c);
}

}  // namespace nmdp::python
