#include "contact_models/mlp/mlp_model.hpp"

#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "common/input_error.hpp"

namespace nmdp {

const std::vector<std::string> kMlpParameters = {"file", "torque_centre", "cutoff", "cutoff_width", "jacobian"};

namespace {
[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}
}  // namespace

std::unique_ptr<ContactModel> makeMlpModel(const nlohmann::json& params, const ConfigContext& ctx) {
  std::vector<std::string> keys = kMlpParameters;
  keys.push_back("type");
  requireKnownKeys(params, keys, ctx);
  if (const std::string type = readString(params, "type", "mlp", ctx); type != "mlp")
    fail(ctx, "type", "expected \"mlp\", got \"" + type + "\"");

  if (!params.contains("file"))
    fail(ctx, "file", "missing: give the MLP model file (HDF5, .h5), as written by 'nmdp fit'");
  const std::string file = readString(params, "file", "", ctx);
  if (file.empty()) fail(ctx, "file", "is empty");
  const std::string path = ctx.resolve(file);

  MlpModelFile model;
  try {
    model = loadMlpModel(path);
  } catch (const InputError& e) {
    fail(ctx, "file", e.what());
  }

  PlanarGeometry geometry = model.geometry;
  geometry.torque_centre = readNumber(params, "torque_centre", geometry.torque_centre, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff = readNumber(params, "cutoff", geometry.cutoff, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff_width = readNumber(params, "cutoff_width", geometry.cutoff_width, ctx, 0.0, kMaxGeometryLength);
  if (!(geometry.cutoff_width > 0.0))
    fail(ctx, "cutoff_width", "must be positive (the wrenches blend to zero over this band below the cut-off)");

  MlpJacobian jacobian = MlpJacobian::ForwardMode;
  if (const std::string name = readString(params, "jacobian", mlpJacobianName(jacobian), ctx);
      !parseMlpJacobian(name, &jacobian))
    fail(ctx, "jacobian", "expected \"forward-mode\", \"double-backward\" or \"tangents\", got \"" + name + "\"");

  auto function = std::make_shared<const MlpFunction>(std::move(model.parameters), jacobian);
  const nlohmann::json source = {{"file", path}, {"jacobian", mlpJacobianName(jacobian)}};
  return std::make_unique<PlanarWrenchModel>(std::move(function), geometry, "mlp", source);
}

}  // namespace nmdp
