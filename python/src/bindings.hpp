// The parts of the Python module nmdp._core, one function per concept (one file each), called by
// python/src/module.cpp in this order.
#pragma once
#include <pybind11/pybind11.h>

namespace nmdp::python {

void bindErrors(pybind11::module_& m);  // InputError and std::invalid_argument → ValueError
void bindContactModel(pybind11::module_& m);  // nmdp.ContactModel
void bindFit(pybind11::module_& m);  // nmdp.fit

}  // namespace nmdp::python
