// nmdp._core: the compiled part of the Python package nmdp (python/nmdp/__init__.py re-exports it).
#include "bindings.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "nmdp: legged robots on rigid and granular ground with learned contact models";
  nmdp::python::bindErrors(m);
  nmdp::python::bindStepStats(m);
  nmdp::python::bindScene(m);
  nmdp::python::bindSimulation(m);
  nmdp::python::bindRollout(m);
  nmdp::python::bindContactModel(m);
  nmdp::python::bindFit(m);
}
