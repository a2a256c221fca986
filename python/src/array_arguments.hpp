// Numbers from Python arguments, checked so that a wrong shape or a NaN is a ValueError naming the
// argument and what was expected ("q_target: expected 15 entries, got 3"), never a crash or a
// silent broadcast. Anything numpy.asarray turns into float64 is accepted (lists, tuples, arrays).
#pragma once
#include <Eigen/Core>
#include <pybind11/numpy.h>
#include <string>
#include <vector>

namespace nmdp::python {

using ContiguousArray = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;

// value as a C-contiguous float64 array (a copy only if it is not one already).
ContiguousArray asDoubleArray(pybind11::handle value, const std::string& name);

// "(3, 4)": an array's shape as numpy prints it.
std::string shapeText(const pybind11::array& array);

// A vector of exactly `size` entries; std::invalid_argument naming `name` otherwise.
Eigen::VectorXd vectorArgument(pybind11::handle value, const std::string& name, Eigen::Index size);

// Every entry finite, but those where skip[i] (e.g. base coordinates) is true; `labels` name the
// entries in the message (may be empty).
void requireFinite(const Eigen::VectorXd& values, const std::string& name, const std::vector<std::string>& labels,
                   const std::vector<bool>& skip = {});

}  // namespace nmdp::python
