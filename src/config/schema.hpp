// Schema rows of keys whose reading is written by hand (sections with optional or data-decided
// values), in the same form as Fields::schema(), and the text `--schema` prints for a configuration.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nmdp {

struct KeyDoc {
  const char* key;
  const char* type;
  nlohmann::ordered_json default_value;  // null: none (required, or decided later)
  const char* range;
  const char* unit;
  const char* doc;
};

std::vector<std::string> keysOf(const std::vector<KeyDoc>& keys);
// [{"key", "type", "default", "range", "unit", "doc"}, ...] (absent entries left out).
nlohmann::ordered_json schemaRows(const std::vector<KeyDoc>& keys);
// {"section": rows, ...} as text: a header per section ("" is the top level) and a line per key
// "  key: type = default  in range  [unit]" with its doc below.
std::string schemaText(const nlohmann::ordered_json& sections);

}  // namespace nmdp
