#include "contact_models/mlp/mlp_model.hpp"

#include "contact_models/mlp/mlp_function.hpp"
#include "common/input_error.hpp"
#include "contact_models/planar_model_config.hpp"
#include "contact_models/spatial_wrench_model.hpp"

namespace nmdp {

const std::vector<std::string> kMlpParameters = {"file", "torque_centre", "cutoff", "cutoff_width", "jacobian"};

std::unique_ptr<ContactModel> makeMlpModel(const nlohmann::json& params, const ConfigContext& ctx) {
  const std::string path =
      requireModelFile(params, kMlpParameters, "mlp", "missing: give the MLP model file (HDF5, .h5), as written by 'nmdp fit'", ctx);
  MlpModelFile model;
  try {
    model = loadMlpModel(path);
  } catch (const InputError& e) {
    failAtKey(ctx, "file", e.what());
  }

  const bool spatial = model.parameters.wrench == MlpWrench::Spatial;
  if (spatial && params.contains("torque_centre"))
    failAtKey(ctx, "torque_centre",
              "is for planar models: the spatial MLP in '" + path + "' gives the torque about the foot point");
  PlanarGeometry geometry = model.geometry;
  readGeometryOverrides(params, ctx, geometry);

  MlpJacobian jacobian = MlpJacobian::ForwardMode;
  if (const std::string name = readString(params, "jacobian", mlpJacobianName(jacobian), ctx);
      !parseMlpJacobian(name, &jacobian))
    failAtKey(ctx, "jacobian", "expected \"forward-mode\", \"double-backward\" or \"tangents\", got \"" + name + "\"");

  auto function = std::make_shared<const MlpFunction>(std::move(model.parameters), jacobian);
  const nlohmann::json source = {{"file", path}, {"jacobian", mlpJacobianName(jacobian)}};
  if (spatial)
    return std::make_unique<SpatialWrenchModel>(std::move(function), SpatialGeometry{geometry.cutoff, geometry.cutoff_width},
                                                "mlp", source);
  return std::make_unique<PlanarWrenchModel>(std::move(function), geometry, "mlp", source);
}

}  // namespace nmdp
