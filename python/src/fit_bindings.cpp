// nmdp.fit: `nmdp fit --data DATA --model rbf|mlp [--config FIT.json] [--out MODEL.h5]` from Python,
// with the data as a path or a dict of numpy arrays (training/force_dataset.hpp), the configuration as
// a dict, and the fitted model (a ContactModel) and the fit report (a dict) returned. The fit runs in
// the library's pipeline (training/mlp/contact_model_fit.hpp) with the GIL released; errors are
// ValueError with the CLI's message.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "contact_model_handle.hpp"
#include "contact_models/registry.hpp"
#include "io/output_path.hpp"
#include "py_json.hpp"
#include "training/fit_data.hpp"
#include "training/fit_warnings.hpp"
#include "training/mlp/contact_model_fit.hpp"

namespace nmdp::python {

namespace py = pybind11;

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

const std::vector<std::string> kDatasetKeys = {"features",     "vertex",        "wrench", "feature_names",
                                               "feature_units", "wrench_names", "wrench_units", "source",
                                               "torque_centre"};

std::string keyName(const std::string& key) { return "data['" + key + "']"; }

// data[key] as an array of `ndim` dimensions (1 or 2) and at most limits::kMaxForceSamples rows.
Doubles requireArray(const py::dict& data, const std::string& key, int ndim, const char* shape) {
  if (!data.contains(key)) throw InputError(keyName(key) + ": missing (" + shape + ")");
  const Doubles a = Doubles::ensure(data[key.c_str()]);
  if (!a) throw InputError(keyName(key) + ": expected an array of numbers (" + shape + ")");
  if (a.ndim() != ndim)
    throw InputError(keyName(key) + ": expected " + shape + ", got " + std::to_string(a.ndim()) + " dimensions");
  if (a.shape(0) < 1 || a.shape(0) > limits::kMaxForceSamples)
    throw InputError(keyName(key) + ": " + std::to_string(a.shape(0)) + " rows; expected 1 to " +
                     std::to_string(limits::kMaxForceSamples));
  return a;
}

Eigen::MatrixXd matrixOf(const Doubles& a) {
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = a.at(i, j);
  return m;
}

// data[key] as names (a list of str or "a, b, c"), or `fallback` when absent.
std::vector<std::string> namesOf(const py::dict& data, const std::string& key, std::vector<std::string> fallback) {
  if (!data.contains(key)) return fallback;
  const py::object v = data[key.c_str()];
  if (py::isinstance<py::str>(v)) return splitNames(v.cast<std::string>());
  try {
    return v.cast<std::vector<std::string>>();
  } catch (const py::cast_error&) {
    throw InputError(keyName(key) + ": expected a list of strings or \"a, b, c\"");
  }
}

// The defaults of the names and units: those of the planar datasets (importSandSamplesCsv) and of
// the 6-D wrench; other sizes must be named.
std::vector<std::string> defaultNames(py::ssize_t columns, bool features, bool units) {
  if (features && columns == 2) return units ? std::vector<std::string>{"m", "rad"} : std::vector<std::string>{"phi", "beta"};
  if (!features && columns == 3)
    return units ? std::vector<std::string>{"N", "N", "N m"} : std::vector<std::string>{"F_x", "F_z", "tau_y"};
  if (!features && columns == 6)
    return units ? std::vector<std::string>{"N m", "N m", "N m", "N", "N", "N"}
                 : std::vector<std::string>{"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};
  return {};
}

// A force dataset from a dict of arrays; shapes are checked here (naming the key), values by
// validateForceDataset (naming the dataset '/features', '/vertex' or '/wrench' of "data").
ForceDataset datasetFromDict(const py::dict& data) {
  for (const auto& item : data) {
    const std::string key = py::str(item.first).cast<std::string>();
    if (std::find(kDatasetKeys.begin(), kDatasetKeys.end(), key) == kDatasetKeys.end())
      throw InputError("data: unknown key " + py::repr(item.first).cast<std::string>().substr(0, 40) +
                       "; expected features, vertex, wrench and optionally feature_names, feature_units, "
                       "wrench_names, wrench_units, source, torque_centre");
  }
  const Doubles features = requireArray(data, "features", 2, "N x F: phi, beta per sample");
  const Doubles vertex = requireArray(data, "vertex", 1, "N vertex indices");
  const Doubles wrench = requireArray(data, "wrench", 2, "N x 3: F_x, F_z, tau_y per sample");
  if (vertex.shape(0) != features.shape(0) || wrench.shape(0) != features.shape(0))
    throw InputError("data: features, vertex and wrench have " + std::to_string(features.shape(0)) + ", " +
                     std::to_string(vertex.shape(0)) + " and " + std::to_string(wrench.shape(0)) +
                     " rows; expected one row per sample in each");
  ForceDataset d;
  d.features = matrixOf(features);
  d.wrench = matrixOf(wrench);
  d.vertex.resize(vertex.shape(0));
  for (py::ssize_t i = 0; i < vertex.shape(0); ++i) {
    const double v = vertex.at(i);
    if (!(v >= 0 && v < limits::kMaxVertices && v == std::floor(v)))
      throw InputError(keyName("vertex") + "[" + std::to_string(i) + "]: " + std::to_string(v) +
                       " is not a vertex index (an integer from 0 to " + std::to_string(limits::kMaxVertices - 1) + ")");
    d.vertex[i] = static_cast<int>(v);
  }
  d.feature_names = namesOf(data, "feature_names", defaultNames(features.shape(1), true, false));
  d.feature_units = namesOf(data, "feature_units", defaultNames(features.shape(1), true, true));
  d.wrench_names = namesOf(data, "wrench_names", defaultNames(wrench.shape(1), false, false));
  d.wrench_units = namesOf(data, "wrench_units", defaultNames(wrench.shape(1), false, true));
  d.source = data.contains("source") ? py::str(data["source"]).cast<std::string>() : "a Python dict";
  if (data.contains("torque_centre") && !data["torque_centre"].is_none()) {
    const double L = py::float_(data["torque_centre"]).cast<double>();
    if (!std::isfinite(L)) throw InputError(keyName("torque_centre") + ": not a finite number");
    d.torque_centre = L;
  }
  validateForceDataset(d, "data");
  return d;
}

py::array_t<double> arrayOf(const Eigen::MatrixXd& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) a.mutable_at(i, j) = m(i, j);
  return a;
}

// What both reports hold: the data, settings, decided settings, warnings, timing, points, geometry.
template <typename Record>
py::dict commonReport(const std::string& model, const Record& r, const PlanarGeometry& g, const std::string& text) {
  py::dict d;
  d["model"] = model;
  d["data"] = r.data;
  d["text"] = text;
  d["settings"] = toPython(nlohmann::json::parse(r.settings.dump()));
  d["from_data"] = py::cast(r.from_data);
  py::list warnings;
  for (const FitWarning& w : r.warnings)
    warnings.append(py::dict(py::arg("what") = w.what, py::arg("suggestion") = w.suggestion));
  d["warnings"] = warnings;
  d["seconds"] = r.seconds;
  d["points"] = arrayOf(r.points.features);
  py::array_t<std::int64_t> origin(r.points.pointCount());
  for (int i = 0; i < r.points.pointCount(); ++i) origin.mutable_at(i) = static_cast<std::int64_t>(r.points.origin[i]);
  d["origin"] = origin;
  d["values"] = arrayOf(r.points.values);
  d["above_surface_share"] = r.above_surface.share();
  d["geometry"] = py::dict(py::arg("torque_centre") = g.torque_centre, py::arg("cutoff") = g.cutoff,
                           py::arg("cutoff_width") = g.cutoff_width);
  return d;
}

py::dict reportOf(const ContactModelFit& fit) {
  const std::string text = formatContactModelFitReport(fit);
  if (fit.rbf) {
    const RbfFitRecord& r = fit.rbf->record;
    py::dict d = commonReport("rbf", r, fit.rbf->geometry, text);
    d["loo_error"] = arrayOf(r.fit.loo_error);
    d["loo_relative"] = arrayOf(r.fit.loo_relative);
    d["loo_rms"] = measuredRms(r.fit.loo_relative, r.points);
    d["rcond"] = r.fit.rcond;
    return d;
  }
  const MlpFitRecord& r = fit.mlp->record;
  py::dict d = commonReport("mlp", r, fit.mlp->geometry, text);
  py::array_t<bool> validation(static_cast<py::ssize_t>(r.fit.validation.size()));
  for (size_t i = 0; i < r.fit.validation.size(); ++i) validation.mutable_at(i) = r.fit.validation[i];
  d["validation"] = validation;
  d["error"] = arrayOf(r.fit.error);
  d["relative_error"] = arrayOf(r.fit.relative);
  d["history"] = arrayOf(r.fit.history);
  d["epochs"] = r.fit.epochs;
  d["best_epoch"] = r.fit.best_epoch;
  d["stopped_early"] = r.fit.stopped_early;
  d["train_loss"] = r.fit.train_loss;
  d["validation_loss"] = r.fit.validation_loss;
  d["teacher_samples"] = r.fit.teacher_samples;
  return d;
}

// A str or os.PathLike as a path; `what` names the argument and what else it accepts.
std::string pathOf(const py::handle& p, const std::string& what) {
  if (!py::isinstance<py::str>(p) && !py::hasattr(p, "__fspath__"))
    throw InputError(what + ": a " + py::str(py::type::handle_of(p).attr("__name__")).cast<std::string>() +
                     " is not accepted");
  return py::str(py::module_::import("os").attr("fspath")(p)).cast<std::string>();
}

// FIT.json's object as a dict (read as an inline --config object) or the path of a .json file (as
// --config FILE: relative paths inside resolve against its folder).
FitConfig fitConfigOf(const py::object& config) {
  if (config.is_none()) return FitConfig();
  if (py::isinstance<py::dict>(config)) return parseFitConfig(toJson(config, "--config"), {"--config", ""});
  const std::string path = pathOf(config, "config: expected a dict (FIT.json's object) or the path of a .json file;");
  const ConfigContext ctx{displayPath(path), std::filesystem::path(path).parent_path().string()};
  return parseFitConfig(loadJsonFile(path, "JSON file of --config"), ctx);
}

py::tuple fit(const py::object& data, const std::string& model, const py::object& config, const py::object& out) {
  const bool from_path = !py::isinstance<py::dict>(data);
  const std::string data_path =
      from_path ? pathOf(data, "data: expected a path (a dataset file or a CSV folder) or a dict of arrays;") : "";
  const std::string out_path = out.is_none() ? "" : pathOf(out, "out: expected a path;");
  if (!out_path.empty()) {  // as nmdp fit: the output replaces no input and no file nmdp did not write
    std::vector<RunInput> inputs = filesInFolder(data_path, "a file of --data's folder");
    if (from_path) inputs.push_back({data_path, "the --data file"});
    if (!config.is_none() && !py::isinstance<py::dict>(config))
      inputs.push_back({pathOf(config, "config: expected a dict or a path;"), "the --config file"});
    checkOutputFile(out_path, inputs, "--out");
  }
  requireFitModelName(model);
  const FitConfig fit_config = fitConfigOf(config);
  ForceDataset dataset = from_path ? ForceDataset() : datasetFromDict(data.cast<py::dict>());
  const std::string data_name = from_path ? data_path : "data";
  ContactModelFit result;
  std::unique_ptr<ContactModel> fitted;
  {
    py::gil_scoped_release release;
    if (from_path) dataset = loadFitData(data_path);
    result = fitContactModel(dataset, model, fit_config, data_name);
    if (out_path.empty()) {
      fitted = fittedContactModel(result);
    } else {
      saveContactModelFit(out_path, result);
      fitted = ContactModelRegistry::withBuiltins().build({{"type", model}, {"file", out_path}}, ConfigContext{"--out", ""});
    }
  }
  return py::make_tuple(std::make_shared<ContactModelHandle>(std::move(fitted)), reportOf(result));
}

}  // namespace

void bindFit(py::module_& m) {
  m.def("fit", &fit, py::arg("data"), py::arg("model") = "rbf", py::arg("config") = py::none(),
        py::arg("out") = py::none(), R"doc(
Fits a contact model to force data as `nmdp fit --data DATA --model MODEL --config CONFIG --out OUT`
does, and returns (model, report).

data: a path nmdp fit --data accepts (a force dataset .h5, a sand_samples-layout CSV folder or a
.csv file in one), or a dict of arrays: "features" (N x 2: phi m, beta rad), "vertex" (N integers
>= 0), "wrench" (N x 3: F_x, F_z N, tau_y N m), optionally "torque_centre" (m), "source" (text) and
"feature_names", "feature_units", "wrench_names", "wrench_units" (defaults: the planar names).
model: "rbf" or "mlp". config: FIT.json's object as a dict, or the path of a FIT.json file (None:
the defaults, decided from the data as nmdp fit does).
out: the model file to write (as --out); the returned model is then loaded from it, so that its
configuration() names the file; without out it is built in memory (configuration() is None).
report: a dict with "text" (what nmdp fit prints), "settings", "from_data", "warnings", "points",
"origin", "values", "geometry", and for the RBF "loo_relative" (P x K: the leave-one-point-out
error per point and vertex relative to the largest wrench at the point), "loo_error", "loo_rms",
"rcond"; for the MLP "validation" (P booleans), "relative_error" (P x K), "error", "history",
"epochs", "best_epoch", "train_loss", "validation_loss". The GIL is released during the fit.)doc");
}

}  // namespace nmdp::python
