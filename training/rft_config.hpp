// The configuration of `nmdp gen-rft` (training/README.md): the medium, the foot and the grid of
// depths, angles and directions. Every key is optional unless marked; unknown keys are rejected with
// the closest valid key; `nmdp gen-rft --schema` prints every key with its default.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "config/schema.hpp"
#include "training/rft.hpp"

namespace nmdp {

struct RftConfig {
  RftMedium medium;
  RftFoot foot;
  RftGrid grid;
  nlohmann::ordered_json resolved;  // the configuration with every default filled in
};

// The keys of each section ("" for the top level, "grid.directions:circle" for one directions type).
const std::vector<KeyDoc>& rftSectionKeys(const std::string& section);
nlohmann::ordered_json rftConfigSchema();

// `where` names the configuration in messages (the file name, or e.g. "defaults"). Throws
// InputError "WHERE: foot.radius: ..." on the first bad, missing or unknown key.
RftConfig readRftConfig(const nlohmann::json& config, const std::string& where);

}  // namespace nmdp
