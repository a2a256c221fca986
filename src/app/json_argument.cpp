#include "app/json_argument.hpp"

#include <filesystem>

#include "common/input_file.hpp"
#include "common/json_text.hpp"

namespace nmdp::app {

nlohmann::json readJsonArgument(const std::string& option, const std::string& text, ConfigContext& ctx) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{') {
    ctx.where = option;
    ctx.base_dir = "";
    return parseJson(text, option);
  }
  ctx.where = displayPath(text);
  ctx.base_dir = std::filesystem::path(text).parent_path().string();
  return loadJsonFile(text, "JSON file of " + option);
}

}  // namespace nmdp::app
