// Python values ⇄ JSON, for scene overrides (Scene.load's `overrides`) and the resolved scene
// (Scene.to_dict): the two places where the bindings hand JSON across.
#pragma once
#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>
#include <string>

namespace nmdp::python {

// None, bool, int, float (finite), str, list/tuple, dict with str keys, numpy scalars and arrays
// (through .tolist()), nested. std::invalid_argument "<where>: ..." for anything else (a set, an
// object, a NaN), naming the value's type.
nlohmann::json toJson(pybind11::handle value, const std::string& where);

// The JSON as plain Python values (dict, list, str, float, int, bool, None).
pybind11::object toPython(const nlohmann::json& value);

}  // namespace nmdp::python
