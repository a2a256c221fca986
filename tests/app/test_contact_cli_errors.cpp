// Contact models through the CLI (`nmdp wrench`) on bad input: every bad model file (wrong shapes,
// NaN weights, missing), heightfield or model configuration gives exactly one line on stderr that
// names the file and the offending field, dataset or key, exit code 1 and nothing on stdout.
// Every fixture is written to a unique temporary folder at test time.
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

}  // namespace
}  // namespace nmdp::test
