// The parts of the Python module nmdp._core, one function per concept (one file each), called by
// python/src/module.cpp in this order.
#pragma once
#include <pybind11/pybind11.h>

namespace nmdp::python {

void bindErrors(pybind11::module_& m);        // InputError and std::invalid_argument → ValueError
void bindStepStats(pybind11::module_& m);     // nmdp.StepStats (stats_bindings.cpp)
void bindScene(pybind11::module_& m);         // nmdp.Scene (scene_bindings.cpp)
void bindSimulation(pybind11::module_& m);    // nmdp.Simulation (simulation_bindings.cpp, simulation_*.cpp)
void bindRollout(pybind11::module_& m);       // nmdp.rollout (rollout_bindings.cpp)
void bindContactModel(pybind11::module_& m);  // nmdp.ContactModel (contact_model_bindings.cpp)
void bindFit(pybind11::module_& m);           // nmdp.fit (fit_bindings.cpp)

}  // namespace nmdp::python
