// Parsing the JSON a user hands to nmdp (scene files, --set values, configuration files, keyframes,
// inline objects): one function, so every entry point has the same limits and messages. The text's
// nesting is bounded (limits::kMaxJsonDepth) before nlohmann::json sees it, since copying, comparing
// or printing a value recurses once per level: a file nested 10^5 deep would overflow the stack.
// Errors are InputError "<where>:<line>:<column>: invalid JSON: <reason>" (the position of the byte
// the parser stopped at), also for a number too large for a double ("1e309").
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace nmdp {

// `where` names the source in messages: a file path, or e.g. "--set duration=1e309".
nlohmann::json parseJson(const std::string& text, const std::string& where);
nlohmann::ordered_json parseOrderedJson(const std::string& text, const std::string& where);

// readInputFile() then parseJson(); `what` names the file's role ("scene file").
nlohmann::json loadJsonFile(const std::string& path, const std::string& what);

// Whether `text` is JSON syntax within the nesting limit (a --set value that is not is a plain
// string); true also for a number too large for a double, which parseJson() then refuses.
bool isJson(const std::string& text);

// A value for a message: its JSON text, cut to about `max_chars` characters with "..." so that an
// error about a huge array or object stays one readable line.
std::string jsonForMessage(const nlohmann::json& value, size_t max_chars = 80);
std::string jsonForMessage(const nlohmann::ordered_json& value, size_t max_chars = 80);

}  // namespace nmdp
