// What the factories of the planar contact models (rbf_model.hpp, mlp/mlp_model.hpp) read the same
// way: the model's "type" and "file" keys, and the geometry keys that override the file's.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/json_params.hpp"
#include "contact_models/planar_wrench_model.hpp"

namespace nmdp {

// InputError "<where>.<key>: <what>" (no key: "<where>: <what>").
[[noreturn]] void failAtKey(const ConfigContext& ctx, const std::string& key, const std::string& what);

// Checks the keys (`keys` and "type") and that "type" is `type`; returns the "file" key resolved
// against ctx, failing with `missing` when it is absent.
std::string requireModelFile(const nlohmann::json& params, std::vector<std::string> keys, const std::string& type,
                             const std::string& missing, const ConfigContext& ctx);

// torque_centre, cutoff and cutoff_width from `params` where given (the file's values otherwise).
void readGeometryOverrides(const nlohmann::json& params, const ConfigContext& ctx, PlanarGeometry& geometry);

}  // namespace nmdp
