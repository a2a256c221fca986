// nmdp.StepStats: what one step reports (solver/step_stats.hpp), as step() returns it and
// sim.stats keeps it.
#include "bindings.hpp"
#include "solver/step_stats.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace nmdp::python {

namespace {

py::dict energyDict(const StepEnergy& e) {
  return py::dict("excess"_a = e.excess, "supplied"_a = e.supplied, "turnover"_a = e.turnover, "tolerance"_a = e.tolerance,
                  "free_fall"_a = e.free_fall);
}

py::dict statsDict(const StepStats& s) {
  return py::dict("status"_a = toString(s.status), "converged"_a = s.converged, "substeps"_a = s.substeps,
                  "outer_iterations"_a = s.outer_iterations, "g_evaluations"_a = s.g_evaluations,
                  "projections"_a = s.projections, "newton_iterations"_a = s.newton_iterations, "rejected"_a = s.rejected,
                  "min_substep"_a = s.min_substep, "wall_time"_a = s.wall_time, "error_estimate"_a = s.error_estimate,
                  "error_rejections"_a = s.error_rejections, "first_order_restarts"_a = s.first_order_restarts,
                  "energy"_a = energyDict(s.energy));
}

}  // namespace

void bindStepStats(py::module_& m) {
  py::class_<StepStats>(m, "StepStats", "What one step reports: its status and the solver's work (read-only).")
      .def_property_readonly("status", [](const StepStats& s) { return toString(s.status); },
                             "\"converged\", or why the step failed (e.g. \"outer-iteration limit reached\").")
      .def_readonly("converged", &StepStats::converged)
      .def_readonly("substeps", &StepStats::substeps, "accepted sub-steps (1: no split)")
      .def_readonly("outer_iterations", &StepStats::outer_iterations, "summed over sub-steps and failed attempts")
      .def_readonly("g_evaluations", &StepStats::g_evaluations)
      .def_readonly("projections", &StepStats::projections)
      .def_readonly("newton_iterations", &StepStats::newton_iterations)
      .def_readonly("rejected", &StepStats::rejected, "outer iterations the trust region rejected")
      .def_readonly("min_substep", &StepStats::min_substep, "smallest accepted sub-step, s")
      .def_readonly("wall_time", &StepStats::wall_time, "s")
      .def_readonly("error_estimate", &StepStats::error_estimate, "largest normalized local error (0: accuracy off)")
      .def_readonly("error_rejections", &StepStats::error_rejections)
      .def_readonly("first_order_restarts", &StepStats::first_order_restarts)
      .def_property_readonly("energy", [](const StepStats& s) { return energyDict(s.energy); },
                             "the divergence check's balance (J): excess, supplied, turnover, tolerance, free_fall")
      .def("to_dict", &statsDict, "Every field as a dict.")
      .def("__repr__", [](const StepStats& s) {
        return "StepStats(status=" + py::repr(py::str(toString(s.status))).cast<std::string>() +
               ", substeps=" + std::to_string(s.substeps) + ", outer_iterations=" + std::to_string(s.outer_iterations) + ")";
      });
}

}  // namespace nmdp::python
