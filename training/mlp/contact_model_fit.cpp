#include "training/mlp/contact_model_fit.hpp"

#include "common/input_error.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/spatial_wrench_model.hpp"

namespace nmdp {

void requireFitModelName(const std::string& model) {
  if (model != "rbf" && model != "mlp") throw InputError("--model: expected rbf or mlp, got '" + model + "'");
}

ContactModelFit fitContactModel(const ForceDataset& data, const std::string& model, const FitConfig& config,
                                const std::string& data_name, const MlpProgress& progress) {
  requireFitModelName(model);
  ContactModelFit fit;
  fit.model = model;
  if (model == "mlp")
    fit.mlp = fitMlpToDataset(data, config, data_name, progress);
  else
    fit.rbf = fitRbfToDataset(data, config, data_name);
  return fit;
}

std::string formatContactModelFitReport(const ContactModelFit& fit) {
  return fit.mlp ? formatMlpFitReport(fit.mlp->record) : formatRbfFitReport(fit.rbf->record);
}

void saveContactModelFit(const std::string& path, const ContactModelFit& fit) {
  if (fit.mlp)
    saveMlpFit(path, fit.mlp->record, fit.mlp->geometry);
  else
    saveRbfFit(path, fit.rbf->record, fit.rbf->geometry);
}

std::unique_ptr<ContactModel> fittedContactModel(const ContactModelFit& fit) {
  if (fit.mlp) {
    auto function = std::make_shared<const MlpFunction>(fit.mlp->record.fit.parameters);
    if (fit.mlp->spatial())
      return std::make_unique<SpatialWrenchModel>(std::move(function), fit.mlp->spatialGeometry(), "mlp");
    return std::make_unique<PlanarWrenchModel>(std::move(function), fit.mlp->geometry, "mlp");
  }
  auto function = std::make_shared<const RbfFunction>(fit.rbf->record.fit.parameters);
  return std::make_unique<PlanarWrenchModel>(std::move(function), fit.rbf->geometry, "rbf");
}

}  // namespace nmdp
