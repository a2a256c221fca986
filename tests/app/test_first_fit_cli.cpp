// `nmdp fit` as a new user runs it first:
//  * acceptance: `nmdp fit --data ../shared/granular/sand_samples --model rbf|mlp --out m.h5` with no
//    configuration gives a model whose largest wrench 1 cm above the surface is below 1 % of its
//    largest wrench 3 cm below, at several angles (`nmdp wrench --depth 0.01` against `--depth
//    -0.03`); the report says what was decided from the data and warns as it should on that data;
//  * --data takes an HDF5 dataset, a folder in the CSV layout of granular/sand_samples, or any .csv
//    file of such a folder, and gives the same model from each; any other path is one message
//    naming it and what is accepted;
//  * the MLP's warnings (epoch limit, validation set too small) appear when they should, not otherwise.
// The acceptance skips with a message when ../shared is absent.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "contact_models/rbf_function.hpp"
#include "fit_fixtures.hpp"
#include "io/hdf5_file.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "training/force_dataset.hpp"
#include "training/sand_samples_csv.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

const char* kSandSamples = "granular/sand_samples";

CliResult fitOk(const std::vector<std::string>& args, const TempDir& dir) {
  std::vector<std::string> full = {"fit"};
  full.insert(full.end(), args.begin(), args.end());
  const CliResult r = runNmdp(full, dir);
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r;
}

// The largest entry of V (6×K: torques about the sphere centre and forces, world frame) that
// `nmdp wrench` prints for a foot at `depth` (m, negative below the surface) and leg angle `angle`.
double largestWrench(const std::string& model_json, double depth, double angle, const TempDir& dir) {
  const CliResult r = runNmdp({"wrench", "--model", model_json, "--depth", std::to_string(depth), "--angle",
                               std::to_string(angle)},
                              dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const json result = json::parse(r.out);
  double largest = 0.0;
  for (const json& column : result.at("V"))
    for (const json& x : column) largest = std::max(largest, std::abs(x.get<double>()));
  return largest;
}

// The sand model a first fit gives: its largest wrench 1 cm above the surface and 3 cm below, over
// angles on both sides of the data's (0..0.9 rad, mirrored), between them and at them.
void expectNothingAboveTheSurface(const std::string& type, const std::string& model, const TempDir& dir) {
  const std::string model_json = json{{"type", type}, {"file", model}}.dump();
  double above = 0.0, below = 0.0;
  for (double angle : {0.0, 0.15, 0.3, 0.45, -0.3, -0.75, 0.9}) {
    const double a = largestWrench(model_json, 0.01, angle, dir), b = largestWrench(model_json, -0.03, angle, dir);
    EXPECT_GT(b, 10.0) << "a wrench 3 cm deep at angle " << angle;
    EXPECT_LT(a, 0.01 * b) << "1 cm above the surface at angle " << angle;
    above = std::max(above, a);
    below = std::max(below, b);
  }
  std::cout << "[ " << type << " first fit ] largest wrench 1 cm above the surface " << above << ", 3 cm below "
            << below << "\n";
  EXPECT_LT(above, 0.01 * below);
}

TEST(FirstFit, SandRbfWithNoConfigurationPushesNothingAboveTheSurface) {
  NMDP_REQUIRE_SHARED(kSandSamples);
  TempDir dir;
  const std::string model = dir.file("m.h5");
  const CliResult r = fitOk({"--data", sharedPath(kSandSamples), "--model", "rbf", "--out", model}, dir);
  expectAll(r.out, {"103 (19 measured, 14 mirrored, 70 zero-wrench above the surface)",
                    "decided from the data: augmentation.mirror = true",
                    "decided from the data: augmentation.above_surface.heights = [0.01, 0.03, 0.05, 0.1, 0.2, 0.3, "
                    "0.4, 0.6, 0.8, 1]",
                    "decided from the data: geometry.cutoff = 0 ", "above the surface: zero",
                    // 15 samples 1–2 cm and 0.3 rad apart: a left-out sample is missed by about half.
                    "warning: the leave-one-point-out error is large"});
  EXPECT_EQ(r.out.find("pushes above the surface"), std::string::npos) << r.out;
  const h5::File f = h5::File::openRead(model);
  const json settings = json::parse(f.readStringAttribute("/fit", "settings"));
  EXPECT_EQ(settings["augmentation"]["scale"], 1.0) << "scale is about the robot: not a default to copy";
  EXPECT_EQ(settings["geometry"]["cutoff"], 0.0);
  EXPECT_EQ(settings["geometry"]["cutoff_width"], 0.01);
  expectAll(f.readStringAttribute("/fit", "warnings"), {"leave-one-point-out"});
  expectNothingAboveTheSurface("rbf", model, dir);
}

TEST(FirstFit, SandMlpWithNoConfigurationPushesNothingAboveTheSurface) {
  NMDP_REQUIRE_SHARED(kSandSamples);
  TempDir dir;
  const std::string model = dir.file("m.h5");
  const CliResult r = fitOk({"--data", sharedPath(kSandSamples), "--model", "mlp", "--out", model}, dir);
  // The default split holds out 8 points that carry a wrench, and early stopping ends the training.
  expectAll(r.out, {"decided from the data: geometry.cutoff = 0 ", "stopped early", "above the surface: zero",
                    "warnings: none"});
  expectNothingAboveTheSurface("mlp", model, dir);
}

// ==== --data ====================================================================================

TEST(FitData, TakesTheCsvFolderAndItsCsvFilesAsTheHdf5Dataset) {
  TempDir dir;
  const ForceDataset d = syntheticDataset(3, {-0.03, -0.02, -0.01, 0.0}, {0.0, 0.3, 0.6});
  const std::string h5 = dir.file("data.h5"), folder = dir.file("samples");
  writeForceDataset(h5, d);
  writeSandSamplesCsv(folder, d);
  const std::string reference = dir.file("from_h5.h5");
  fitOk({"--data", h5, "--model", "rbf", "--out", reference, "--quiet"}, dir);
  const Eigen::MatrixXd weights = readRbfHdf5(reference).parameters.weights;
  for (const std::string& data : {folder, folder + "/wrench_samples.csv", folder + "/features.csv",
                                  folder + "/./wrench_samples.csv"}) {
    const std::string model = dir.file("from_csv.h5");
    const CliResult r = fitOk({"--data", data, "--model", "rbf", "--out", model}, dir);
    expectAll(r.out, {"RBF fit of " + data, "wrote " + model});
    EXPECT_EQ(readRbfHdf5(model).parameters.weights, weights) << data;
    fs::remove(model);
  }
}

TEST(FitData, AnyOtherPathIsOneMessageNamingItAndWhatIsAccepted) {
  TempDir dir;
  const std::string out = dir.file("m.h5");
  const std::string empty_folder = dir.file("empty"), stray_csv = dir.write("stray/table.csv", "a,b\n1,2\n");
  fs::create_directory(empty_folder);
  const std::string text = dir.write("notes.txt", "not data\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir.file("nowhere.h5"), "no such file or folder"},
      {empty_folder, "a folder without features.csv, wrench_samples.csv and scalars.txt"},
      {stray_csv, "a .csv file whose folder lacks"},
      {text, "neither an HDF5 file nor a .csv file"},
      {"/dev/null", "neither a regular file nor a folder"},
  };
  for (const auto& [path, what] : cases) {
    const CliResult r = runNmdp({"fit", "--data", path, "--model", "rbf", "--out", out}, dir);
    ASSERT_TRUE(r.exited) << path;
    EXPECT_EQ(r.exit_code, 1) << path << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
    expectAll(r.err, {"nmdp fit: error: --data " + path + ": " + what, "expected a force dataset (HDF5",
                      "a folder in the CSV layout of granular/sand_samples", "a .csv file in such a folder"});
  }
  EXPECT_FALSE(fs::exists(out));
}

// ==== the MLP's warnings ========================================================================

TEST(FitWarningsMlp, EpochLimitAndValidationSizeWarnWhenTheyShould) {
  TempDir dir;
  // 6 × 6 points, 30 of them with a wrench.
  const std::string data = dir.file("data.h5");
  writeForceDataset(data, syntheticDataset(2, {-0.05, -0.04, -0.03, -0.02, -0.01, 0.0},
                                           {-0.75, -0.45, -0.15, 0.15, 0.45, 0.75}));
  const auto fit = [&](const json& mlp) {
    const std::string model = dir.file("m.h5");
    const CliResult r = fitOk({"--data", data, "--model", "mlp", "--config", json{{"mlp", mlp}}.dump(), "--out",
                               model},
                              dir);
    fs::remove(model);
    return r.out;
  };
  const json small = {{"width", 8}, {"seed", 3}};
  const std::string epoch_limit = "warning: MLP training stopped at its epoch limit";
  const std::string too_small = "warning: the validation set is too small to mean anything";

  // 40 epochs with a patience of 1000: stopped by the limit. 10 % held out: 3 points with a wrench.
  json limited = small;
  limited.update({{"max_epochs", 40}, {"patience", 1000}, {"validation_fraction", 0.1}});
  expectAll(fit(limited), {epoch_limit, too_small, "3 validation points carry a wrench", "suggestion: raise mlp."});

  // No early stopping asked for (patience 0) and no validation asked for: nothing to warn about.
  json chosen = small;
  chosen.update({{"max_epochs", 40}, {"patience", 0}, {"validation_fraction", 0}});
  const std::string quiet = fit(chosen);
  EXPECT_EQ(quiet.find(epoch_limit), std::string::npos) << quiet;
  EXPECT_EQ(quiet.find(too_small), std::string::npos) << quiet;
  expectAll(quiet, {"warnings: none"});

  // Large steps make the validation loss wander, so a short patience ends the training; 30 % held
  // out gives 9 points with a wrench.
  json stopped = small;
  stopped.update({{"max_epochs", 3000}, {"learning_rate", 5e-2}, {"final_learning_rate", 5e-2}, {"patience", 50},
                  {"validation_fraction", 0.3}});
  const std::string early = fit(stopped);
  expectAll(early, {"stopped early", "warnings: none"});
}

}  // namespace
}  // namespace nmdp::test
