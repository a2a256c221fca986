#include "array_arguments.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace py = pybind11;

namespace nmdp::python {

ContiguousArray asDoubleArray(py::handle value, const std::string& name) {
  if (value.is_none()) throw std::invalid_argument(name + ": expected numbers, got None");
  try {
    return py::module_::import("numpy").attr("ascontiguousarray")(value, "float64").cast<ContiguousArray>();
  } catch (py::error_already_set& e) {  // e.g. a string among the numbers: numpy's reason, with the argument
    if (!e.matches(PyExc_ValueError) && !e.matches(PyExc_TypeError)) throw;
    throw std::invalid_argument(name + ": expected numbers: " + py::str(e.value()).cast<std::string>());
  }
}

std::string shapeText(const py::array& array) {
  std::ostringstream text;
  text << "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) text << (i ? ", " : "") << array.shape(i);
  text << (array.ndim() == 1 ? ",)" : ")");
  return text.str();
}

Eigen::VectorXd vectorArgument(py::handle value, const std::string& name, Eigen::Index size) {
  const ContiguousArray array = asDoubleArray(value, name);
  if (array.ndim() != 1)
    throw std::invalid_argument(name + ": expected a vector of " + std::to_string(size) + " entries, got an array of shape " +
                                shapeText(array));
  if (array.shape(0) != size)
    throw std::invalid_argument(name + ": expected " + std::to_string(size) + " entries, got " + std::to_string(array.shape(0)));
  return Eigen::Map<const Eigen::VectorXd>(array.data(), size);
}

void requireFinite(const Eigen::VectorXd& values, const std::string& name, const std::vector<std::string>& labels,
                   const std::vector<bool>& skip) {
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const size_t k = static_cast<size_t>(i);
    if (std::isfinite(values[i]) || (k < skip.size() && skip[k])) continue;
    std::ostringstream text;
    text << name << ": entry " << i;
    if (k < labels.size()) text << " (" << labels[k] << ")";
    text << " is " << values[i] << "; expected a finite number";
    throw std::invalid_argument(text.str());
  }
}

}  // namespace nmdp::python
