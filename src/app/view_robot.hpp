// The robot of one run for the page: each link's shapes (URDF visuals, with mesh files inlined; a
// link whose mesh is not found is drawn from its collision shapes, then from the box of its mass
// and inertia) and each link's world pose per frame. Without a URDF the trunk is a box at /base.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/view_run.hpp"

namespace nmdp::app {

// The trunk drawn when a run has no URDF, m.
inline constexpr double kFallbackTrunkSize[3] = {0.3, 0.2, 0.1};

struct RobotPayload {
  nlohmann::json links = nlohmann::json::array();  // [{"name", "visuals"}]
  nlohmann::json link_poses;                        // float32 N × L × 7
};

// Appends what it cannot draw as asked to run.warnings; mesh bytes count against `mesh_bytes_left`
// (limits::kMaxPageMeshBytes for the whole page).
RobotPayload robotPayload(RunFile& run, std::uintmax_t& mesh_bytes_left);

}  // namespace nmdp::app
