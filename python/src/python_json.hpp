// JSON values to and from Python objects, for the bindings that take or give the JSON objects of the
// CLI (contact model configurations, FIT.json): dict ↔ object, list/tuple ↔ array, str, bool, int,
// float, None; numpy scalars and arrays through their tolist().
#pragma once
#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>
#include <string>

namespace nmdp::python {

// ValueError "`where`: ..." naming the entry (e.g. "config.rbf.scaling[1]") for a value JSON cannot hold.
nlohmann::json jsonFromPython(const pybind11::handle& value, const std::string& where);
pybind11::object pythonFromJson(const nlohmann::json& value);

}  // namespace nmdp::python
