#include "contact_models/planar_model_config.hpp"

#include "common/input_error.hpp"

namespace nmdp {

void failAtKey(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

std::string requireModelFile(const nlohmann::json& params, std::vector<std::string> keys, const std::string& type,
                             const std::string& missing, const ConfigContext& ctx) {
  keys.push_back("type");
  requireKnownKeys(params, keys, ctx);
  if (const std::string given = readString(params, "type", type, ctx); given != type)
    failAtKey(ctx, "type", "expected \"" + type + "\", got \"" + given + "\"");
  if (!params.contains("file")) failAtKey(ctx, "file", missing);
  const std::string file = readString(params, "file", "", ctx);
  if (file.empty()) failAtKey(ctx, "file", "is empty");
  return ctx.resolve(file);
}

void readGeometryOverrides(const nlohmann::json& params, const ConfigContext& ctx, PlanarGeometry& geometry) {
  geometry.torque_centre = readNumber(params, "torque_centre", geometry.torque_centre, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff = readNumber(params, "cutoff", geometry.cutoff, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff_width = readNumber(params, "cutoff_width", geometry.cutoff_width, ctx, 0.0, kMaxGeometryLength);
  if (!(geometry.cutoff_width > 0.0))
    failAtKey(ctx, "cutoff_width", "must be positive (the wrenches blend to zero over this band below the cut-off)");
}

}  // namespace nmdp
