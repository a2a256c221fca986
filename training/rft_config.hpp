// The configuration of `nmdp gen-rft` (training/README.md): a JSON object
//   {
//     "medium": {"zeta": 1.0,                       // N/cm³, > 0
//                "coefficients": {"A00": ..., ...}}  // all nine, or omitted for the generic values
//     "foot":   {"shape": "disc" | "plate" | "blade",
//                "radius": 0.02,                     // disc only, m (default 0.02)
//                "length": ...,                      // plate and blade only, m (required)
//                "width": ...,                       // m; disc default 2 radius, required otherwise
//                "torque_centre": 0.0,               // m up the leg from the foot point
//                "elements": 400},
//     "grid":   {"depths": [...],                    // m, ≤ 0, no repeats (default the sand samples')
//                "angles": [...],                    // rad, in [−π/2, π/2], no repeats
//                "directions": {"type": "circle", "count": 26}
//                            | {"type": "cube", "rotation_radius": R}
//                            | {"type": "list", "twists": [[vx, vz, omega], ...]}}
//   }
// Every key is optional unless marked; unknown keys are rejected with the closest valid key.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "training/rft.hpp"

namespace nmdp {

struct RftConfig {
  RftMedium medium;
  RftFoot foot;
  RftGrid grid;
  nlohmann::ordered_json resolved;  // the configuration with every default filled in
};

// `where` names the configuration in messages (the file name, or e.g. "defaults"). Throws
// InputError "WHERE: foot.radius: ..." on the first bad, missing or unknown key.
RftConfig readRftConfig(const nlohmann::json& config, const std::string& where);

}  // namespace nmdp
