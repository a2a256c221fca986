// The payload of the page nmdp view writes (format "nmdp-view", version 1; the contract with the
// front end in viewer/README.md): runs read from their files (view_run.hpp), the robot of each
// (view_robot.hpp) and one terrain grid (view_terrain.hpp), with every warning of what was missing.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nmdp::app {

struct ViewPayload {
  nlohmann::json json;
  std::vector<std::string> warnings;  // of the page and of every run, in order (for stderr)
  long frames = 0;                    // the most frames of a run
};

// InputError naming the file and the dataset for a run that cannot be shown.
ViewPayload buildViewPayload(const std::vector<std::string>& run_files);

}  // namespace nmdp::app
