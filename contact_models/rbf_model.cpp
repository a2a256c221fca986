#include "contact_models/rbf_model.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "contact_models/planar_model_config.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/spatial_rbf_function.hpp"
#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/input_file.hpp"

namespace nmdp {

const std::vector<std::string> kRbfParameters = {"file",    "format",        "weights_file", "kernel",      "scaling",
                                                 "epsilon", "torque_centre", "cutoff",       "cutoff_width"};

namespace {

namespace fs = std::filesystem;

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Whether the model is in the published text format (else HDF5): the "format" key, or the path.
bool isPublishedFormat(const nlohmann::json& params, const std::string& path, const ConfigContext& ctx) {
  const std::string format = readString(params, "format", "auto", ctx);
  std::error_code ec;
  if (format == "published") return true;
  if (format == "hdf5") return false;
  if (format != "auto") failAtKey(ctx, "format", "expected \"auto\", \"published\" or \"hdf5\", got \"" + format + "\"");
  const std::string ext = lowerExtension(path);
  if (fs::is_directory(path, ec) || ext == ".txt") return true;
  if (ext == ".h5" || ext == ".hdf5") return false;
  if (!pathExists(path)) failAtKey(ctx, "file", displayPath(path) + ": no such file or folder");
  failAtKey(ctx, "file",
            displayPath(path) +
                ": cannot tell the format from the name: give an HDF5 file (.h5), a folder with "
                "inputs.txt and weights.txt, or a centres file (.txt), or set \"format\" to "
                "\"published\" or \"hdf5\"");
}

// The published text format: the kernel keys, the centres and weights files; records them in `source`.
RbfParameters readPublished(const nlohmann::json& params, const std::string& path, const ConfigContext& ctx,
                            nlohmann::json& source) {
  RbfKernelSpec spec;
  const std::string kernel = readString(params, "kernel", rbfKernelName(spec.kernel), ctx);
  if (!parseRbfKernel(kernel, &spec.kernel))
    failAtKey(ctx, "kernel", "unknown kernel \"" + kernel + "\"; valid kernels: " + rbfKernelNames());
  const std::vector<double> scaling = readNumbers(params, "scaling", {spec.scaling[0], spec.scaling[1]}, ctx);
  if (scaling.size() != 2 || !(scaling[0] > 0.0) || !(scaling[1] > 0.0))
    failAtKey(ctx, "scaling", "expected two positive numbers [s_phi, s_beta], got " + jsonForMessage(params.at("scaling")));
  spec.scaling = Eigen::Vector2d(scaling[0], scaling[1]);
  spec.epsilon = readNumber(params, "epsilon", spec.epsilon, ctx, 0.0);
  if (!(spec.epsilon > 0.0)) failAtKey(ctx, "epsilon", "must be positive");

  std::error_code ec;
  std::string inputs, weights;
  if (fs::is_directory(path, ec)) {
    inputs = (fs::path(path) / "inputs.txt").string();
    weights = (fs::path(path) / "weights.txt").string();
  } else {
    inputs = path;
    weights = (fs::path(path).parent_path() / "weights.txt").string();
  }
  if (params.contains("weights_file")) weights = ctx.resolve(readString(params, "weights_file", "", ctx));
  RbfParameters parameters;
  try {
    parameters = readPublishedRbf(inputs, weights, spec);
  } catch (const InputError& e) {
    failAtKey(ctx, "file", e.what());
  }
  source["weights_file"] = weights;
  source["kernel"] = rbfKernelName(spec.kernel);
  source["scaling"] = {spec.scaling[0], spec.scaling[1]};
  source["epsilon"] = spec.epsilon;
  return parameters;
}

// The HDF5 format, which stores the kernel with the weights (the published-format keys are refused).
RbfModelFile readHdf5(const nlohmann::json& params, const std::string& path, const ConfigContext& ctx) {
  for (const char* key : {"weights_file", "kernel", "scaling", "epsilon"})
    if (params.contains(key))
      failAtKey(ctx, key,
                std::string("is stored in the HDF5 model file ") + path +
                    " and belongs to its fitted weights; "
                    "remove the key (it applies to the published text format only)");
  try {
    return readRbfHdf5(path);
  } catch (const InputError& e) {
    failAtKey(ctx, "file", e.what());
  }
}

// Whether the HDF5 model file holds a 3-D model (three columns of centres).
bool isSpatial(const std::string& path, const ConfigContext& ctx) {
  try {
    return isSpatialRbfFile(path);
  } catch (const InputError& e) {
    failAtKey(ctx, "file", e.what());
  }
}

// A 3-D model file: its kernel and features are fixed by the file; only the cut-off may be given.
std::unique_ptr<ContactModel> makeSpatialRbfModel(const nlohmann::json& params, const std::string& path,
                                                  const ConfigContext& ctx) {
  for (const char* key : {"weights_file", "kernel", "scaling", "epsilon", "torque_centre"})
    if (params.contains(key))
      failAtKey(ctx, key,
                std::string("does not apply to the 3-D RBF model file ") + path +
                    " (its kernel and scaling are stored with its weights and its torque is about the foot point); "
                    "remove the key: a 3-D model takes only file, cutoff and cutoff_width");
  SpatialRbfModelFile model;
  try {
    model = readSpatialRbfHdf5(path);
  } catch (const InputError& e) {
    failAtKey(ctx, "file", e.what());
  }
  PlanarGeometry cut = planarGeometryOf(model.geometry);
  readGeometryOverrides(params, ctx, cut);
  model.geometry.cutoff = cut.cutoff;
  model.geometry.cutoff_width = cut.cutoff_width;
  auto function = std::make_shared<const SpatialRbfFunction>(std::move(model.parameters));
  nlohmann::json source = {{"file", path}, {"format", "hdf5"}};
  return std::make_unique<SpatialWrenchModel>(std::move(function), model.geometry, "rbf", std::move(source));
}

}  // namespace

std::unique_ptr<ContactModel> makeRbfModel(const nlohmann::json& params, const ConfigContext& ctx) {
  const std::string path = requireModelFile(params, kRbfParameters, "rbf",
                                            "missing: give the RBF model, an HDF5 file (.h5) or a folder with the "
                                            "published inputs.txt and weights.txt",
                                            ctx);
  const bool published = isPublishedFormat(params, path, ctx);
  if (!published && isSpatial(path, ctx)) return makeSpatialRbfModel(params, path, ctx);
  RbfParameters parameters;
  PlanarGeometry geometry;
  // The keys that identify the function, with the values used (PlanarWrenchModel::configuration).
  nlohmann::json source = {{"file", path}, {"format", published ? "published" : "hdf5"}};
  if (published) {
    parameters = readPublished(params, path, ctx, source);
    geometry = publishedRbfGeometry();
  } else {
    RbfModelFile model = readHdf5(params, path, ctx);
    parameters = std::move(model.parameters);
    geometry = model.geometry;
  }
  readGeometryOverrides(params, ctx, geometry);
  auto function = std::make_shared<const RbfFunction>(std::move(parameters));
  return std::make_unique<PlanarWrenchModel>(std::move(function), geometry, "rbf", std::move(source));
}

}  // namespace nmdp
