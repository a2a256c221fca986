// Loading a scene file and applying `--set key.path=value` overrides to it.
#include "sim/scene.hpp"

#include <stdexcept>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "common/limits.hpp"
#include "common/utf8.hpp"

namespace nmdp {

using json = nlohmann::json;


json loadSceneJson(const std::string& path) {
  const json scene = parseJson(readInputFile(path, "scene file"), displayPath(path));
  if (!scene.is_object())
    throw InputError(displayPath(path) + ": expected a JSON object {\"robot\": ..., ...}, got " + std::string(scene.type_name()));
  return scene;
}

void applyOverride(json& scene, const std::string& assignment, const std::string& file) {
  // The assignment as messages show it: an absurdly long one is shortened like a path.
  const std::string prefix = (file.empty() ? "" : file + ": ") + "--set " + displayPath(assignment) + ": ";
  if (!isValidUtf8(assignment)) throw InputError(prefix + "not valid UTF-8 text");
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) throw InputError(prefix + "expected key.path=value (e.g. integrator.dt=0.01)");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  std::vector<std::string> segments;
  {
    size_t start = 0;
    while (true) {
      const size_t dot = key.find('.', start);
      segments.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
  }
  for (const std::string& s : segments)
    if (s.empty()) throw InputError(prefix + "empty key" + (key.empty() ? "" : " segment in '" + key + "'") + "; expected key.path=value");
  if (segments.size() > static_cast<size_t>(limits::kMaxJsonDepth))
    throw InputError(prefix + "the key has " + std::to_string(segments.size()) + " levels, more than the " +
                     std::to_string(limits::kMaxJsonDepth) + " a scene may nest");

  // A plain string unless it is JSON: --set integrator.method=ne-zopgm.
  const json value = isJson(text) ? parseJson(text, prefix.substr(0, prefix.size() - 2)) : json(text);

  if (!scene.is_object()) scene = json::object();
  json* node = &scene;
  std::string walked;
  for (size_t i = 0; i < segments.size(); ++i) {
    const std::string& s = segments[i];
    const bool last = i + 1 == segments.size();
    json* next = nullptr;
    if (node->is_array()) {
      size_t used = 0;
      long index = -1;
      try {
        index = std::stol(s, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != s.size() || index < 0 || static_cast<size_t>(index) >= node->size())
        throw InputError(prefix + "'" + walked + "' is a list of " + std::to_string(node->size()) +
                         " items; expected an index 0.." + std::to_string(static_cast<long>(node->size()) - 1) + ", got '" + s + "'");
      next = &(*node)[static_cast<size_t>(index)];
    } else {
      if (!node->contains(s) && !last) (*node)[s] = json::object();
      next = &(*node)[s];
    }
    walked += (walked.empty() ? "" : ".") + s;
    if (last) {
      *next = value;
      return;
    }
    if (!next->is_object() && !next->is_array())
      throw InputError(prefix + "'" + walked + "' is " + jsonForMessage(*next) + ", not an object; cannot set a key inside it");
    node = next;
  }
}

}  // namespace nmdp
