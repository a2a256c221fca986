#include "app/view_payload.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/build_version.hpp"
#include "app/view_page.hpp"
#include "app/view_robot.hpp"
#include "app/view_run.hpp"
#include "app/view_terrain.hpp"
#include "common/limits.hpp"

namespace nmdp::app {

namespace {

std::vector<float> toFloats(const Rows& rows) {
  std::vector<float> out(static_cast<size_t>(rows.size()));
  for (Eigen::Index k = 0; k < rows.size(); ++k) out[static_cast<size_t>(k)] = static_cast<float>(rows.data()[k]);
  return out;
}

size_t count(Eigen::Index n) { return static_cast<size_t>(n); }

const nlohmann::json& contactModelOf(const RunFile& run) {
  static const nlohmann::json kNone;
  const nlohmann::json& c = run.config;
  return c.contains("contacts") && c["contacts"].is_object() && c["contacts"].contains("model") ? c["contacts"]["model"] : kNone;
}

// "trot.h5: ne-pgm, dt = 50 ms, rbf".
std::string label(const RunFile& run) {
  std::string out = run.name;
  std::vector<std::string> parts;
  if (!run.method.empty()) parts.push_back(run.method);
  if (run.dt > 0) {
    char dt[48];
    std::snprintf(dt, sizeof dt, "dt = %g ms", run.dt * 1e3);
    parts.push_back(dt);
  }
  const nlohmann::json& model = contactModelOf(run);
  if (model.is_object() && model.contains("type") && model["type"].is_string()) parts.push_back(model["type"].get<std::string>());
  for (size_t k = 0; k < parts.size(); ++k) out += (k ? ", " : ": ") + parts[k];
  return out;
}

// Torso height over the ground below it and the distance walked along the initial heading.
nlohmann::json series(const RunFile& run, const Terrain& terrain) {
  const long n = run.rows;
  std::vector<float> height(n), forward(n);
  const Eigen::Quaterniond q0(run.base_quaternion(0, 3), run.base_quaternion(0, 0), run.base_quaternion(0, 1), run.base_quaternion(0, 2));
  Eigen::Vector2d heading = (q0.normalized() * Eigen::Vector3d::UnitX()).head<2>();
  heading = heading.norm() > 1e-9 ? heading.normalized() : Eigen::Vector2d::UnitX();
  for (long i = 0; i < n; ++i) {
    const double x = run.base_position(i, 0), y = run.base_position(i, 1), z = run.base_position(i, 2);
    height[i] = static_cast<float>(z - surfaceHeight(terrain, x, y));
    forward[i] = static_cast<float>(heading.dot(Eigen::Vector2d(x - run.base_position(0, 0), y - run.base_position(0, 1))));
  }
  return {{"torso_height", floatArray(height, {count(n)})}, {"forward_distance", floatArray(forward, {count(n)})}};
}

nlohmann::json contacts(const RunFile& run, const Terrain& terrain) {
  const size_t n = count(run.rows), c = run.contact_names.size();
  nlohmann::json out = {{"names", run.contact_names},
                        {"forces", floatArray(toFloats(run.contact_forces), {n, c, 3})},
                        {"points", nullptr},
                        {"normal_force", nullptr}};
  if (!run.foot_points) return out;
  out["points"] = floatArray(toFloats(*run.foot_points), {n, c, 3});
  std::vector<float> normal(n * c);
  TerrainQuery q;
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < c; ++k) {
      const Vec3 point = run.foot_points->row(static_cast<Eigen::Index>(i)).segment<3>(static_cast<Eigen::Index>(3 * k));
      terrain.query(point, q, false);
      normal[i * c + k] = static_cast<float>(q.normal.dot(run.contact_forces.row(static_cast<Eigen::Index>(i)).segment<3>(static_cast<Eigen::Index>(3 * k))));
    }
  out["normal_force"] = floatArray(normal, {n, c});
  return out;
}

nlohmann::json runPayload(RunFile& run, std::uintmax_t& mesh_bytes_left) {
  std::vector<std::string> quiet;  // the terrain's own warning is the page's (terrainPayload)
  const std::unique_ptr<Terrain> terrain = rebuildTerrain(run.terrain ? *run.terrain : nlohmann::json::object(),
                                                          std::filesystem::path(run.path).parent_path().string(),
                                                          run.name + ": terrain", quiet);
  const RobotPayload robot = robotPayload(run, mesh_bytes_left);
  const size_t n = count(run.rows);
  return {{"label", label(run)},
          {"file", run.path},
          {"status", run.status},
          {"warnings", run.warnings},
          {"frames", run.rows},
          {"time", doubleArray(run.time, {n})},
          {"links", robot.links},
          {"link_poses", robot.link_poses},
          {"base", {{"position", floatArray(toFloats(run.base_position), {n, 3})},
                    {"quaternion", floatArray(toFloats(run.base_quaternion), {n, 4})}}},
          {"contacts", contacts(run, *terrain)},
          {"joints", {{"names", run.joint_names}, {"q", floatArray(toFloats(run.joint_q), {n, run.joint_names.size()})}}},
          {"series", series(run, *terrain)}};
}

}  // namespace

ViewPayload buildViewPayload(const std::vector<std::string>& run_files) {
  std::vector<RunFile> runs;
  for (const std::string& file : run_files) runs.push_back(readRunFile(file));

  ViewPayload out;
  const BuildVersion version = buildVersion();
  nlohmann::json page = {{"format", "nmdp-view"},
                         {"version", 1},
                         {"generator", std::string("nmdp ") + version.version + " (commit " + version.commit + ")"},
                         {"terrain", nullptr}};
  std::vector<std::string> page_warnings;
  GridBounds bounds;
  for (const RunFile& run : runs)
    for (long i = 0; i < run.rows; ++i) {
      bounds.add(run.base_position(i, 0), run.base_position(i, 1));
      if (run.foot_points)
        for (Eigen::Index k = 0; k + 2 < run.foot_points->cols(); k += 3) bounds.add((*run.foot_points)(i, k), (*run.foot_points)(i, k + 1));
    }
  for (const RunFile& run : runs) {
    if (!run.terrain) continue;
    page["terrain"] = terrainPayload(*run.terrain, std::filesystem::path(run.path).parent_path().string(), run.name + ": terrain",
                                     contactModelOf(run), bounds, page_warnings);
    break;
  }
  if (page["terrain"].is_null()) page_warnings.push_back("no run file describes its terrain: the ground is not drawn");

  std::uintmax_t mesh_bytes_left = limits::kMaxPageMeshBytes;
  page["runs"] = nlohmann::json::array();
  for (RunFile& run : runs) {
    page["runs"].push_back(runPayload(run, mesh_bytes_left));
    out.frames = std::max(out.frames, run.rows);
  }
  out.warnings = page_warnings;
  for (const RunFile& run : runs) out.warnings.insert(out.warnings.end(), run.warnings.begin(), run.warnings.end());
  page["warnings"] = page_warnings;
  out.json = std::move(page);
  return out;
}

}  // namespace nmdp::app
