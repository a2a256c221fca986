// `nmdp fit` end to end: CSV → dataset → fit → a model file that the contact-model
// registry and `nmdp simulate` load with no other step; the report on stdout and in the file;
// `--model mlp` trains an MLP that loads as {"type": "mlp"}; bad data and bad configurations exit 1 with one line naming the
// file and the field.
//  * Without ../shared: a dataset sampled from the project's hand-made sand model
//    (data/granular/handmade_sand_rbf.h5) at its own centres, refitted with its kernel, scaling and
//    tail, must give back that model (the same interpolant), and the quadruped trots on it.
//  * With ../shared: the sand samples with data/granular/sand_rbf_fit.json through the CLI.
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "contact_models/rbf_function.hpp"
#include "contact_models/registry.hpp"
#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"
#include "terrain/plane.hpp"
#include "test_cli.hpp"
#include "fit_fixtures.hpp"
#include "planar_foot.hpp"
#include "test_support.hpp"
#include "training/force_dataset.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

// Bad input: exit code 1, one stderr line "nmdp fit: error: ..." with every string of `expect`.
void expectFitError(const std::vector<std::string>& args, const TempDir& dir, const std::vector<std::string>& expect) {
  std::vector<std::string> full = {"fit"};
  full.insert(full.end(), args.begin(), args.end());
  const CliResult r = runNmdp(full, dir);
  ASSERT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  expectAll(r.err, {"nmdp fit: error: "});
  expectAll(r.err, expect);
}

// The hand-made sand model's wrenches at its own centres, as a force dataset.
ForceDataset sampleHandmadeModel(const RbfModelFile& model) {
  const RbfFunction f(model.parameters);
  Eigen::MatrixXd W;
  f.evaluate(model.parameters.centres, W, nullptr, nullptr);
  const Eigen::Index P = W.rows(), K = W.cols() / 3;
  ForceDataset d;
  d.features.resize(P * K, 2);
  d.vertex.resize(P * K);
  d.wrench.resize(P * K, 3);
  for (Eigen::Index i = 0; i < P; ++i)
    for (Eigen::Index j = 0; j < K; ++j) {
      d.features.row(i * K + j) = model.parameters.centres.row(i);
      d.vertex[i * K + j] = static_cast<int>(j);
      d.wrench.row(i * K + j) = W.block(i, 3 * j, 1, 3);
    }
  d.feature_names = {"phi", "beta"};
  d.feature_units = {"m", "rad"};
  d.wrench_names = {"F_x", "F_z", "tau_y"};
  d.wrench_units = {"N", "N", "N m"};
  d.source = "data/granular/handmade_sand_rbf.h5 at its centres";
  d.torque_centre = model.geometry.torque_centre;
  return d;
}

std::unique_ptr<ContactModel> loadModel(const std::string& path) {
  return ContactModelRegistry::withBuiltins().build(json{{"type", "rbf"}, {"file", path}}, ConfigContext{"test", ""});
}

// The models' V at random foot states (depth −0.1..0.01 m, tilt ±0.9), largest difference relative
// to the reference's largest entry at each state.
double largestRelativeDifference(const ContactModel& a, const ContactModel& reference, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> depth(-0.1, 0.01), tilt(-0.9, 0.9);
  const PlaneTerrain ground;
  double worst = 0.0;
  for (int n = 0; n < 200; ++n) {
    const double t = tilt(rng);  // drawn before the depth, as the frames always were
    std::vector<ContactFrame> frames{planarFoot(0.02, depth(rng), t, 0.1)};
    std::vector<ContactWrenches> va(1), vr(1);
    va[0].resize(a.vertexCount());
    vr[0].resize(reference.vertexCount());
    a.evaluate(frames, ground, va, false);
    reference.evaluate(frames, ground, vr, false);
    const double scale = vr[0].V.cwiseAbs().maxCoeff();
    if (scale > 0.0)
      worst = std::max(worst, (va[0].V - vr[0].V).cwiseAbs().maxCoeff() / scale);
    else
      EXPECT_EQ(va[0].V.cwiseAbs().maxCoeff(), 0.0);
  }
  return worst;
}

TEST(FitCli, RefitOfTheHandmadeModelLoadsThroughTheRegistryAndSimulates) {
  TempDir dir;
  const std::string handmade = sourcePath("data/granular/handmade_sand_rbf.h5");
  const RbfModelFile original = readRbfHdf5(handmade);
  const std::string data = dir.file("handmade_samples.h5");
  writeForceDataset(data, sampleHandmadeModel(original));
  const std::string config = dir.write(
      "fit.json",
      json{{"rbf",
            {{"kernel", "thin_plate"},
             {"scaling", {original.parameters.spec.scaling[0], original.parameters.spec.scaling[1]}},
             {"polynomial_tail", true}}},
           {"geometry", {{"cutoff", original.geometry.cutoff}, {"cutoff_width", original.geometry.cutoff_width}}}}
          .dump());
  const std::string model = dir.file("refit.h5");
  const CliResult r = runNmdp({"fit", "--data", data, "--config", config, "--model", "rbf", "--out", model}, dir);
  ASSERT_TRUE(r.exited);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectAll(r.out,
            {"RBF fit of " + data, "leave-one-point-out", "40 measured", "\"polynomial_tail\":true", "wrote " + model});
  {
    const h5::File f = h5::File::openRead(model);
    expectAll(f.readStringAttribute("/fit", "report"), {"leave-one-point-out", "max(measured)"});
  }

  // The same interpolant as the original: the registry builds it and it agrees to rounding.
  const std::unique_ptr<ContactModel> refit = loadModel(model);
  const std::unique_ptr<ContactModel> reference = loadModel(handmade);
  ASSERT_EQ(refit->vertexCount(), reference->vertexCount());
  EXPECT_LT(largestRelativeDifference(*refit, *reference, 11), 1e-6);

  // `nmdp simulate` runs the sand trot on it with only the file changed.
  const std::string run = dir.file("run.h5");
  const CliResult sim = runNmdp({"simulate", sourcePath("models/scenes/quadruped_trot_sand.json"), "--set",
                                 "contacts.model.file=" + model, "--set", "duration=0.5", "--quiet", "--out", run},
                                dir);
  ASSERT_TRUE(sim.exited);
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(TrajectoryWriter::readStatus(run), "complete");
  const h5::File out = h5::File::openRead(run);
  const json scene = json::parse(out.readStringAttribute("/", "config"));
  EXPECT_EQ(scene["contacts"]["model"]["file"], model) << scene["contacts"]["model"].dump();
}

TEST(FitCli, SandSamplesThroughTheCliMatchThePublishedModel) {
  NMDP_REQUIRE_SHARED("granular/sand_samples");
  NMDP_REQUIRE_SHARED("granular/robosimian_sand_rbf");
  TempDir dir;
  const std::string data = dir.file("sand.h5");
  const CliResult imp = runNmdp({"fit", "--import-csv", sharedPath("granular/sand_samples"), "--out", data}, dir);
  ASSERT_EQ(imp.exit_code, 0) << imp.err;
  expectAll(imp.out, {"wrote " + data, "494 samples", "26 vertices"});
  const std::string model = dir.file("sand_rbf.h5");
  const std::string config = sourcePath("data/granular/sand_rbf_fit.json");
  const CliResult fit = runNmdp({"fit", "--data", data, "--config", config, "--model", "rbf", "--out", model}, dir);
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  expectAll(fit.out, {"103 (19 measured, 14 mirrored, 70 zero-wrench above the surface)", "26 vertices"});
  // The CSV folder directly gives the same model file contents.
  const std::string direct = dir.file("direct.h5");
  ASSERT_EQ(runNmdp({"fit", "--data", sharedPath("granular/sand_samples"), "--config", config, "--model", "rbf",
                     "--out", direct, "--quiet"},
                    dir)
                .exit_code,
            0);
  EXPECT_EQ(readRbfHdf5(direct).parameters.weights, readRbfHdf5(model).parameters.weights);

  const std::unique_ptr<ContactModel> fitted = loadModel(model);
  const std::unique_ptr<ContactModel> published = ContactModelRegistry::withBuiltins().build(
      json{{"type", "rbf"}, {"file", sharedPath("granular/robosimian_sand_rbf")}}, ConfigContext{"test", ""});
  EXPECT_LT(largestRelativeDifference(*fitted, *published, 5), 0.01);
}

TEST(FitCli, MlpFitLoadsThroughTheRegistryAndSimulates) {
  TempDir dir;
  const RbfModelFile original = readRbfHdf5(sourcePath("data/granular/handmade_sand_rbf.h5"));
  const std::string data = dir.file("handmade_samples.h5");
  writeForceDataset(data, sampleHandmadeModel(original));
  const std::string config = dir.write(
      "fit.json",
      json{{"mlp", {{"width", 16}, {"max_epochs", 400}, {"learning_rate", 1e-2}, {"validation_fraction", 0.1}}},
           {"geometry", {{"cutoff", original.geometry.cutoff}, {"cutoff_width", original.geometry.cutoff_width}}}}
          .dump());
  const std::string model = dir.file("mlp.h5");
  const CliResult r = runNmdp({"fit", "--data", data, "--config", config, "--model", "mlp", "--out", model}, dir);
  ASSERT_TRUE(r.exited);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectAll(r.out, {"MLP fit of " + data, "40 measured", "2-16-16-", "best epoch", "\"max_epochs\":400",
                    "\"activation\":\"tanh\"", "wrote " + model});
  EXPECT_TRUE(r.err.empty()) << "no progress line when stderr is not a terminal: " << r.err;
  {
    const h5::File f = h5::File::openRead(model);
    EXPECT_EQ(f.readStringAttribute("/", "nmdp_model"), "mlp");
    expectAll(f.readStringAttribute("/fit", "report"), {"MLP fit of", "relative to the largest wrench"});
  }
  // --quiet: only the last line.
  const std::string quiet = dir.file("quiet.h5");
  const CliResult q =
      runNmdp({"fit", "--data", data, "--config", config, "--model", "mlp", "--out", quiet, "--quiet"}, dir);
  ASSERT_EQ(q.exit_code, 0) << q.err;
  EXPECT_EQ(q.out, "wrote " + quiet + "\n");

  // The registry builds {"type": "mlp", "file": MODEL} and `nmdp simulate` runs the sand trot on it
  // with only the model changed.
  const std::unique_ptr<ContactModel> m = ContactModelRegistry::withBuiltins().build(
      json{{"type", "mlp"}, {"file", model}}, ConfigContext{"test", ""});
  EXPECT_EQ(m->vertexCount(), original.parameters.weights.cols() / 3);
  const std::string run = dir.file("run.h5");
  const CliResult sim = runNmdp({"simulate", sourcePath("models/scenes/quadruped_trot_sand.json"), "--set",
                                 "contacts.model.type=mlp", "--set", "contacts.model.file=" + model, "--set",
                                 "duration=0.5", "--quiet", "--out", run},
                                dir);
  ASSERT_TRUE(sim.exited);
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(TrajectoryWriter::readStatus(run), "complete");
}

TEST(FitCli, MlpBadSettingsExitOneNamingTheKey) {
  TempDir dir;
  const std::string data = dir.file("handmade_samples.h5");
  writeForceDataset(data, sampleHandmadeModel(readRbfHdf5(sourcePath("data/granular/handmade_sand_rbf.h5"))));
  const std::string out = dir.file("m.h5");
  expectFitError({"--data", data, "--model", "mlp", "--config", R"({"mlp": {"max_epochs": 0}})", "--out", out}, dir,
                 {"--config.mlp.max_epochs", "at least 1"});
  expectFitError({"--data", data, "--model", "mlp", "--config", R"({"mlp": {"validation_fraction": 0.999}})", "--out",
                  out},
                 dir, {data, "mlp.validation_fraction", "no point is left to train on"});
  expectFitError({"--data", data, "--model", "mlp", "--config", R"({"mlp": {"activation": "relu"}})", "--out", out},
                 dir, {"--config.mlp.activation", "ReLU", "tanh, softplus or silu"});
  expectFitError({"--data", data, "--model", "mlp", "--config", R"({"mlp": {"epochs": 10}})", "--out", out}, dir,
                 {"--config.mlp.epochs", "unknown key"});
  EXPECT_FALSE(fs::exists(out));
}

TEST(FitCli, BadInputExitsOneNamingTheFileAndField) {
  TempDir dir;
  const std::string out = dir.file("m.h5");
  // A NaN in the data.
  const std::string nan = dir.file("nan.h5");
  {
    h5::File f = h5::File::createAtomic(nan);
    f.writeStringAttribute("/", "nmdp_dataset", "force_samples");
    Eigen::MatrixXd features(2, 2), wrench = Eigen::MatrixXd::Ones(2, 3);
    features << -0.01, 0, -0.02, 0;
    wrench(1, 2) = std::nan("");
    f.writeMatrix("/features", features);
    f.writeStringAttribute("/features", "names", "phi, beta");
    f.writeStringAttribute("/features", "units", "m, rad");
    f.writeIntegerVector("/vertex", Eigen::VectorXi::Zero(2));
    f.writeMatrix("/wrench", wrench);
    f.writeStringAttribute("/wrench", "names", "F_x, F_z, tau_y");
    f.writeStringAttribute("/wrench", "units", "N, N, N m");
    f.commit();
  }
  expectFitError({"--data", nan, "--model", "rbf", "--out", out}, dir,
                 {nan, "'/wrench'", "non-finite", "row 1, column 2"});
  EXPECT_FALSE(fs::exists(out));

  // A CSV folder with a wrong column.
  dir.write("csv/features.csv", "depth,theta\n-0.01,0\n");
  dir.write("csv/wrench_samples.csv", "depth,theta,vel,fx,fz,wy\n-0.01,0,0,1,2,3\n");
  dir.write("csv/scalars.txt", "Nvel 1\nNtheta 1\n");
  expectFitError({"--data", dir.file("csv"), "--model", "rbf", "--out", out}, dir,
                 {dir.file("csv") + "/wrench_samples.csv:1", "depth, theta, vel_index, fx, fz, wy"});

  // An unknown configuration key, with the closest one.
  const std::string config = dir.write("fit.json", R"({"rbf": {"scalng": [5, 1]}})");
  expectFitError({"--data", nan, "--config", config, "--model", "rbf", "--out", out}, dir,
                 {config + ".rbf.scalng", "did you mean 'scaling'"});
  expectFitError({"--data", nan, "--config", R"({"augmentation": {"mirorr": true}})", "--model", "rbf", "--out", out},
                 dir, {"--config.augmentation.mirorr", "did you mean 'mirror'"});
  expectFitError({"--data", nan, "--model", "spline", "--out", out}, dir, {"--model", "rbf or mlp", "'spline'"});
  expectFitError({"--data", nan, "--model", "rbf"}, dir, {"--out is required"});
  expectFitError({"--import-csv", dir.file("nowhere"), "--out", out}, dir, {dir.file("nowhere"), "not a folder"});
}

}  // namespace
}  // namespace nmdp::test
