#include "python_json.hpp"

#include "common/input_error.hpp"

namespace nmdp::python {

namespace py = pybind11;

nlohmann::json jsonFromPython(const py::handle& value, const std::string& where) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    try {
      return value.cast<long long>();
    } catch (const py::cast_error&) {
      throw InputError(where + ": the integer " + py::str(value).cast<std::string>().substr(0, 40) +
                       " does not fit in 64 bits");
    }
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& item : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first))
        throw InputError(where + ": key " + py::repr(item.first).cast<std::string>().substr(0, 40) + " is not a string");
      const std::string key = item.first.cast<std::string>();
      object[key] = jsonFromPython(item.second, where + "." + key);
    }
    return object;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    size_t i = 0;
    for (const auto& item : value) array.push_back(jsonFromPython(item, where + "[" + std::to_string(i++) + "]"));
    return array;
  }
  if (py::hasattr(value, "tolist")) return jsonFromPython(value.attr("tolist")(), where);  // numpy
  throw InputError(where + ": a " + py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() +
                   " is not a JSON value (expected dict, list, str, number, bool or None)");
}

py::object pythonFromJson(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

}  // namespace nmdp::python
