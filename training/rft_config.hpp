// The configuration of `nmdp gen-rft` (training/README.md): the medium, the foot and the grid of
// depths, angles and directions. Every key is optional unless marked; unknown keys are rejected with
// the closest valid key; `nmdp gen-rft --schema` prints every key with its default.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "config/json_params.hpp"
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

// Shared with the 3-D configuration (training/rft3d_config.hpp). The section "medium" at `where`;
// `resolved` gets it with every default filled in.
RftMedium readRftMedium(const nlohmann::json& medium, const std::string& where, nlohmann::ordered_json& resolved);
// The numbers of `key` in `object` (fallback when absent): 1 to 1000 distinct values in [lo, hi]
// (`range` describes it in messages, e.g. "[-pi/2, pi/2] (rad)").
std::vector<double> readRftGridValues(const nlohmann::json& object, const std::string& key,
                                      const std::vector<double>& fallback, const ConfigContext& ctx, double lo,
                                      double hi, const std::string& range);

}  // namespace nmdp
