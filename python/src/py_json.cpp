#include "py_json.hpp"

#include <cmath>
#include <stdexcept>

#include "common/limits.hpp"

namespace py = pybind11;

namespace nmdp::python {

namespace {

nlohmann::json toJsonAt(py::handle value, const std::string& where, int depth) {
  // Self-containing lists would recurse forever; a scene nests far less than the JSON limit.
  if (depth > limits::kMaxJsonDepth)
    throw std::invalid_argument(where + ": nested more than " + std::to_string(limits::kMaxJsonDepth) + " levels");
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::float_>(value)) {  // also numpy.float64, a float subclass
    const double x = value.cast<double>();
    if (!std::isfinite(x)) throw std::invalid_argument(where + ": " + py::repr(value).cast<std::string>() + " is not a finite number");
    return x;
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype"))  // numpy arrays and scalars
    return toJsonAt(value.attr("tolist")(), where, depth + 1);
  if (PyIndex_Check(value.ptr())) {  // int and objects that act as one
    const py::int_ integer = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    if (!integer) throw py::error_already_set();
    try {
      return integer.cast<long long>();
    } catch (const py::cast_error&) {
      throw std::invalid_argument(where + ": the integer " + py::repr(value).cast<std::string>() + " does not fit in 64 bits");
    }
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    size_t i = 0;
    for (py::handle item : value) array.push_back(toJsonAt(item, where + "[" + std::to_string(i++) + "]", depth + 1));
    return array;
  }
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (auto [key, item] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw std::invalid_argument(where + ": a JSON object's keys are strings, got " + py::repr(key).cast<std::string>());
      const std::string name = key.cast<std::string>();
      object[name] = toJsonAt(item, where + "." + name, depth + 1);
    }
    return object;
  }
  throw std::invalid_argument(where + ": a " + py::str(value.get_type().attr("__name__")).cast<std::string>() +
                              " has no JSON form (expected None, bool, int, float, str, list, tuple or dict)");
}

}  // namespace

nlohmann::json toJson(py::handle value, const std::string& where) { return toJsonAt(value, where, 0); }

py::object toPython(const nlohmann::json& value) {
  // The json module's reading of the text is the plain Python form, with no type to special-case.
  return py::module_::import("json").attr("loads")(value.dump());
}

}  // namespace nmdp::python
