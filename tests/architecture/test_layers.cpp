// The layers go one way (README, "Layers"): a source file may include its own folder and the layers
// below it, never a layer above or beside it, so no folder cycle can form. libtorch and HDF5 stay
// behind the layers that own them.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "source_tree.hpp"

namespace fs = std::filesystem;

namespace {

using nmdp::test::readText;
using nmdp::test::sourceFiles;
using nmdp::test::sourceRoot;

// Rank of each layer folder; a folder may include only strictly lower ranks (and itself). io and
// multibody share a rank and so may not include each other; so do control and training, and the
// two edges, the CLI (src/app) and the Python module (python/src).
const std::map<std::string, int>& layerRanks() {
  static const std::map<std::string, int> ranks = {
      {"src/common", 0},          {"src/config", 10},  {"src/io", 20},     {"src/multibody", 20},
      {"src/terrain", 30},        {"contact_models", 40}, {"contact_models/mlp", 45}, {"src/control", 50},
      {"training", 50},           {"training/mlp", 55}, {"src/solver", 60}, {"src/sim", 70},
      {"src/app", 80},            {"python/src", 80}};
  return ranks;
}

// The layer folder of a path relative to the source root ("src/solver/step.cpp" → "src/solver"),
// or nullopt for a path in no layer.
std::optional<std::string> layerOf(const std::string& relative) {
  const std::string folder = fs::path(relative).parent_path().generic_string();
  if (layerRanks().count(folder)) return folder;
  return std::nullopt;
}

// Where `#include "x"` in `file` resolves: the same folder first, then the source root's src/,
// then the root (the include path of every target).
std::string resolveInclude(const fs::path& root, const std::string& file, const std::string& include) {
  const fs::path sibling = fs::path(file).parent_path() / include;
  if (fs::exists(root / sibling)) return sibling.lexically_normal().generic_string();
  if (fs::exists(root / "src" / include)) return (fs::path("src") / include).generic_string();
  return include;
}

struct Violation {
  std::string file, include, why;
};

// Checks one file's include lines; `text` is its content, `file` its path relative to root.
std::vector<Violation> checkIncludes(const fs::path& root, const std::string& file, const std::string& text) {
  std::vector<Violation> out;
  const auto own = layerOf(file);
  if (!own) return {{file, "", "is in no layer folder"}};
  static const std::regex quoted(R"(^\s*#\s*include\s*"([^"]+)\")");
  static const std::regex angled(R"(^\s*#\s*include\s*<([^>]+)>)");
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_search(line, m, angled)) {
      const std::string header = m[1];
      const bool torch = header.rfind("torch/", 0) == 0 || header.rfind("ATen/", 0) == 0;
      if (torch && *own != "contact_models/mlp" && *own != "training/mlp")
        out.push_back({file, header, "libtorch belongs to contact_models/mlp and training/mlp"});
      if (header == "hdf5.h" && *own != "src/io")
        out.push_back({file, header, "HDF5 belongs to src/io (hdf5_file.hpp, hdf5_handle.hpp)"});
      continue;
    }
    if (!std::regex_search(line, m, quoted)) continue;
    const std::string target = resolveInclude(root, file, m[1]);
    const auto layer = layerOf(target);
    if (!layer) {
      out.push_back({file, m[1], "includes a file outside the layers"});
      continue;
    }
    if (*layer == *own) continue;
    if (layerRanks().at(*layer) >= layerRanks().at(*own))
      out.push_back({file, m[1], *own + " may not include " + *layer + " (a layer above or beside it)"});
  }
  return out;
}

TEST(Layers, NoIncludeGoesUpALayer) {
  const fs::path root = sourceRoot();
  const std::vector<std::string> files = sourceFiles(root, {"src", "contact_models", "training", "python/src"}, {".cpp", ".hpp"});
  std::vector<Violation> all;
  for (const std::string& relative : files) {
    auto found = checkIncludes(root, relative, readText(root / relative));
    all.insert(all.end(), found.begin(), found.end());
  }
  EXPECT_GT(files.size(), 100u) << "the source tree was not found at " << root;
  for (const Violation& v : all) ADD_FAILURE() << v.file << ": #include \"" << v.include << "\": " << v.why;
}

// The checker itself: each rule catches what it is for.
TEST(Layers, CheckerFlagsAnIncludeUpALayer) {
  const fs::path root = sourceRoot();
  EXPECT_EQ(checkIncludes(root, "src/multibody/x.cpp", "#include \"solver/integrator.hpp\"\n").size(), 1u);
  EXPECT_EQ(checkIncludes(root, "src/io/x.cpp", "#include \"multibody/model.hpp\"\n").size(), 1u);  // beside
  EXPECT_EQ(checkIncludes(root, "src/control/x.cpp", "#include \"training/rft.hpp\"\n").size(), 1u);
  EXPECT_EQ(checkIncludes(root, "src/solver/x.cpp", "#include <torch/torch.h>\n").size(), 1u);
  EXPECT_EQ(checkIncludes(root, "src/sim/x.cpp", "#include \"bench/equal_accuracy.hpp\"\n").size(), 1u);
  EXPECT_EQ(checkIncludes(root, "src/unknown/x.cpp", "").size(), 1u);
  EXPECT_TRUE(checkIncludes(root, "src/solver/x.cpp",
                            "#include \"multibody/model.hpp\"\n#include \"control/gait.hpp\"\n#include <vector>\n")
                  .empty());
  EXPECT_TRUE(checkIncludes(root, "contact_models/mlp/x.cpp", "#include <torch/torch.h>\n").empty());
}

}  // namespace
