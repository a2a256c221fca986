// nmdp.rollout: many independent runs of one scene from given states, threaded in C++
// (sim/rollout.hpp) with the GIL released; the result is one numpy array [B, steps + 1, nx].
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "array_arguments.hpp"
#include "bindings.hpp"
#include "contact_models/registry.hpp"
#include "py_scene.hpp"
#include "sim/rollout.hpp"

namespace py = pybind11;

namespace nmdp::python {

namespace {

RowMajorMatrix initialStates(py::handle value) {
  const ContiguousArray array = asDoubleArray(value, "initial_states");
  if (array.ndim() != 2 || array.shape(0) < 1)
    throw std::invalid_argument("initial_states: expected an array of shape (B, nx) (flat states, Simulation.get_state()) or "
                                "(B, 2 nq) (q and qdot), B >= 1; got shape " + shapeText(array));
  return Eigen::Map<const RowMajorMatrix>(array.data(), array.shape(0), array.shape(1));
}

// controls [B, steps, 2 nq or 3 nq] as the request's [B, steps · width] (the same row-major memory).
RowMajorMatrix controlRows(py::handle value, Eigen::Index entries, long steps, int nq) {
  const ContiguousArray array = asDoubleArray(value, "controls");
  if (array.ndim() != 3 || array.shape(0) != entries || array.shape(1) != steps ||
      (array.shape(2) != 2 * nq && array.shape(2) != 3 * nq)) {
    const std::string leading = "(" + std::to_string(entries) + ", " + std::to_string(steps) + ", ";
    throw std::invalid_argument("controls: expected an array of shape " + leading + std::to_string(2 * nq) +
                                ") (B, steps, 2 nq: q and qdot targets per step) or " + leading + std::to_string(3 * nq) +
                                ") (and the feed-forward torque); got shape " + shapeText(array));
  }
  return Eigen::Map<const RowMajorMatrix>(array.data(), entries, steps * array.shape(2));
}

// The result's states as a numpy array that owns them (no copy).
py::array statesArray(std::vector<double>&& states, Eigen::Index entries, long steps) {
  auto* owned = new std::vector<double>(std::move(states));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  const py::ssize_t rows = static_cast<py::ssize_t>(entries) * (steps + 1);
  const py::ssize_t nx = rows > 0 ? static_cast<py::ssize_t>(owned->size()) / rows : 0;
  return py::array_t<double>({static_cast<py::ssize_t>(entries), static_cast<py::ssize_t>(steps + 1), nx}, owned->data(), owner);
}

py::object runRollout(const PyScene& scene, py::handle initial_states, long steps, py::handle controls, int threads,
                      bool return_status) {
  RolloutRequest request;
  request.initial_states = initialStates(initial_states);
  if (steps < 1 || steps > 1000000000L)
    throw std::invalid_argument("steps: expected a positive number of steps, got " + std::to_string(steps));
  request.steps = static_cast<int>(steps);
  if (!controls.is_none()) request.controls = controlRows(controls, request.initial_states.rows(), steps, scene.nq());
  request.threads = threads;
  const ContactModelRegistry models = ContactModelRegistry::withBuiltins();
  RolloutResult result;
  {
    py::gil_scoped_release release;
    result = rollout(*scene.config, models, request);
  }
  py::array states = statesArray(std::move(result.states), request.initial_states.rows(), steps);
  if (!return_status) return std::move(states);
  std::vector<std::string> status;
  for (StepStatus s : result.status) status.emplace_back(toString(s));
  return py::make_tuple(states, status, py::array_t<int>(static_cast<py::ssize_t>(result.steps_done.size()), result.steps_done.data()));
}

const char* const kRolloutDoc = R"(Runs B independent simulations of `scene` for `steps` steps each, on `threads` threads in C++
(without the GIL), and returns their flat states as an array [B, steps + 1, nx] (nx as
Simulation.get_state(); row 0 is the start, so states[:, :, 1:1+nq] is q and states[:, :, 0] time).

initial_states: [B, nx] flat states (Simulation.get_state()), each restored as set_state does; or
  [B, 2 nq] rows (q, qdot), each started as the scene starts (time 0, the scene's start state but
  for q and qdot).
controls: None (the scene's gait), or [B, steps, 2 nq] (PD target position and velocity held over
  each step, as set_targets) or [B, steps, 3 nq] (and the feed-forward torque, as set_feedforward).
threads: every entry gives the same bits with any number of threads, and the bits of a loop of
  Simulation.step from its state.
return_status: if True, returns (states, status, steps_done): status[b] is "converged" or why the
  entry's step failed (as StepStats.status), steps_done[b] its converged steps. From a step that
  does not converge on, an entry's states are NaN.
ValueError naming the argument for a wrong shape or a non-finite entry.)";

}  // namespace

void bindRollout(py::module_& m) {
  m.def("rollout", &runRollout, py::arg("scene"), py::arg("initial_states"), py::arg("steps"), py::arg("controls") = py::none(),
        py::arg("threads") = 1, py::arg("return_status") = false, kRolloutDoc);
}

}  // namespace nmdp::python
