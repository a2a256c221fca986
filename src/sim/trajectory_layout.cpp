#include "sim/trajectory_layout.hpp"

#include <algorithm>
#include <filesystem>

#include "common/input_file.hpp"
#include "multibody/urdf_loader.hpp"
#include "terrain/heightfield.hpp"

namespace nmdp {

namespace {
// The name of q's column j in the output: a floating base's chart angles are named as what they are.
std::string columnName(const Model& model, int j) {
  const Body& body = model.bodies[static_cast<size_t>(j)];
  if (model.base == BaseType::Floating && body.is_base) {
    if (body.joint_name == "base_roll") return "base_chart_x";
    if (body.joint_name == "base_pitch") return "base_chart_y";
    if (body.joint_name == "base_yaw") return "base_chart_z";
  }
  return model.dof_names[static_cast<size_t>(j)];
}

// The rows of a CSV grid file as JSON arrays (row j along x).
nlohmann::json gridRows(const std::string& path) {
  const HeightGrid grid = readHeightGridCsv(path);
  nlohmann::json rows = nlohmann::json::array();
  for (int j = 0; j < grid.ny; ++j) {
    nlohmann::json row = nlohmann::json::array();
    for (int i = 0; i < grid.nx; ++i) row.push_back(grid.z[static_cast<size_t>(j) * static_cast<size_t>(grid.nx) + static_cast<size_t>(i)]);
    rows.push_back(std::move(row));
  }
  return rows;
}
}  // namespace

std::vector<std::string> urdfMeshFiles(const std::string& urdf_text) {
  std::vector<std::string> files;
  for (size_t at = urdf_text.find("<mesh"); at != std::string::npos; at = urdf_text.find("<mesh", at + 5)) {
    const size_t end = urdf_text.find('>', at);
    const std::string element = urdf_text.substr(at, end == std::string::npos ? std::string::npos : end - at);
    const size_t key = element.find("filename");
    if (key == std::string::npos) continue;
    const size_t open = element.find_first_of("\"'", key);
    if (open == std::string::npos) continue;
    const size_t close = element.find(element[open], open + 1);
    if (close == std::string::npos) continue;
    const std::string file = element.substr(open + 1, close - open - 1);
    if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
  }
  return files;
}

nlohmann::json selfContainedTerrain(const nlohmann::json& terrain) {
  nlohmann::json out = terrain;
  if (!out.is_object()) return out;
  if (out.value("type", "") == "heightfield" && out.contains("file") && out.at("file").is_string()) {
    out["heights"] = gridRows(out.at("file").get<std::string>());
    out.erase("file");
  }
  return out;
}

std::vector<std::string> outputCoordinateNames(const Model& model) {
  std::vector<std::string> names;
  for (int j = 0; j < model.nq; ++j) names.push_back(columnName(model, j));
  return names;
}

TrajectoryLayout trajectoryLayout(const Simulation& sim) {
  const Model& model = sim.model();
  TrajectoryLayout layout;
  layout.joint_names = outputCoordinateNames(model);
  for (int j = 0; j < model.nq; ++j) {
    layout.coordinate_units.push_back(model.bodies[static_cast<size_t>(j)].kind == JointKind::Prismatic ? "m" : "rad");
  }
  for (const ContactPoint& c : sim.system().contacts) layout.contact_names.push_back(c.name);
  layout.feature_names.clear();
  layout.feature_units.clear();
  layout.feature_descriptions.clear();
  for (const ContactFeatureInfo& f : sim.contactModel().featureInfo()) {
    layout.feature_names.push_back(f.name);
    layout.feature_units.push_back(f.unit.empty() ? "1" : f.unit);
    layout.feature_descriptions.push_back(f.description);
  }
  for (const Link& link : model.links) layout.link_names.push_back(link.name);
  layout.config_json = sim.resolvedScene().dump(2);
  layout.string_attributes = {{"robot", model.robot_name},
                              {"method", methodName(sim.options().method)},
                              {"contact_model", sim.contactModel().describe()},
                              {"terrain", sim.terrain().describe()}};
  layout.number_attributes = {{"dt", sim.dt()}, {"duration", sim.scene().duration}};
  layout.urdf_path = sim.scene().urdf;
  layout.urdf_text = readInputFile(layout.urdf_path, "URDF file");
  layout.mesh_files = urdfMeshFiles(layout.urdf_text);
  for (const std::string& file : layout.mesh_files) layout.mesh_paths.push_back(resolveMeshFile(file, std::filesystem::path(layout.urdf_path).parent_path().string()));
  layout.terrain_description = selfContainedTerrain(sim.scene().terrain).dump();
  return layout;
}

}  // namespace nmdp
