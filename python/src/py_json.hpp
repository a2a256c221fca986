// Python values ⇄ JSON, wherever the bindings hand JSON across: scene overrides (Scene.load's
// `overrides`), the resolved scene (Scene.to_dict), contact-model configurations and FIT.json.
#pragma once
#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>
#include <string>

namespace nmdp::python {

// None, bool, int, float (finite), str, list/tuple, dict with str keys, numpy scalars and arrays
// (through .tolist()), nested. std::invalid_argument "<where>: ..." for anything else (a set, an
// object, a NaN), naming the value's type and its entry (e.g. "--config.rbf.scaling[1]").
nlohmann::json toJson(pybind11::handle value, const std::string& where);

// The JSON as plain Python values (dict, list, str, float, int, bool, None).
pybind11::object toPython(const nlohmann::json& value);

}  // namespace nmdp::python
