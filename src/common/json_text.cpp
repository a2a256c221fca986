#include "common/json_text.hpp"

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"

namespace nmdp {

namespace {

// "line:column" of byte offset `offset` (0-based) of `text`, both 1-based.
std::string position(const std::string& text, size_t offset) {
  offset = std::min(offset, text.size());
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

// The offset of the first bracket that opens level kMaxJsonDepth + 1, if any. Strings are skipped
// (with their escapes); anything else malformed is left to the parser.
std::optional<size_t> tooDeep(const std::string& text) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limits::kMaxJsonDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::nullopt;
}

std::string withoutPrefix(const std::string& what) {  // "[json.exception.parse_error.101] parse error at ..."
  const size_t close = what.find("] ");
  return what.rfind("[json.exception", 0) == 0 && close != std::string::npos ? what.substr(close + 2) : what;
}

template <class Json>
Json parse(const std::string& text, const std::string& where) {
  if (const std::optional<size_t> at = tooDeep(text))
    throw InputError(where + ":" + position(text, *at) + ": invalid JSON: nested more than " +
                     std::to_string(limits::kMaxJsonDepth) + " levels deep");
  // Keys seen in each object being parsed: a key given twice is refused (nlohmann::json would keep the
  // last silently, so one of two values the user wrote would be ignored).
  std::vector<std::set<std::string>> keys;
  std::string duplicate;
  const auto callback = [&](int, typename Json::parse_event_t event, Json& parsed) {
    if (event == Json::parse_event_t::object_start) keys.emplace_back();
    else if (event == Json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    else if (event == Json::parse_event_t::key && !keys.empty() && !keys.back().insert(parsed.template get<std::string>()).second &&
             duplicate.empty())
      duplicate = parsed.template get<std::string>();
    return true;
  };
  try {
    Json value = Json::parse(text, callback);
    if (!duplicate.empty())
      throw InputError(where + ": invalid JSON: the key \"" + (duplicate.size() > 80 ? duplicate.substr(0, 80) + "..." : duplicate) +
                       "\" appears twice in one object");
    return value;
  } catch (const typename Json::parse_error& e) {
    throw InputError(where + ":" + position(text, e.byte == 0 ? 0 : e.byte - 1) + ": invalid JSON: " + withoutPrefix(e.what()));
  } catch (const typename Json::exception& e) {  // out_of_range.406: a number too large for a double
    throw InputError(where + ": invalid JSON: " + withoutPrefix(e.what()));
  }
}

template <class Json>
std::string forMessage(const Json& value, size_t max_chars) {
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > max_chars) text = text.substr(0, max_chars) + "...";
  return text;
}

}  // namespace

nlohmann::json parseJson(const std::string& text, const std::string& where) { return parse<nlohmann::json>(text, where); }

nlohmann::ordered_json parseOrderedJson(const std::string& text, const std::string& where) {
  return parse<nlohmann::ordered_json>(text, where);
}

nlohmann::json loadJsonFile(const std::string& path, const std::string& what) {
  return parseJson(readInputFile(path, what), displayPath(path));
}

bool isJson(const std::string& text) {
  if (tooDeep(text)) return false;
  try {
    const nlohmann::json parsed = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error&) {
    return false;
  } catch (const nlohmann::json::exception&) {  // JSON, but a number overflows: parseJson says so
  }
  return true;
}

std::string jsonForMessage(const nlohmann::json& value, size_t max_chars) { return forMessage(value, max_chars); }
std::string jsonForMessage(const nlohmann::ordered_json& value, size_t max_chars) { return forMessage(value, max_chars); }

}  // namespace nmdp
