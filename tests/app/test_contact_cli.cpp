// Contact models through the CLI (`nmdp wrench`): --derivatives for every built-in model; swapping
// the model (Coulomb, RBF, MLP) is a configuration change only and gives what the library gives;
// relative paths in a .json model file are resolved against its folder; and the published sand RBF
// reproduces 3x the measured sand wrenches at a measured centre. Bad input:
// test_contact_cli_errors.cpp. Every fixture is written to a unique temporary folder at test time.
#include <fstream>
#include <map>

#include "contact_models/registry.hpp"
#include "terrain/plane.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "contact_model_files.hpp"
#include "test_support.hpp"
#include "wrench_cli.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// ==== --derivatives ===============================================================================

TEST(ContactCliDerivatives, AcceptedForEveryBuiltinModel) {
  TempDir dir;
  const std::string rbf = writePublishedRbf(dir, "rbf");
  const std::string mlp = writeRandomMlp(dir, "mlp.h5");
  struct Case {
    std::string name;
    json model;
    int K;
  };
  for (const Case& c : {Case{"coulomb", {{"type", "coulomb"}}, 6}, Case{"rbf", rbfConfig(rbf), kRbfVertices},
                        Case{"mlp", mlpConfig(mlp), kMlpVertices},
                        Case{"mlp_tangents", {{"type", "mlp"}, {"file", mlp}, {"jacobian", "tangents"}}, kMlpVertices}}) {
    SCOPED_TRACE(c.name);
    const json out = runWrenchOk({"wrench", "--model", c.model.dump(), "--depth", "-0.01", "--angle", "0.2", "--derivatives"}, dir);
    ASSERT_TRUE(out.is_object());
    EXPECT_EQ(out.value("vertices", -1), c.K);
    ASSERT_TRUE(out.contains("dV")) << out.dump();
    ASSERT_TRUE(out["dV"].is_array());
    ASSERT_EQ(out["dV"].size(), 6u);
    double largest = 0.0;
    for (const json& d : out["dV"]) {
      const Mat6X M = matrixOf(d, c.K);
      EXPECT_TRUE(M.allFinite()) << d.dump();
      largest = std::max(largest, M.cwiseAbs().maxCoeff());
    }
    EXPECT_GT(largest, 0.0) << "dV is all zero";
    // Without --derivatives there is no dV.
    const json plain = runWrenchOk({"wrench", "--model", c.model.dump(), "--depth", "-0.01", "--angle", "0.2"}, dir);
    EXPECT_FALSE(plain.contains("dV"));
    // The values agree with and without derivatives (to rounding: the RBF's product differs).
    EXPECT_LE(relativeError(matrixOf(plain["V"], c.K), matrixOf(out["V"], c.K)), 1e-12);
  }
}

// ==== positive: swapping the model is a configuration change only ==============================

TEST(ContactCliModels, SwappingTheModelIsAConfigurationChange) {
  TempDir dir;
  const std::string rbf = writePublishedRbf(dir, "rbf");
  const std::string mlp = writeRandomMlp(dir, "mlp.h5");
  struct Case {
    std::string name;
    json model;
    int K;
    std::string type;
  };
  std::vector<Mat6X> Vs;
  for (const Case& c : {Case{"coulomb", {{"type", "coulomb"}}, 6, "coulomb"}, Case{"rbf", rbfConfig(rbf), kRbfVertices, "RBF"},
                        Case{"mlp", mlpConfig(mlp), kMlpVertices, "MLP"}}) {
    SCOPED_TRACE(c.name);
    const json out = runWrenchOk({"wrench", "--model", c.model.dump(), "--depth", "-0.01"}, dir);
    ASSERT_TRUE(out.is_object());
    EXPECT_EQ(out.value("vertices", -1), c.K);
    EXPECT_NE(out.value("model", std::string()).find(c.type), std::string::npos) << out["model"];
    EXPECT_FALSE(out.contains("dV"));
    for (const char* key : {"model", "derivative", "terrain", "foot", "vertices", "V"})
      EXPECT_TRUE(out.contains(key)) << key;
    const Mat6X V = matrixOf(out["V"], c.K);
    EXPECT_TRUE(V.allFinite());
    EXPECT_GT(V.bottomRows(3).cwiseAbs().maxCoeff(), 1e-3) << "no force at 1 cm depth";
    Vs.push_back(V);
  }
  ASSERT_EQ(Vs.size(), 3u);
  for (size_t a = 0; a < Vs.size(); ++a)
    for (size_t b = a + 1; b < Vs.size(); ++b) {
      const Eigen::Index k = std::min(Vs[a].cols(), Vs[b].cols());
      EXPECT_GT((Vs[a].leftCols(k) - Vs[b].leftCols(k)).cwiseAbs().maxCoeff(), 1e-6) << "models " << a << " and " << b;
    }
}

// The CLI gives what the library gives for the same foot (RBF and MLP files built in-process).
TEST(ContactCliModels, CliMatchesTheLibrary) {
  TempDir dir;
  const std::string rbf = writePublishedRbf(dir, "rbf");
  const std::string mlp = writeRandomMlp(dir, "mlp.h5");
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  const PlaneTerrain plane;
  ContactFrame frame;
  frame.radius = 0.02;
  frame.position = Vec3(0.0, 0.0, 0.02 - 0.01);
  frame.leg_axis = Vec3(std::sin(0.25), 0.0, std::cos(0.25));
  for (const json& config : {json{{"type", "coulomb"}, {"mu", 0.5}}, rbfConfig(rbf), mlpConfig(mlp)}) {
    SCOPED_TRACE(config.dump());
    const std::unique_ptr<ContactModel> model = registry.build(config, ConfigContext{"test", ""});
    std::vector<ContactWrenches> expected(1);
    expected[0].resize(model->vertexCount());
    model->evaluate({frame}, plane, expected, false);
    const json out = runWrenchOk({"wrench", "--model", config.dump(), "--depth", "-0.01", "--angle", "0.25"}, dir);
    ASSERT_TRUE(out.is_object());
    const Mat6X V = matrixOf(out["V"], model->vertexCount());
    EXPECT_LE(relativeError(V, expected[0].V), 1e-12) << "CLI:\n" << V << "\nlibrary:\n" << expected[0].V;
  }
}

// ==== positive: relative paths in a .json model file =============================================

TEST(ContactCliModels, RelativeFileIsResolvedAgainstTheJsonFolder) {
  TempDir dir;
  // The model folder and the JSON sit in a sub-folder; nmdp runs with another working directory.
  writePublishedRbf(dir, "configs/models/rbf");
  const std::string rbf_json = dir.write("configs/rbf.json", R"({"type": "rbf", "file": "models/rbf"})");
  const std::string mlp_abs = writeRandomMlp(dir, "configs/models/mlp.h5");
  const std::string mlp_json = dir.write("configs/mlp.json", R"({"type": "mlp", "file": "models/mlp.h5"})");
  ASSERT_FALSE(fs::exists(fs::current_path() / "models/rbf")) << "the test's working directory must not hold models/rbf";

  const json via_json = runWrenchOk({"wrench", "--model", rbf_json, "--depth", "-0.01"}, dir);
  const json via_abs = runWrenchOk({"wrench", "--model", rbfConfig(dir.file("configs/models/rbf")).dump(), "--depth", "-0.01"}, dir);
  ASSERT_TRUE(via_json.is_object() && via_abs.is_object());
  EXPECT_EQ(via_json.value("vertices", -1), kRbfVertices);
  EXPECT_EQ(via_json["V"], via_abs["V"]);

  const json mlp_via_json = runWrenchOk({"wrench", "--model", mlp_json, "--depth", "-0.01"}, dir);
  const json mlp_via_abs = runWrenchOk({"wrench", "--model", mlpConfig(mlp_abs).dump(), "--depth", "-0.01"}, dir);
  ASSERT_TRUE(mlp_via_json.is_object() && mlp_via_abs.is_object());
  EXPECT_EQ(mlp_via_json.value("vertices", -1), kMlpVertices);
  EXPECT_EQ(mlp_via_json["V"], mlp_via_abs["V"]);

  // "../" climbs from the JSON's folder, not from the working directory.
  const std::string up_json = dir.write("configs/deeper/rbf.json", R"({"type": "rbf", "file": "../models/rbf"})");
  const json via_up = runWrenchOk({"wrench", "--model", up_json, "--depth", "-0.01"}, dir);
  ASSERT_TRUE(via_up.is_object());
  EXPECT_EQ(via_up["V"], via_abs["V"]);

  // A relative path that does not exist next to the JSON is reported resolved against its folder.
  const std::string bad_json = dir.write("configs/bad.json", R"({"type": "mlp", "file": "models/missing.h5"})");
  expectWrenchError({"wrench", "--model", bad_json}, dir, {bad_json + ": model.file", dir.file("configs/models/missing.h5"), "no such file"});
}

// ==== positive: the published sand model reproduces 3x the sand samples ===========================

TEST(ContactCliModels, PublishedSandRbfGivesThreeTimesTheSamples) {
  NMDP_REQUIRE_SHARED("granular/robosimian_sand_rbf/weights.txt");
  NMDP_REQUIRE_SHARED("granular/sand_samples/wrench_samples.csv");
  const double depth = -0.03, theta = 0.3;

  // The 26 samples at (depth, theta), by vel_index, read in place.
  std::ifstream csv(sharedPath("granular/sand_samples/wrench_samples.csv"));
  ASSERT_TRUE(csv) << "cannot read wrench_samples.csv";
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line.rfind("depth,theta,vel_index,fx,fz,wy", 0), 0u) << line;
  std::map<int, Eigen::Vector3d> samples;
  while (std::getline(csv, line)) {
    if (line.empty()) continue;
    std::istringstream s(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 6u) << line;
    if (std::abs(v[0] - depth) < 1e-9 && std::abs(v[1] - theta) < 1e-9) samples[static_cast<int>(v[2])] = Eigen::Vector3d(v[3], v[4], v[5]);
  }
  ASSERT_EQ(samples.size(), 26u);

  TempDir dir;
  const json model = rbfConfig(sharedPath("granular/robosimian_sand_rbf"));
  const json out = runWrenchOk({"wrench", "--model", model.dump(), "--depth", "-0.03", "--angle", "0.3", "--radius", "0"}, dir);
  ASSERT_TRUE(out.is_object());
  ASSERT_EQ(out.value("vertices", -1), 26);
  // On flat ground with the lateral axis y, the sagittal frame is the world frame: x_s = y × n = x,
  // and the leg axis cos(β) n + sin(β) x leans toward +x for β > 0, i.e. β = +0.3.
  const json& axis = out["foot"]["leg_axis"];
  EXPECT_NEAR(axis[0].get<double>(), std::sin(theta), 1e-12);
  EXPECT_NEAR(axis[2].get<double>(), std::cos(theta), 1e-12);
  const Mat6X V = matrixOf(out["V"], 26);
  double largest = 0.0;
  for (const auto& [k, w] : samples) largest = std::max({largest, 3.0 * std::abs(w[0]), 3.0 * std::abs(w[1])});
  for (const auto& [k, w] : samples) {
    SCOPED_TRACE("vel_index " + std::to_string(k));
    EXPECT_NEAR(V(3, k), 3.0 * w[0], 1e-6 * largest) << "force x";
    EXPECT_NEAR(V(4, k), 0.0, 1e-9 * largest) << "force y (planar model)";
    EXPECT_NEAR(V(5, k), 3.0 * w[1], 1e-6 * largest) << "force z";
  }
}

}  // namespace
}  // namespace nmdp::test
