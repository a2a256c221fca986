// fuzz_make_seeds OUT_DIR: the seed corpus of every fuzz target, from the files the project owns
// (models/, data/, tests/data/) and, when it is there, ../shared (real robots, the published sand
// model and samples), into OUT_DIR/<target>/, plus a libFuzzer dictionary OUT_DIR/<target>.dict of
// the JSON keys and string values the seeds use. Nothing is copied into the repository: the corpora
// are rebuilt from the files in place before every campaign and every replay.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "contact_models/mlp/mlp_function.hpp"
#include "fuzz/h5_text.hpp"
#include "training/force_dataset.hpp"

namespace fs = std::filesystem;

namespace {

std::string source(const std::string& relative) { return std::string(NMDP_SOURCE_DIR) + "/" + relative; }

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Files under `dir` (recursively) whose name ends in `suffix` and that are at most `max_bytes` long.
std::vector<fs::path> filesIn(const fs::path& dir, const std::string& suffix, std::uintmax_t max_bytes = 1 << 20) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0 && e.file_size() <= max_bytes)
      out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A libFuzzer dictionary line: "word" with \\, \" and \xHH escapes.
std::string dictionaryEntry(const std::string& word) {
  std::string out = "\"";
  for (const char c : word) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", u);
      out += hex;
    }
  }
  return out + "\"";
}

class Corpus {
 public:
  Corpus(const fs::path& root, const std::string& target) : dir_(root / target), dict_(root / (target + ".dict")) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Corpus() {
    std::ofstream out(dict_);
    for (const std::string& w : words_) out << dictionaryEntry(w) << "\n";
  }
  void add(const std::string& content, bool json_words = false) {
    std::ofstream(dir_ / ("seed_" + std::to_string(count_++)), std::ios::binary) << content;
    if (json_words) collectWords(content);
  }
  size_t size() const { return count_; }
  // Words libFuzzer inserts whole: the names a format is made of.
  void words(const std::vector<std::string>& list) {
    for (const std::string& w : list) words_.insert(w);
  }
  // The element and attribute names of an XML text ("<joint", "type=").
  void xmlWords(const std::string& text) {
    for (size_t i = 0; (i = text.find('<', i)) != std::string::npos; ++i) {
      size_t end = i + 1;
      while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_')) ++end;
      if (end > i + 1 && end - i < 30) words_.insert(text.substr(i, end - i));
    }
    for (size_t i = 0; (i = text.find("=\"", i)) != std::string::npos; ++i) {
      size_t start = i;
      while (start > 0 && (std::isalnum(static_cast<unsigned char>(text[start - 1])) || text[start - 1] == '_')) --start;
      if (start < i && i - start < 30) words_.insert(text.substr(start, i - start + 2));
    }
  }

 private:
  void collectWords(const std::string& text) {
    try {
      collect(nlohmann::json::parse(text.substr(0, text.find("\n--set "))));
    } catch (const nlohmann::json::exception&) {
    }
  }
  void collect(const nlohmann::json& v) {
    if (v.is_object())
      for (auto it = v.begin(); it != v.end(); ++it) {
        words_.insert("\"" + it.key() + "\"");
        collect(it.value());
      }
    else if (v.is_array())
      for (const auto& x : v) collect(x);
    else if (v.is_string() && v.get<std::string>().size() < 40)
      words_.insert("\"" + v.get<std::string>() + "\"");
  }
  fs::path dir_, dict_;
  size_t count_ = 0;
  std::set<std::string> words_;
};

std::string joined(const std::vector<std::string>& parts) {
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? "\n@@\n" : "") + parts[i];
  return out;
}

void seedScene(const fs::path& root) {
  Corpus c(root, "scene");
  for (const fs::path& p : filesIn(source("models/scenes"), ".json")) {
    const std::string scene = read(p);
    c.add(scene, true);
    c.add(scene + "\n--set integrator.method=pbd-zopgm\n--set integrator.dt=0.02\n--set controller.gait.type=trot", true);
    c.add(scene + "\n--set contacts.model={\"type\": \"rbf\", \"file\": \"../../data/granular/rft_quadruped_rbf.h5\"}" +
              "\n--set terrain={\"type\": \"heightfield\", \"file\": \"../terrain/gentle_bumps.csv\", \"spacing\": 0.1}",
          true);
  }
}

void seedUrdf(const fs::path& root, const fs::path& shared) {
  Corpus c(root, "urdf");
  for (const fs::path& dir : {fs::path(source("models")), fs::path(source("tests/data")), shared / "robots"})
    for (const fs::path& p : filesIn(dir, ".urdf")) {
      c.add(read(p));
      c.xmlWords(read(p));
    }
}

void seedStl(const fs::path& root, const fs::path& shared) {
  Corpus c(root, "stl");
  c.words({"solid", "facet normal", "outer loop", "vertex", "endloop", "endfacet", "endsolid"});
  c.add("solid foot\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid foot\n");
  for (const fs::path& p : filesIn(shared / "robots", ".stl", 200000)) c.add(read(p));
  for (const fs::path& p : filesIn(shared / "robots", ".STL", 200000)) c.add(read(p));
}

void seedRbfText(const fs::path& root, const fs::path& shared) {
  Corpus c(root, "rbf_text");
  c.words({"\n@@\n", "nan", "inf", "1e308", "#"});
  const fs::path published = shared / "granular" / "robosimian_sand_rbf";
  if (fs::exists(published / "inputs.txt")) c.add(joined({read(published / "inputs.txt"), read(published / "weights.txt")}));
  c.add(joined({"-0.01 0\n-0.03 0.3\n0.05 0\n", "1 2 3\n4 5 6\n7 8 9\n"}));
}

void seedModelH5(const fs::path& root, const fs::path& scratch) {
  Corpus c(root, "model_h5");
  c.words({"group ", "attr ", "dset ", " f64 ", " f32 ", " i64 ", " i32 ", " u8 ", " str ", " fstr ", "nan", "inf", "1e308"});
  for (const fs::path& p : filesIn(source("data"), ".h5")) c.add(nmdp::fuzz::hdf5ToText(p.string()));
  // A small MLP of each envelope, written by the program's own writer.
  nmdp::PlanarGeometry geometry;
  geometry.torque_centre = 0.05;
  for (const nmdp::MlpOutputEnvelope envelope : {nmdp::MlpOutputEnvelope::None, nmdp::MlpOutputEnvelope::SoftDepth}) {
    nmdp::MlpParameters p = nmdp::randomMlpParameters(2, 4, 3, nmdp::MlpActivation::Tanh, 3);
    p.output_envelope = envelope;
    p.envelope_width = 0.005;
    const std::string file = (scratch / "mlp.h5").string();
    nmdp::saveMlpModel(file, p, geometry);
    c.add(nmdp::fuzz::hdf5ToText(file));
  }
}

void seedDatasetH5(const fs::path& root, const fs::path& scratch) {
  Corpus c(root, "dataset_h5");
  c.words({"group ", "attr ", "dset ", " f64 ", " f32 ", " i64 ", " i32 ", " u8 ", " str ", " fstr ", "nan", "inf", "1e308"});
  const std::string file = (scratch / "data.h5").string();
  nmdp::writeForceDataset(file, nmdp::importSandSamplesCsv(source("data/granular/rft_quadruped_samples")));
  c.add(nmdp::fuzz::hdf5ToText(file));
}

void seedForceCsv(const fs::path& root, const fs::path& shared) {
  Corpus c(root, "force_csv");
  c.words({"depth,theta", "depth,theta,vel_index,fx,fz,wy", "Nvel ", "Ntheta ", "cT ", "\n@@\n", "nan", "inf", "1e308"});
  for (const fs::path& dir : {fs::path(source("data/granular/rft_quadruped_samples")), shared / "granular" / "sand_samples"})
    if (fs::exists(dir / "features.csv"))
      c.add(joined({read(dir / "features.csv"), read(dir / "wrench_samples.csv"), read(dir / "scalars.txt")}));
}

void seedHeightfieldCsv(const fs::path& root) {
  Corpus c(root, "heightfield_csv");
  c.words({"nan", "inf", "1e308", "#", ","});
  for (const fs::path& p : filesIn(source("models/terrain"), ".csv")) c.add(read(p));
  c.add("# heights, m\n0, 0.01\n0.02, 0.03\n");
}

void seedKeyframes(const fs::path& root) {
  Corpus c(root, "keyframes");
  c.words({"time,", "FL_knee_joint", "FR_hip_joint", "\"times\"", "\"joints\"", "nan", "1e308"});
  c.add("time,FL_knee_joint,FR_knee_joint\n0,-1.2,-1.2\n0.5,-1.5,-1.0\n1,-1.2,-1.2\n");
  c.add("{\"times\": [0, 0.5, 1], \"joints\": {\"FL_knee_joint\": [-1.2, -1.5, -1.2], \"FL_hip_joint\": [0, 0.1, 0]}}", true);
}

void seedFitConfig(const fs::path& root) {
  Corpus c(root, "fit_config");
  for (const fs::path& p : filesIn(source("data/granular"), "_fit.json")) c.add(read(p), true);
  c.add("{}", true);
}

void seedRftConfig(const fs::path& root) {
  Corpus c(root, "rft_config");
  c.add(read(source("data/granular/rft_quadruped_foot.json")), true);
  c.add(read(source("data/granular/rft_quadruped_samples/rft_config.json")), true);
  c.add("{\"foot\": {\"shape\": \"plate\", \"length\": 0.05, \"width\": 0.02, \"elements\": 20}, \"grid\": "
        "{\"depths\": [-0.01], \"angles\": [0, 0.5], \"directions\": {\"type\": \"cube\", \"rotation_radius\": 0.05}}}",
        true);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds OUT_DIR\n";
    return 2;
  }
  const fs::path root(argv[1]);
  const fs::path shared = fs::path(source("..")) / "shared";
  const fs::path scratch = root / "scratch";
  fs::create_directories(scratch);

  seedScene(root);
  seedUrdf(root, shared);
  seedStl(root, shared);
  seedRbfText(root, shared);
  seedModelH5(root, scratch);
  seedDatasetH5(root, scratch);
  seedForceCsv(root, shared);
  seedHeightfieldCsv(root);
  seedKeyframes(root);
  seedFitConfig(root);
  seedRftConfig(root);
  fs::remove_all(scratch);
  std::cout << "seed corpora written to " << root.string() << "\n";
  return 0;
}
