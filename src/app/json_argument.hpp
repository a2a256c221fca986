// A JSON object given on the command line (nmdp wrench --model/--terrain, fit --config, gen-rft
// --config): inline when it starts with '{', else the path of a .json file. Read through
// common/json_text.hpp, so every option has the same limits and messages as a scene file.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "config/json_params.hpp"

namespace nmdp::app {

// Sets ctx.where to `option` for inline JSON or to the file's path, and ctx.base_dir to the file's
// folder ("" inline), against which relative paths inside the object resolve. InputError on a
// file that cannot be read or text that is not JSON (naming the option or file, line and column).
nlohmann::json readJsonArgument(const std::string& option, const std::string& text, ConfigContext& ctx);

}  // namespace nmdp::app
