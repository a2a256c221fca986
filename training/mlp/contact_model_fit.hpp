// One fit of `nmdp fit --model rbf|mlp` (and the Python nmdp.fit): the RBF or MLP pipeline on a
// dataset (fitRbfToDataset in fit_config.hpp, fitMlpToDataset in mlp_fit.hpp), its report, its model
// file and the contact model it makes, whichever model was fitted.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "contact_models/contact_model.hpp"
#include "training/fit_config.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp {

struct ContactModelFit {
  std::string model;                // "rbf" or "mlp"
  std::optional<RbfFitOutcome> rbf;  // set for "rbf"
  std::optional<MlpFitOutcome> mlp;  // set for "mlp"
};

// InputError "--model: expected rbf or mlp, got '...'" for any other name.
void requireFitModelName(const std::string& model);

// Runs the pipeline of `model`; `progress` sees every MLP epoch (unused for the RBF). Throws what the
// pipeline throws (InputError for bad data or settings).
ContactModelFit fitContactModel(const ForceDataset& data, const std::string& model, const FitConfig& config,
                                const std::string& data_name, const MlpProgress& progress = {});

// The report `nmdp fit` prints (formatRbfFitReport or formatMlpFitReport).
std::string formatContactModelFitReport(const ContactModelFit& fit);

// Writes the model file (saveRbfFit or saveMlpFit), which the "rbf" or "mlp" contact model loads.
void saveContactModelFit(const std::string& path, const ContactModelFit& fit);

// The fitted model in memory: the same function and geometry as the file loads (bit for bit), with
// no configuration() (it has no file; load the saved file for one).
std::unique_ptr<ContactModel> fittedContactModel(const ContactModelFit& fit);

}  // namespace nmdp
