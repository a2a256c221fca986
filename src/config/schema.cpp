#include "config/schema.hpp"

#include <sstream>

namespace nmdp {

std::vector<std::string> keysOf(const std::vector<KeyDoc>& keys) {
  std::vector<std::string> out;
  for (const KeyDoc& k : keys) out.emplace_back(k.key);
  return out;
}

nlohmann::ordered_json schemaRows(const std::vector<KeyDoc>& keys) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const KeyDoc& k : keys) {
    nlohmann::ordered_json row;
    row["key"] = k.key;
    row["type"] = k.type;
    if (!k.default_value.is_null()) row["default"] = k.default_value;
    if (*k.range) row["range"] = k.range;
    if (*k.unit) row["unit"] = k.unit;
    row["doc"] = k.doc;
    rows.push_back(row);
  }
  return rows;
}

std::string schemaText(const nlohmann::ordered_json& sections) {
  std::ostringstream os;
  for (auto it = sections.begin(); it != sections.end(); ++it) {
    os << (it.key().empty() ? "(top level)" : it.key()) << "\n";
    for (const nlohmann::ordered_json& row : it.value()) {
      os << "  " << row.at("key").get<std::string>() << ": " << row.at("type").get<std::string>();
      if (row.contains("default")) os << " = " << row.at("default").dump();
      if (row.contains("range")) {
        const std::string range = row.at("range");
        os << (range.find(" | ") != std::string::npos ? "  one of " : "  in ") << range;
      }
      if (row.contains("unit")) os << "  [" << row.at("unit").get<std::string>() << "]";
      os << "\n      " << row.at("doc").get<std::string>() << "\n";
    }
  }
  return os.str();
}

}  // namespace nmdp
