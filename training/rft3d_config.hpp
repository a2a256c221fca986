// The configuration of `nmdp gen-rft` in three dimensions (training/rft3d_samples.hpp). gen-rft
// reads this one when the configuration's top level says "dimension": 3 (2 or absent: the planar
// configuration of training/rft_config.hpp). Keys (every one optional except those marked; unknown
// keys are rejected with the closest valid key; `nmdp gen-rft --schema` prints them all):
//   dimension  3
//   output     "spatial" (default: the 3-D dataset, vertex j = direction j) or "planar" (the planar
//              dataset of the same foot and medium: γ = 0, directions in the x–z plane)
//   medium     as the planar configuration: zeta (N/cm³) and the nine coefficients
//   foot       shape "sphere" (radius, m, default 0.02) | "plate" | "blade" (length and width, m,
//              required); elements (cuts per direction, default 64); torque_centre (m up the leg,
//              planar output only, default 0)
//   grid       depths (m, ≤ 0), betas and gammas (rad, in [−π/2, π/2]; gammas not with the planar
//              output), directions {"type": "cube"} (the 26 cube directions, the spatial default) |
//              {"type": "fibonacci", "count": N} | {"type": "list", "vectors": [[x, y, z], ...]} |
//              {"type": "circle", "count": N} (in the x–z plane, the planar default)
// Every error is one InputError "WHERE: key: what".
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/schema.hpp"
#include "training/rft3d_samples.hpp"

namespace nmdp {

enum class Rft3dOutput { Spatial, Planar };

struct Rft3dConfig {
  RftMedium medium;
  Rft3dFoot foot;
  Rft3dGrid grid;
  Rft3dOutput output = Rft3dOutput::Spatial;
  double torque_centre = 0.0;  // m, planar output
  nlohmann::ordered_json resolved;  // the configuration with every default filled in
};

// True when `config` asks for the 3-D configuration ("dimension": 3). Throws InputError naming
// `where` and "dimension" when the key holds anything but 2 or 3.
bool isRft3dConfig(const nlohmann::json& config, const std::string& where);

const std::vector<KeyDoc>& rft3dSectionKeys(const std::string& section);
nlohmann::ordered_json rft3dConfigSchema();

// Throws InputError "WHERE: grid.betas: ..." on the first bad, missing or unknown key.
Rft3dConfig readRft3dConfig(const nlohmann::json& config, const std::string& where);

// The dataset the configuration asks for.
ForceDataset rft3dConfigSamples(const Rft3dConfig& config);

}  // namespace nmdp
