#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/json_argument.hpp"
#include "app/progress_bar.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "config/json_params.hpp"
#include "io/output_path.hpp"
#include "training/fit_config.hpp"
#include "training/fit_data.hpp"
#include "training/force_dataset.hpp"
#include "training/spatial_rbf_fit.hpp"
#include "training/mlp/contact_model_fit.hpp"

namespace nmdp::app {

const char* const kFitHelp =
    "usage: nmdp fit --data DATA --model rbf|mlp [--config FIT.json] --out MODEL.h5 [--quiet]\n"
    "       nmdp fit --import-csv FOLDER --out DATA.h5\n\n"
    "Fits a wrench-space contact model to force data (DESIGN.md §9; training/README.md) and writes a\n"
    "model file that 'nmdp simulate' loads as {\"type\": \"rbf\", \"file\": \"MODEL.h5\"} (--model rbf) or\n"
    "{\"type\": \"mlp\", \"file\": \"MODEL.h5\"} (--model mlp). After the fit a report is printed and stored\n"
    "in the model file (/fit): for the RBF the settings and the leave-one-point-out error per vertex, for\n"
    "the MLP the settings, epochs, losses and the validation error per vertex, both relative to the\n"
    "largest wrench at each point; then the model's largest wrench above the surface and warnings, each\n"
    "with a suggestion (a large leave-one-out error, a model that pushes above the surface, an MLP that\n"
    "stopped at its epoch limit or validated on too few points). MLP training shows a progress line on\n"
    "stderr when it is a terminal. 3-D data (features phi, beta, gamma; 6 wrench columns tau_x, tau_y,\n"
    "tau_z, F_x, F_y, F_z) gives the 3-D RBF (contact_models/spatial_rbf_function.hpp): rbf.scaling takes\n"
    "three numbers, and the planar keys augmentation.mirror and geometry.torque_centre are refused.\n\n"
    "  --data DATA         a force dataset (HDF5, training/force_dataset.hpp), a folder in the CSV layout\n"
    "                      of granular/sand_samples (features.csv, wrench_samples.csv, scalars.txt) or\n"
    "                      a .csv file in such a folder (e.g. its wrench_samples.csv)\n"
    "  --model rbf|mlp     the model to fit: an RBF interpolant or a libtorch MLP (training/mlp/mlp_fit.hpp)\n"
    "  --config FIT.json   augmentation, rbf (kernel, scaling, ridge, tail), mlp (layers, width,\n"
    "                      activation, epochs, learning rate, validation, seed, ...), geometry, as a\n"
    "                      file or an inline JSON object (every key: --schema; default: the\n"
    "                      published augmentation decided from the data: mirror when the data covers\n"
    "                      one side of beta = 0, zero-wrench points above the surface, the cut-off at\n"
    "                      the lowest zero point above the data's wrenches (the surface for the sand\n"
    "                      samples); thin-plate diag(5, 1); MLP 2-64-64-3K tanh, Adam, early stopping)\n"
    "  --out FILE.h5       the model file (or, with --import-csv, the dataset file) to write\n"
    "  --quiet             no report and no progress line\n"
    "  --import-csv FOLDER convert a sand_samples-layout folder to a force dataset and stop\n"
    "  --schema            print every FIT.json key with its type, default, range, unit and use, and stop\n";

namespace {
// The MLP training progress: one line redrawn in place with '\r' (at most 10 times a second),
// "epoch 1200/20000 [=====     ] train 1.2e-04 val 3.4e-04 best 1100 (3.1e-04) lr 1.0e-03 2.3 s".
// Disabled (nothing written) when the stream is not a terminal or with --quiet (ProgressBar's rule).
class TrainingLine {
 public:
  TrainingLine(std::FILE* stream, bool enabled) : stream_(stream), enabled_(enabled) {}
  ~TrainingLine() { finish(); }
  void update(const MlpEpochStatus& st) {
    if (!enabled_) return;
    last_ = st;
    if (drawn_ && st.seconds - last_draw_ < ProgressBar::kMinRedrawInterval && st.epoch < st.max_epochs) return;
    last_draw_ = st.seconds;
    draw();
  }
  void finish() {
    if (!enabled_ || !drawn_) return;
    draw();
    std::fputc('\n', stream_);
    std::fflush(stream_);
    drawn_ = false;
    enabled_ = false;
  }

 private:
  void draw() {
    constexpr int kWidth = 20;
    const int filled = last_.max_epochs > 0 ? kWidth * last_.epoch / last_.max_epochs : 0;
    char line[256];
    const std::string bar = std::string(filled, '=') + std::string(kWidth - filled, ' ');
    int n;
    if (std::isnan(last_.validation_loss))
      n = std::snprintf(line, sizeof line, "epoch %d/%d [%s] train %.2e best %d (%.2e) lr %.1e %.1f s", last_.epoch,
                        last_.max_epochs, bar.c_str(), last_.train_loss, last_.best_epoch, last_.best_loss,
                        last_.learning_rate, last_.seconds);
    else
      n = std::snprintf(line, sizeof line, "epoch %d/%d [%s] train %.2e val %.2e best %d (%.2e) lr %.1e %.1f s",
                        last_.epoch, last_.max_epochs, bar.c_str(), last_.train_loss, last_.validation_loss,
                        last_.best_epoch, last_.best_loss, last_.learning_rate, last_.seconds);
    std::fprintf(stream_, "\r%s%*s", line, std::max(0, length_ - n), "");
    std::fflush(stream_);
    length_ = n;
    drawn_ = true;
  }
  std::FILE* stream_;
  bool enabled_;
  bool drawn_ = false;
  double last_draw_ = 0.0;
  int length_ = 0;
  MlpEpochStatus last_;
};

}  // namespace

int runFit(const Args& args) {
  if (args.size() == 1 && args[0] == "--schema") return std::cout << schemaText(fitConfigSchema()), 0;
  std::string data, model, config, out, import_csv;
  bool quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto next = [&]() -> const std::string& { return optionValue(args, i, "fit"); };
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
  // The output replaces no input and no file nmdp did not write (io/output_path.hpp).
  std::vector<RunInput> inputs = filesInFolder(import_csv, "a file of --import-csv's folder");
  for (const RunInput& file : filesInFolder(data, "a file of --data's folder")) inputs.push_back(file);
  inputs.push_back({data, "the --data file"});
  if (config.find_first_not_of(" \t") != std::string::npos && config[config.find_first_not_of(" \t")] != '{')
    inputs.push_back({config, "the --config file"});
  checkOutputFile(out, inputs, "--out");

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
  if (model.empty()) throw InputError("--model is required: rbf or mlp (see nmdp fit --help)");
  requireFitModelName(model);

  FitConfig fit_config;
  if (!config.empty()) {
    ConfigContext ctx;
    const nlohmann::json json = readJsonArgument("--config", config, ctx);
    fit_config = parseFitConfig(json, ctx);
  }
  const ForceDataset dataset = loadFitData(data);
  if (model == "rbf" && isSpatialDataset(dataset)) {  // features (phi, beta, gamma): the 3-D RBF
    const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(dataset, fit_config, data);
    saveSpatialRbfFit(out, fit);
    if (!quiet) std::cout << formatSpatialRbfFitReport(fit.record);
    std::cout << "wrote " << out << "\n";
    return 0;
  }
  TrainingLine line(stderr, model == "mlp" && ProgressBar::shouldShow(stderr, quiet));
  const ContactModelFit fit =
      fitContactModel(dataset, model, fit_config, data, [&](const MlpEpochStatus& st) { line.update(st); });
  line.finish();
  saveContactModelFit(out, fit);
  if (!quiet) std::cout << formatContactModelFitReport(fit);
  std::cout << "wrote " << out << "\n";
  return 0;
}

}  // namespace nmdp::app
