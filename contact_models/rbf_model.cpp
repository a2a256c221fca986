#include "contact_models/rbf_model.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "common/input_file.hpp"

namespace nmdp {

const std::vector<std::string> kRbfParameters = {"file",    "format",        "weights_file", "kernel",      "scaling",
                                                 "epsilon", "torque_centre", "cutoff",       "cutoff_width"};

namespace {

[[noreturn]] void fail(const ConfigContext& ctx, const std::string& key, const std::string& what) {
  throw InputError(ctx.where + (key.empty() ? "" : "." + key) + ": " + what);
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

std::unique_ptr<ContactModel> makeRbfModel(const nlohmann::json& params, const ConfigContext& ctx) {
  namespace fs = std::filesystem;
  std::vector<std::string> keys = kRbfParameters;
  keys.push_back("type");
  requireKnownKeys(params, keys, ctx);
  if (const std::string type = readString(params, "type", "rbf", ctx); type != "rbf")
    fail(ctx, "type", "expected \"rbf\", got \"" + type + "\"");

  if (!params.contains("file"))
    fail(ctx, "file",
         "missing: give the RBF model, an HDF5 file (.h5) or a folder with the published "
         "inputs.txt and weights.txt");
  const std::string file = readString(params, "file", "", ctx);
  if (file.empty()) fail(ctx, "file", "is empty");
  const std::string path = ctx.resolve(file);

  // Format: explicit, or from the path.
  const std::string format = readString(params, "format", "auto", ctx);
  bool published = false;
  std::error_code ec;
  if (format == "published") {
    published = true;
  } else if (format == "hdf5") {
    published = false;
  } else if (format == "auto") {
    const std::string ext = lowerExtension(path);
    if (fs::is_directory(path, ec) || ext == ".txt") {
      published = true;
    } else if (ext == ".h5" || ext == ".hdf5") {
      published = false;
    } else if (!pathExists(path)) {
      fail(ctx, "file", displayPath(path) + ": no such file or folder");
    } else {
      fail(ctx, "file",
           displayPath(path) +
               ": cannot tell the format from the name: give an HDF5 file (.h5), a folder with "
               "inputs.txt and weights.txt, or a centres file (.txt), or set \"format\" to "
               "\"published\" or \"hdf5\"");
    }
  } else {
    fail(ctx, "format", "expected \"auto\", \"published\" or \"hdf5\", got \"" + format + "\"");
  }

  RbfParameters parameters;
  PlanarGeometry geometry;
  // The keys that identify the function, with the values used (PlanarWrenchModel::configuration).
  nlohmann::json source = {{"file", path}, {"format", published ? "published" : "hdf5"}};
  if (published) {
    RbfKernelSpec spec;
    const std::string kernel = readString(params, "kernel", rbfKernelName(spec.kernel), ctx);
    if (!parseRbfKernel(kernel, &spec.kernel))
      fail(ctx, "kernel", "unknown kernel \"" + kernel + "\"; valid kernels: " + rbfKernelNames());
    const std::vector<double> scaling = readNumbers(params, "scaling", {spec.scaling[0], spec.scaling[1]}, ctx);
    if (scaling.size() != 2 || !(scaling[0] > 0.0) || !(scaling[1] > 0.0))
      fail(ctx, "scaling", "expected two positive numbers [s_phi, s_beta], got " + jsonForMessage(params.at("scaling")));
    spec.scaling = Eigen::Vector2d(scaling[0], scaling[1]);
    spec.epsilon = readNumber(params, "epsilon", spec.epsilon, ctx, 0.0);
    if (!(spec.epsilon > 0.0)) fail(ctx, "epsilon", "must be positive");

    std::string inputs, weights;
    if (fs::is_directory(path, ec)) {
      inputs = (fs::path(path) / "inputs.txt").string();
      weights = (fs::path(path) / "weights.txt").string();
    } else {
      inputs = path;
      weights = (fs::path(path).parent_path() / "weights.txt").string();
    }
    if (params.contains("weights_file")) weights = ctx.resolve(readString(params, "weights_file", "", ctx));
    try {
      parameters = readPublishedRbf(inputs, weights, spec);
    } catch (const InputError& e) {
      fail(ctx, "file", e.what());
    }
    geometry = publishedRbfGeometry();
    source["weights_file"] = weights;
    source["kernel"] = rbfKernelName(spec.kernel);
    source["scaling"] = {spec.scaling[0], spec.scaling[1]};
    source["epsilon"] = spec.epsilon;
  } else {
    for (const char* key : {"weights_file", "kernel", "scaling", "epsilon"})
      if (params.contains(key))
        fail(ctx, key,
             std::string("is stored in the HDF5 model file ") + path +
                 " and belongs to its fitted weights; "
                 "remove the key (it applies to the published text format only)");
    try {
      RbfModelFile model = readRbfHdf5(path);
      parameters = std::move(model.parameters);
      geometry = model.geometry;
    } catch (const InputError& e) {
      fail(ctx, "file", e.what());
    }
  }

  geometry.torque_centre = readNumber(params, "torque_centre", geometry.torque_centre, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff = readNumber(params, "cutoff", geometry.cutoff, ctx, -kMaxGeometryLength, kMaxGeometryLength);
  geometry.cutoff_width = readNumber(params, "cutoff_width", geometry.cutoff_width, ctx, 0.0, kMaxGeometryLength);
  if (!(geometry.cutoff_width > 0.0))
    fail(ctx, "cutoff_width", "must be positive (the wrenches blend to zero over this band below the cut-off)");

  auto function = std::make_shared<const RbfFunction>(std::move(parameters));
  return std::make_unique<PlanarWrenchModel>(std::move(function), geometry, "rbf", std::move(source));
}

}  // namespace nmdp
