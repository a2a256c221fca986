// Keyframe files of the keyframes gait: CSV with the header time,<joint names...> and one row per
// keyframe, or JSON {"times": [...], "joints": {name: [...]}}.
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "sim/scene_parts.hpp"

namespace nmdp::scene_detail {

namespace {
// Keyframes of one file: a motion sampled at 1 kHz for 15 minutes has 10^6.
constexpr size_t kMaxKeyframes = 1000000;

}  // namespace

[[noreturn]] void keyframeFail(const SceneConfig& c, const std::string& what) {
  (Where{fileOf(c), "controller.gait.file"}).fail(displayPath(c.keyframe_file) + ": " + what);
}

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    const size_t a = cell.find_first_not_of(" \t\r");
    const size_t b = cell.find_last_not_of(" \t\r");
    out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// {"times": [...], "joints": {name: [...]}}
void readJsonKeyframes(const SceneConfig& c, const std::string& text, Keyframes& k) {
  json j;
  try {
    j = parseJson(text, displayPath(c.keyframe_file));
  } catch (const InputError& e) {
    (Where{fileOf(c), "controller.gait.file"}).fail(e.what());
  }
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "times" && it.key() != "joints")
      keyframeFail(c, "unknown key '" + it.key() + "'; valid keys: times, joints");
  if (!j.contains("times") || !j.contains("joints"))
    keyframeFail(c, "expected {\"times\": [...], \"joints\": {name: [...]}}");
  const json& times = j.at("times");
  if (!times.is_array()) keyframeFail(c, "times: expected a list of numbers");
  if (times.size() > kMaxKeyframes) keyframeFail(c, "times: more than " + std::to_string(kMaxKeyframes) + " keyframes");
  if (j.at("joints").is_object() && j.at("joints").size() > static_cast<size_t>(limits::kMaxJoints))
    keyframeFail(c, "joints: more than " + std::to_string(limits::kMaxJoints) + " joints");
  for (const json& t : times) {
    if (!t.is_number() || !std::isfinite(t.get<double>())) keyframeFail(c, "times: expected a list of numbers, got " + jsonForMessage(t));
    k.times.push_back(t.get<double>());
  }
  if (!j.at("joints").is_object()) keyframeFail(c, "joints: expected an object {name: [values]}");
  for (auto it = j.at("joints").begin(); it != j.at("joints").end(); ++it) {
    std::vector<double> column;
    if (!it.value().is_array() || it.value().size() != k.times.size())
      keyframeFail(c, "joints." + it.key() + ": expected " + std::to_string(k.times.size()) + " numbers (one per time)");
    for (const json& x : it.value()) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) keyframeFail(c, "joints." + it.key() + ": expected numbers, got " + jsonForMessage(x));
      column.push_back(x.get<double>());
    }
    k.joints.push_back(it.key());
    k.columns.push_back(column);
  }
}

// time,<joint names...> and one row per keyframe; blank lines and # comments skipped.
void readCsvKeyframes(const SceneConfig& c, const std::string& text, Keyframes& k) {
  std::stringstream lines(text);
  std::string line;
  int line_number = 0;
  bool header = false;
  while (std::getline(lines, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::vector<std::string> cells = splitCsv(line);
    if (!header) {
      header = true;
      if (cells.empty() || cells[0] != "time")
        keyframeFail(c, "line " + std::to_string(line_number) + ": the header must be time,<joint names...>");
      if (cells.size() > static_cast<size_t>(limits::kMaxJoints) + 1)
        keyframeFail(c, "line " + std::to_string(line_number) + ": more than " + std::to_string(limits::kMaxJoints) + " joints");
      k.joints.assign(cells.begin() + 1, cells.end());
      for (const std::string& name : k.joints)
        if (name.empty()) keyframeFail(c, "line " + std::to_string(line_number) + ": empty joint name in the header");
      k.columns.assign(k.joints.size(), {});
      continue;
    }
    if (cells.size() != k.joints.size() + 1)
      keyframeFail(c, "line " + std::to_string(line_number) + ": expected " + std::to_string(k.joints.size() + 1) +
                          " values, got " + std::to_string(cells.size()));
    if (k.times.size() >= kMaxKeyframes)
      keyframeFail(c, "line " + std::to_string(line_number) + ": more than " + std::to_string(kMaxKeyframes) + " keyframes");
    for (size_t i = 0; i < cells.size(); ++i) {
      double v = 0;
      try {
        size_t used = 0;
        v = std::stod(cells[i], &used);
        if (used != cells[i].size() || !std::isfinite(v)) throw std::invalid_argument(cells[i]);
      } catch (const std::exception&) {
        keyframeFail(c, "line " + std::to_string(line_number) + ", column " + std::to_string(i + 1) + ": '" +
                            cells[i].substr(0, 40) + (cells[i].size() > 40 ? "..." : "") + "' is not a number");
      }
      if (i == 0) k.times.push_back(v);
      else k.columns[i - 1].push_back(v);
    }
  }
  if (!header) keyframeFail(c, "empty file; expected the header time,<joint names...> and one row per keyframe");
}

}  // namespace

Keyframes readKeyframes(const SceneConfig& c) {
  std::string text;
  try {
    text = readInputFile(c.keyframe_file, "keyframe file");
  } catch (const InputError& e) {
    (Where{fileOf(c), "controller.gait.file"}).fail(e.what());
  }
  Keyframes k;
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{')
    readJsonKeyframes(c, text, k);
  else
    readCsvKeyframes(c, text, k);
  if (k.times.empty()) keyframeFail(c, "no keyframes");
  for (size_t i = 1; i < k.times.size(); ++i)
    if (!(k.times[i] > k.times[i - 1]))
      keyframeFail(c, "times must increase strictly (keyframe " + std::to_string(i + 1) + ": " + numberText(k.times[i]) +
                          " after " + numberText(k.times[i - 1]) + ")");
  std::set<std::string> listed;
  for (const std::string& name : k.joints)
    if (!listed.insert(name).second) keyframeFail(c, "joint '" + name + "' is listed twice");
  return k;
}

// Keyframe positions (nq each) from the file over the base pose.
std::vector<Eigen::VectorXd> keyframePositions(const SceneConfig& c, const Model& model, const Keyframes& k,
                                               const Eigen::VectorXd& base) {
  std::vector<int> index;
  for (const std::string& name : k.joints) {
    const int i = model.dofIndex(name);
    if (i < 0 || model.bodies[i].is_base) {
      std::vector<std::string> names;
      for (int j = 0; j < model.nq; ++j)
        if (!model.bodies[j].is_base) names.push_back(model.dof_names[j]);
      keyframeFail(c, "the robot has no actuated joint '" + name + "'" + suggestion(name, names));
    }
    index.push_back(i);
  }
  std::vector<Eigen::VectorXd> positions(k.times.size(), base);
  for (size_t f = 0; f < k.times.size(); ++f)
    for (size_t j = 0; j < index.size(); ++j) positions[f][index[j]] = k.columns[j][f];
  return positions;
}



}  // namespace nmdp::scene_detail
