// The output layout of a run (sim/trajectory_writer.hpp's TrajectoryLayout) from its Simulation:
// what `nmdp simulate` and the Python module write.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/simulation.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp {

// Coordinate, contact, feature and link names with their units; the resolved scene as `config`; the
// robot, method, contact model, terrain, dt and duration as root attributes (the caller adds more,
// e.g. the nmdp version); the URDF text, path and meshes; the terrain's description. A floating
// base's chart angles are named base_chart_x/y/z (the model's base_roll/pitch/yaw are not the
// /base/rpy angles). InputError if the URDF or a terrain file can no longer be read.
TrajectoryLayout trajectoryLayout(const Simulation& sim);

// The names of q's entries as the output's /joint_names gives them (the model's dof names, a floating
// base's chart angles as base_chart_x/y/z).
std::vector<std::string> outputCoordinateNames(const Model& model);

// Every distinct filename="..." of the <mesh> elements of a URDF text, in the order they appear.
std::vector<std::string> urdfMeshFiles(const std::string& urdf_text);

// The resolved terrain object with a heightfield's "file" replaced by its "heights", so that
// makeTerrain builds the same terrain from it without that file. (A material map keeps its "file".)
nlohmann::json selfContainedTerrain(const nlohmann::json& terrain);

}  // namespace nmdp
