#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "io/input_error.hpp"
#include "io/json_params.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"

namespace nmdp::app {

const char* const kFitHelp =
    "usage: nmdp fit --data DATA --model rbf [--config FIT.json] --out MODEL.h5 [--quiet]\n"
    "       nmdp fit --import-csv FOLDER --out DATA.h5\n\n"
    "Fits a wrench-space contact model to force data (DESIGN.md §9; training/README.md) and writes a\n"
    "model file that 'nmdp simulate' loads as {\"type\": \"rbf\", \"file\": \"MODEL.h5\"}. After the fit a\n"
    "report (settings, leave-one-point-out error per vertex relative to the largest wrench at each\n"
    "point) is printed and stored in the model file (/fit).\n\n"
    "  --data DATA         a force dataset (HDF5, training/force_dataset.hpp) or a folder in the CSV\n"
    "                      layout of granular/sand_samples (features.csv, wrench_samples.csv, scalars.txt)\n"
    "  --model rbf|mlp     the model to fit; mlp is not yet available\n"
    "  --config FIT.json   augmentation, kernel, scaling, ridge, polynomial tail, geometry, as a file\n"
    "                      or an inline JSON object\n"
    "                      (training/fit_config.hpp; default: no augmentation, thin-plate, diag(5, 1))\n"
    "  --out FILE.h5       the model file (or, with --import-csv, the dataset file) to write\n"
    "  --quiet             do not print the report\n"
    "  --import-csv FOLDER convert a sand_samples-layout folder to a force dataset and stop\n";

namespace {
// FIT.json, or the JSON object itself given inline ('{...}', as nmdp wrench --model takes it).
nlohmann::json readConfig(const std::string& path, ConfigContext& ctx) {
  const size_t first = path.find_first_not_of(" \t");
  if (first != std::string::npos && path[first] == '{') {
    ctx.where = "--config";
    try {
      return nlohmann::json::parse(path);
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(std::string("--config: not valid JSON: ") + e.what());
    }
  }
  std::ifstream in(path);
  if (!in) throw InputError("--config " + path + ": cannot open the file");
  ctx.where = path;
  ctx.base_dir = std::filesystem::path(path).parent_path().string();
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
}

// A dataset file, or a sand_samples-layout folder imported on the fly.
ForceDataset loadData(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return importSandSamplesCsv(path);
  return readForceDataset(path);
}
}  // namespace

int runFit(const Args& args) {
  std::string data, model, config, out, import_csv;
  bool quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto next = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw InputError(a + " needs a value (see nmdp fit --help)");
      return args[++i];
    };
    if (a == "--data")
      data = next();
    else if (a == "--model")
      model = next();
    else if (a == "--config")
      config = next();
    else if (a == "--out")
      out = next();
    else if (a == "--import-csv")
      import_csv = next();
    else if (a == "--quiet")
      quiet = true;
    else
      throw InputError("unknown argument '" + a + "' (see nmdp fit --help)");
  }
  if (out.empty()) throw InputError("--out is required (see nmdp fit --help)");

  if (!import_csv.empty()) {
    if (!data.empty() || !model.empty() || !config.empty())
      throw InputError("--import-csv converts data only: it takes --out and no --data, --model or --config");
    const ForceDataset d = importSandSamplesCsv(import_csv);
    writeForceDataset(out, d);
    std::cout << "wrote " << out << ": " << d.features.rows() << " samples, " << d.vertex.maxCoeff() + 1
              << " vertices, features " << joinNames(d.feature_names) << "\n";
    return 0;
  }

  if (data.empty()) throw InputError("--data is required (see nmdp fit --help)");
  if (model.empty()) throw InputError("--model is required: rbf (see nmdp fit --help)");
  if (model == "mlp")
    throw InputError(
        "--model mlp: MLP training is not yet available in this version; fit an RBF model with --model rbf");
  if (model != "rbf") throw InputError("--model: expected rbf or mlp, got '" + model + "'");

  FitConfig fit_config;
  if (!config.empty()) {
    ConfigContext ctx;
    const nlohmann::json json = readConfig(config, ctx);
    fit_config = parseFitConfig(json, ctx);
  }
  const ForceDataset dataset = loadData(data);
  const RbfFitOutcome fit = fitRbfToDataset(dataset, fit_config, data);
  saveRbfFit(out, fit.record, fit.geometry);
  if (!quiet) std::cout << formatRbfFitReport(fit.record);
  std::cout << "wrote " << out << "\n";
  return 0;
}

}  // namespace nmdp::app
