// Contact models through the CLI (`nmdp wrench`) and the registry: every bad model file, heightfield
// or model configuration gives exactly one line on stderr that names the file and the offending
// field, dataset or key, exit code 1 and nothing on stdout; swapping the model (Coulomb, RBF, MLP)
// is a configuration change only; relative paths in a .json model file are resolved against its
// folder; and the published sand RBF reproduces 3x the measured sand wrenches at a measured centre.
// Every fixture is written to a unique temporary folder at test time.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/registry.hpp"
#include "contact_models/rbf_function.hpp"
#include "io/hdf5_file.hpp"
#include "common/input_error.hpp"
#include "terrain/plane.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "nmdp";
  for (const std::string& a : args) s += " " + shellQuote(a);
  return s;
}

// The contract for bad input: exit code exactly 1, nothing on stdout, one stderr line
// "nmdp wrench: error: ..." that contains every string of `expect` (the file, the key, ...).
void expectWrenchError(const std::vector<std::string>& args, const TempDir& dir, const std::vector<std::string>& expect) {
  SCOPED_TRACE(commandLine(args));
  const CliResult r = runNmdp(args, dir);
  ASSERT_TRUE(r.exited) << "nmdp was killed by a signal";
  EXPECT_EQ(r.exit_code, 1) << "stderr: " << r.err;  // not 0, not an internal error (3), not a crash
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout for bad input, got:\n" << r.out;
  ASSERT_NO_FATAL_FAILURE(expectOneLine(r.err, "stderr"));
  EXPECT_EQ(r.err.rfind("nmdp wrench: error: ", 0), 0u) << r.err;
  for (const std::string& s : expect) EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

// Runs a command that must succeed and returns its JSON output.
json runWrenchOk(const std::vector<std::string>& args, const TempDir& dir) {
  SCOPED_TRACE(commandLine(args));
  const CliResult r = runNmdp(args, dir);
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0) << "stderr: " << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  try {
    return json::parse(r.out);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "stdout is not JSON (" << e.what() << "):\n" << r.out;
    return json();
  }
}

// V (or one dV) of the JSON output as a 6×K matrix; checks the layout on the way.
Mat6X matrixOf(const json& columns, int K) {
  Mat6X M(6, K);
  M.setConstant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(columns.is_array()) << columns.dump();
  if (!columns.is_array()) return M;
  EXPECT_EQ(static_cast<int>(columns.size()), K) << "expected " << K << " columns: " << columns.dump();
  for (int j = 0; j < K && j < static_cast<int>(columns.size()); ++j) {
    EXPECT_TRUE(columns[j].is_array() && columns[j].size() == 6) << "column " << j << ": " << columns[j].dump();
    if (!columns[j].is_array() || columns[j].size() != 6) continue;
    for (int i = 0; i < 6; ++i) M(i, j) = columns[j][i].is_number() ? columns[j][i].get<double>() : M(i, j);
  }
  return M;
}

// ---- fixtures ----------------------------------------------------------------------------------

// A small synthetic RBF in the published format: N = 3 centres, K = 4 vertices.
constexpr int kRbfCentres = 3;
constexpr int kRbfVertices = 4;

std::string publishedInputs() { return "# depth theta\n-0.04 0.0\n-0.02 0.3\n0.0 -0.3\n"; }

// K·N lines "fx fz wy" (vertex v, centre i on line v*N + i); `lines` < K·N truncates.
std::string publishedWeights(int lines = kRbfCentres * kRbfVertices) {
  std::ostringstream s;
  s.precision(17);
  for (int v = 0; v < kRbfVertices; ++v)
    for (int i = 0; i < kRbfCentres; ++i) {
      if (v * kRbfCentres + i >= lines) return s.str();
      const double base = 1.0 + v + 0.5 * i;
      s << (i % 2 ? -1.0 : 1.0) * 20.0 * base << " " << 40.0 * base * (v % 2 ? 0.5 : 1.0) << " " << 0.3 * (v - i) << "\n";
    }
  return s.str();
}

// Writes the published RBF folder `name` (inputs.txt, weights.txt) and returns its path.
std::string writePublishedRbf(const TempDir& dir, const std::string& name, const std::string& weights = publishedWeights()) {
  dir.write(name + "/inputs.txt", publishedInputs());
  dir.write(name + "/weights.txt", weights);
  return dir.file(name);
}

// An HDF5 RBF file in the project's layout with the given weights (not validated).
std::string writeRbfHdf5(const TempDir& dir, const std::string& name, const Eigen::MatrixXd& weights) {
  const std::string path = dir.file(name);
  Eigen::MatrixXd centres(kRbfCentres, 2);
  centres << -0.04, 0.0, -0.02, 0.3, 0.0, -0.3;
  h5::File file = h5::File::createAtomic(path);
  file.writeStringAttribute("/", "nmdp_model", "rbf");
  file.createGroup("/rbf");
  file.writeDoubleAttribute("/rbf", "format_version", 1.0);
  file.writeDoubleAttribute("/rbf", "epsilon", 1.0);
  file.writeDoubleAttribute("/rbf", "torque_centre", 0.1);
  file.writeDoubleAttribute("/rbf", "cutoff", 0.1);
  file.writeDoubleAttribute("/rbf", "cutoff_width", 0.02);
  file.writeMatrix("/rbf/centres", centres);
  file.writeMatrix("/rbf/weights", weights);
  file.writeStrings("/rbf/kernel", {"thin_plate"});
  file.writeVector("/rbf/scaling", Eigen::Vector2d(5.0, 1.0));
  file.writeStrings("/rbf/feature_names", {"phi", "beta"});
  file.commit();
  return path;
}

// An HDF5 MLP file in the layout of mlp_function.hpp, written without validation (so that shapes
// that do not chain and NaNs can be stored); `vertices` is the attribute, whatever the layers say.
std::string writeMlpHdf5Raw(const TempDir& dir, const std::string& name, const MlpParameters& p, int vertices) {
  const std::string path = dir.file(name);
  h5::File file = h5::File::createAtomic(path);
  file.writeStringAttribute("/", "nmdp_model", "mlp");
  file.createGroup("/mlp");
  file.writeDoubleAttribute("/mlp", "format_version", 1.0);
  file.writeStringAttribute("/mlp", "activation", "tanh");
  file.writeDoubleAttribute("/mlp", "layers", static_cast<double>(p.layers.size()));
  file.writeDoubleAttribute("/mlp", "vertices", vertices);
  file.writeStringAttribute("/mlp", "wrench", "planar");
  file.writeDoubleAttribute("/mlp", "torque_centre", 0.1);
  file.writeDoubleAttribute("/mlp", "cutoff", 0.1);
  file.writeDoubleAttribute("/mlp", "cutoff_width", 0.02);
  file.writeStrings("/mlp/feature_names", {"phi", "beta"});
  file.writeVector("/mlp/input_mean", p.input_mean);
  file.writeVector("/mlp/input_std", p.input_std);
  file.writeVector("/mlp/output_scale", p.output_scale);
  file.writeVector("/mlp/output_offset", p.output_offset);
  for (size_t i = 0; i < p.layers.size(); ++i) {
    const std::string layer = "/mlp/layer_" + std::to_string(i);
    file.createGroup(layer);
    file.writeMatrix(layer + "/weight", p.layers[i].weight);
    file.writeVector(layer + "/bias", p.layers[i].bias);
  }
  file.commit();
  return path;
}

constexpr int kMlpVertices = 5;

// A valid small random MLP (2-8-15 tanh, K = 5) saved with saveMlpModel.
std::string writeRandomMlp(const TempDir& dir, const std::string& name, std::uint32_t seed = 7) {
  const std::string path = dir.file(name);
  PlanarGeometry g;
  g.torque_centre = 0.1;
  g.cutoff = 0.1;
  g.cutoff_width = 0.02;
  MlpParameters p = randomMlpParameters(1, 8, kMlpVertices, MlpActivation::Tanh, seed);
  p.output_scale.setConstant(50.0);  // forces of tens of N, like the sand data
  saveMlpModel(path, p, g);
  return path;
}

json rbfConfig(const std::string& file) { return {{"type", "rbf"}, {"file", file}}; }
json mlpConfig(const std::string& file) { return {{"type", "mlp"}, {"file", file}}; }

// ==== bad model files: wrong shapes ===============================================================

TEST(ContactCliBadModelFile, PublishedRbfWeightLinesNotAMultipleOfTheCentres) {
  TempDir dir;
  const std::string folder = writePublishedRbf(dir, "rbf_bad_count", publishedWeights(kRbfCentres * kRbfVertices - 2));
  const std::string weights = folder + "/weights.txt";
  expectWrenchError({"wrench", "--model", rbfConfig(folder).dump()}, dir,
                    {"--model.file", weights, "10 weight lines", "multiple", std::to_string(kRbfCentres) + " centres",
                     folder + "/inputs.txt"});
}

TEST(ContactCliBadModelFile, HdfRbfWeightsOfTheWrongWidth) {
  TempDir dir;
  // N x 3K needs a multiple of 3 columns; 4 is not.
  const std::string path = writeRbfHdf5(dir, "wide.h5", Eigen::MatrixXd::Ones(kRbfCentres, 4));
  expectWrenchError({"wrench", "--model", rbfConfig(path).dump()}, dir,
                    {"--model.file", path, "dataset '/rbf/weights'", "N x 3K", "3 x 4"});
  // and the wrong number of rows (2 for 3 centres)
  const std::string rows = writeRbfHdf5(dir, "rows.h5", Eigen::MatrixXd::Ones(2, 3 * kRbfVertices));
  expectWrenchError({"wrench", "--model", rbfConfig(rows).dump()}, dir,
                    {"--model.file", rows, "dataset '/rbf/weights'", "'/rbf/centres'", "2 x 12"});
}

TEST(ContactCliBadModelFile, HdfMlpLayerSizesDoNotChain) {
  TempDir dir;
  MlpParameters p = randomMlpParameters(2, 8, 4, MlpActivation::Tanh, 3);  // 2-8-8-12
  p.layers[1].weight = Eigen::MatrixXd::Constant(8, 6, 0.1);               // 8x6, the previous layer has 8 outputs
  const std::string path = writeMlpHdf5Raw(dir, "chain.h5", p, 4);
  expectWrenchError({"wrench", "--model", mlpConfig(path).dump()}, dir,
                    {"--model.file", path, "dataset '/mlp/layer_1/weight'", "8 x 6", "/mlp/layer_0", "8 outputs"});
  // The first layer must take the 2 features.
  MlpParameters q = randomMlpParameters(0, 1, 4, MlpActivation::Tanh, 4);  // 2-12
  q.layers[0].weight = Eigen::MatrixXd::Constant(12, 3, 0.1);
  const std::string first = writeMlpHdf5Raw(dir, "first.h5", q, 4);
  expectWrenchError({"wrench", "--model", mlpConfig(first).dump()}, dir,
                    {"--model.file", first, "dataset '/mlp/layer_0/weight'", "12 x 3", "(phi, beta)"});
}

// ==== bad model files: NaN weights ================================================================

TEST(ContactCliBadModelFile, PublishedRbfNanWeight) {
  TempDir dir;
  std::string weights = publishedWeights();
  // Line 5 (1-based) becomes "1 nan 2".
  std::istringstream in(weights);
  std::string line, edited;
  for (int n = 1; std::getline(in, line); ++n) edited += (n == 5 ? std::string("1 nan 2") : line) + "\n";
  const std::string folder = writePublishedRbf(dir, "rbf_nan", edited);
  expectWrenchError({"wrench", "--model", rbfConfig(folder).dump()}, dir,
                    {"--model.file", folder + "/weights.txt:5:", "non-finite", "'nan'"});
}

TEST(ContactCliBadModelFile, HdfMlpNanWeight) {
  TempDir dir;
  MlpParameters p = randomMlpParameters(1, 8, 4, MlpActivation::Tanh, 5);
  p.layers[1].weight(3, 2) = std::numeric_limits<double>::quiet_NaN();
  const std::string path = writeMlpHdf5Raw(dir, "nan.h5", p, 4);
  expectWrenchError({"wrench", "--model", mlpConfig(path).dump()}, dir,
                    {"--model.file", path, "dataset '/mlp/layer_1/weight'", "non-finite", "row 3, column 2"});
}

TEST(ContactCliBadModelFile, HdfRbfNanWeight) {
  TempDir dir;
  Eigen::MatrixXd w = Eigen::MatrixXd::Ones(kRbfCentres, 3 * kRbfVertices);
  w(1, 4) = std::numeric_limits<double>::quiet_NaN();
  const std::string path = writeRbfHdf5(dir, "nan_rbf.h5", w);
  expectWrenchError({"wrench", "--model", rbfConfig(path).dump()}, dir,
                    {"--model.file", path, "dataset '/rbf/weights'", "non-finite", "row 1, column 4"});
}

// ==== missing files and bad JSON ==================================================================

TEST(ContactCliMissing, ModelFiles) {
  TempDir dir;
  const std::string h5 = dir.file("no_such_model.h5");
  expectWrenchError({"wrench", "--model", rbfConfig(h5).dump()}, dir, {"--model.file", h5, "no such file"});
  expectWrenchError({"wrench", "--model", mlpConfig(h5).dump()}, dir, {"--model.file", h5, "no such file"});
  const std::string folder = dir.file("no_such_rbf_folder");
  expectWrenchError({"wrench", "--model", rbfConfig(folder).dump()}, dir, {"--model.file", folder, "no such file"});
  // A published folder whose weights.txt is missing.
  dir.write("half_rbf/inputs.txt", publishedInputs());
  expectWrenchError({"wrench", "--model", rbfConfig(dir.file("half_rbf")).dump()}, dir,
                    {"--model.file", dir.file("half_rbf") + "/weights.txt", "no such file"});
}

TEST(ContactCliMissing, ModelJsonFileDoesNotExist) {
  TempDir dir;
  const std::string path = dir.file("no_such_model.json");
  expectWrenchError({"wrench", "--model", path}, dir, {"--model", path, "cannot read"});
}

TEST(ContactCliMissing, ModelJsonFileWithInvalidJson) {
  TempDir dir;
  const std::string path = dir.write("broken.json", "{\"type\": \"coulomb\",\n \"mu\": }\n");
  expectWrenchError({"wrench", "--model", path}, dir, {path + ":2:", "invalid JSON"});
  // Inline JSON that does not parse names the option.
  expectWrenchError({"wrench", "--model", "{\"type\": coulomb}"}, dir, {"--model:1:", "invalid JSON"});
}

// ==== heightfields ================================================================================

TEST(ContactCliHeightfield, HoleAsEmptyCell) {
  TempDir dir;
  const std::string csv = dir.write("hole.csv", "0,0,0\n0,,0\n0,0,0\n");
  const json terrain = {{"type", "heightfield"}, {"file", csv}, {"spacing", 0.1}};
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--terrain", terrain.dump()}, dir,
                    {"--terrain.file", csv, "line 2, column 2", "empty cell", "holes"});
}

TEST(ContactCliHeightfield, HoleAsNan) {
  TempDir dir;
  const std::string csv = dir.write("nan.csv", "# heights\n0,0,0\n0,0,0\n0,nan,0\n");
  const json terrain = {{"type", "heightfield"}, {"file", csv}, {"spacing", 0.1}};
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--terrain", terrain.dump()}, dir,
                    {"--terrain.file", csv, "line 4, column 2", "'nan'", "holes"});
  // The same through a terrain .json file with a relative path: the message names both files.
  dir.write("terrains/nan.csv", "0,0\nnan,0\n");
  const std::string config = dir.write("terrains/terrain.json", R"({"type": "heightfield", "file": "nan.csv", "spacing": 0.1})");
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--terrain", config}, dir,
                    {config + ": terrain.file", dir.file("terrains/nan.csv"), "line 2, column 1", "'nan'"});
}

TEST(ContactCliHeightfield, MissingFile) {
  TempDir dir;
  const std::string csv = dir.file("no_such_heights.csv");
  const json terrain = {{"type", "heightfield"}, {"file", csv}, {"spacing", 0.1}};
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--terrain", terrain.dump()}, dir,
                    {"--terrain.file", csv, "no such file"});
}

// ==== configuration errors ========================================================================

// Each case runs inline ("--model.KEY") and from a .json model file ("<path>.KEY").
struct ConfigCase {
  std::string name;
  json model;
  std::string key;                  // the key the message must name
  std::vector<std::string> expect;  // further substrings
};

std::vector<ConfigCase> configCases() {
  return {
      {"unknown_type", {{"type", "colomb"}}, "type", {"'colomb'", "did you mean 'coulomb'", "coulomb, mlp, rbf"}},
      {"unknown_type_mlp", {{"type", "mpl"}, {"file", "x.h5"}}, "type", {"'mpl'", "did you mean 'mlp'", "coulomb, mlp, rbf"}},
      {"unknown_key", {{"type", "coulomb"}, {"muu", 0.5}}, "muu", {"unknown key", "did you mean 'mu'", "valid keys", "type, mu, K, k, p, zeta"}},
      {"unknown_key_rbf", {{"type", "rbf"}, {"fiel", "x"}}, "fiel", {"unknown key", "did you mean 'file'", "valid keys", "weights_file", "cutoff_width"}},
      {"out_of_range", {{"type", "coulomb"}, {"mu", -1}}, "mu", {"-1", "must be > 0"}},
      {"wrong_type", {{"type", "coulomb"}, {"mu", "high"}}, "mu", {"expected a number", "\"high\""}},
      {"missing_type", {{"mu", 0.5}}, "type", {"missing", "coulomb, mlp, rbf"}},
      {"rbf_without_file", {{"type", "rbf"}}, "file", {"missing"}},
      {"mlp_without_file", {{"type", "mlp"}}, "file", {"missing"}},
      {"integer_K", {{"type", "coulomb"}, {"K", 2.5}}, "K", {"integer"}},
  };
}

TEST(ContactCliConfig, InlineModelNamesTheKey) {
  for (const ConfigCase& c : configCases()) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    std::vector<std::string> expect = c.expect;
    expect.push_back("--model." + c.key + ":");
    expectWrenchError({"wrench", "--model", c.model.dump()}, dir, expect);
  }
}

TEST(ContactCliConfig, ModelFileNamesTheFileAndTheKey) {
  for (const ConfigCase& c : configCases()) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    const std::string path = dir.write("model.json", c.model.dump(2));
    std::vector<std::string> expect = c.expect;
    expect.push_back(path + ": model." + c.key + ":");
    expectWrenchError({"wrench", "--model", path}, dir, expect);
  }
}

TEST(ContactCliConfig, BadOptions) {
  TempDir dir;
  expectWrenchError({"wrench"}, dir, {"--model", "required"});
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--depth", "deep"}, dir, {"--depth", "'deep'"});
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--depth", "nan"}, dir, {"--depth", "finite"});
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--radius", "-1"}, dir, {"--radius"});
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--at", "1"}, dir, {"--at", "X,Y"});
  expectWrenchError({"wrench", "--model", "{\"type\":\"coulomb\"}", "--frobnicate"}, dir, {"--frobnicate"});
  expectWrenchError({"wrench", "--model"}, dir, {"--model", "needs a value"});
}

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

// ==== the registry (library) ======================================================================

TEST(ContactModelRegistryTest, BuiltinTypes) {
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  EXPECT_EQ(registry.types(), (std::vector<std::string>{"coulomb", "mlp", "rbf"}));
  EXPECT_EQ(registry.parameters("coulomb"), kCoulombParameters);
  EXPECT_THROW(registry.parameters("nope"), InputError);
}

TEST(ContactModelRegistryTest, MissingTypeNamesTheKey) {
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  const ConfigContext ctx{"scene.json: contacts.model", ""};
  for (const json& config : {json{{"mu", 0.5}}, json::object(), json{{"type", 3}}}) {
    SCOPED_TRACE(config.dump());
    try {
      registry.build(config, ctx);
      ADD_FAILURE() << "build accepted a configuration without a type";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("scene.json: contacts.model.type"), std::string::npos) << m;
      EXPECT_NE(m.find("missing"), std::string::npos) << m;
      EXPECT_NE(m.find("coulomb, mlp, rbf"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  EXPECT_THROW(registry.build(json::array(), ctx), InputError);
}

// A model that returns a constant force, to check that add() is used by build().
class ConstantModel : public ContactModel {
 public:
  ConstantModel(double force, int K) : force_(force), K_(K) {}
  int vertexCount() const override { return K_; }
  DerivativeSupport derivative() const override { return DerivativeSupport::None; }
  std::string describe() const override { return "constant " + std::to_string(force_); }
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain&, std::vector<ContactWrenches>& out,
                bool) const override {
    for (size_t i = 0; i < frames.size(); ++i) {
      out[i].resize(K_);
      out[i].V.row(5).setConstant(force_);
    }
  }
  double force() const { return force_; }

 private:
  double force_;
  int K_;
};

TEST(ContactModelRegistryTest, CustomFactoryIsUsed) {
  ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  int calls = 0;
  json seen;
  registry.add("constant", {"force", "K"}, [&](const json& params, const ConfigContext& ctx) -> std::unique_ptr<ContactModel> {
    ++calls;
    seen = params;
    return std::make_unique<ConstantModel>(readNumber(params, "force", 1.0, ctx), readInteger(params, "K", 3, ctx, 1, 100));
  });
  EXPECT_EQ(registry.types(), (std::vector<std::string>{"constant", "coulomb", "mlp", "rbf"}));
  EXPECT_EQ(registry.parameters("constant"), (std::vector<std::string>{"force", "K"}));

  const std::unique_ptr<ContactModel> model = registry.build({{"type", "constant"}, {"force", 12.5}, {"K", 4}}, {"test", ""});
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(seen.contains("type")) << "the factory gets the parameters without \"type\": " << seen.dump();
  const auto* constant = dynamic_cast<const ConstantModel*>(model.get());
  ASSERT_NE(constant, nullptr) << model->describe();
  EXPECT_EQ(constant->force(), 12.5);
  EXPECT_EQ(model->vertexCount(), 4);
  std::vector<ContactWrenches> out(1);
  model->evaluate({ContactFrame{}}, PlaneTerrain(), out, false);
  EXPECT_EQ(out[0].V(5, 3), 12.5);

  // An unknown key is rejected before the factory runs, naming the key and the closest valid one.
  try {
    registry.build({{"type", "constant"}, {"forse", 1.0}}, {"test", ""});
    ADD_FAILURE() << "unknown key accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.forse"), std::string::npos) << m;
    EXPECT_NE(m.find("'force'"), std::string::npos) << m;
  }
  EXPECT_EQ(calls, 1);

  // Adding a type again replaces its factory; the built-ins still work.
  registry.add("constant", {}, [](const json&, const ConfigContext&) -> std::unique_ptr<ContactModel> {
    return std::make_unique<ConstantModel>(-1.0, 3);
  });
  const std::unique_ptr<ContactModel> replaced = registry.build({{"type", "constant"}}, {"test", ""});
  EXPECT_EQ(dynamic_cast<const ConstantModel&>(*replaced).force(), -1.0);
  EXPECT_EQ(registry.build({{"type", "coulomb"}}, {"test", ""})->vertexCount(), 6);
  // The unknown-type message now lists the custom type too.
  try {
    registry.build({{"type", "constnt"}}, {"test", ""});
    ADD_FAILURE() << "unknown type accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("did you mean 'constant'"), std::string::npos) << m;
    EXPECT_NE(m.find("constant, coulomb, mlp, rbf"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace nmdp::test
