#include "app/view_robot.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>

#include "app/view_page.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"
#include "multibody/urdf_visuals.hpp"

namespace nmdp::app {

namespace {

// Mesh files read for one page: a file shared by links (or runs) is read once.
struct MeshReader {
  std::uintmax_t& bytes_left;
  std::map<std::string, std::vector<std::uint8_t>> cache;
  // The bytes of `path`, or why they cannot be inlined.
  const std::vector<std::uint8_t>* read(const std::string& path, std::string& why) {
    if (const auto hit = cache.find(path); hit != cache.end()) return &hit->second;
    try {
      const std::string bytes = readInputFile(path, "mesh file", limits::kMaxMeshFileBytes);
      if (bytes.size() > bytes_left) {
        why = "it would take the page's meshes beyond " + std::to_string(limits::kMaxPageMeshBytes >> 20) + " MB";
        return nullptr;
      }
      bytes_left -= bytes.size();
      return &(cache[path] = std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
    } catch (const InputError& e) {
      why = e.what();
      return nullptr;
    }
  }
};

std::string lowerExtension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

nlohmann::json origin(const ShapeOfLink& s) {
  return {s.position.x(), s.position.y(), s.position.z(), s.rotation.x(), s.rotation.y(), s.rotation.z(), s.rotation.w()};
}

struct Context {
  const RunFile& run;
  MeshReader& meshes;
};

// The visual of one shape; null with `problem` set when its mesh cannot be inlined.
nlohmann::json visual(const ShapeOfLink& shape, const char* source, Context& ctx, std::string& problem) {
  nlohmann::json v = {{"origin", origin(shape)}, {"source", source}};
  v["color"] = shape.color ? nlohmann::json{(*shape.color)[0], (*shape.color)[1], (*shape.color)[2], (*shape.color)[3]} : nlohmann::json();
  switch (shape.type) {
    case ShapeOfLink::Type::Box:
      v["type"] = "box";
      v["size"] = {shape.size.x(), shape.size.y(), shape.size.z()};
      return v;
    case ShapeOfLink::Type::Sphere:
      v["type"] = "sphere";
      v["radius"] = shape.radius;
      return v;
    case ShapeOfLink::Type::Cylinder:
      v["type"] = "cylinder";
      v["radius"] = shape.radius;
      v["length"] = shape.length;
      return v;
    case ShapeOfLink::Type::Mesh:
      break;
  }
  std::string path = shape.mesh_path;  // the run's own resolution first: it is where the run found it
  for (const auto& [file, resolved] : ctx.run.mesh_paths)
    if (file == shape.mesh_file && !resolved.empty() && pathExists(resolved)) path = resolved;
  const std::string format = lowerExtension(path.empty() ? shape.mesh_file : path);
  if (path.empty() || !pathExists(path)) {
    problem = "mesh " + shape.mesh_file + " is not found";
    return nullptr;
  }
  if (format != "stl" && format != "obj" && format != "dae") {
    problem = "mesh " + shape.mesh_file + " is a ." + format + " file (the page draws STL, OBJ and DAE)";
    return nullptr;
  }
  std::string why;
  const std::vector<std::uint8_t>* bytes = ctx.meshes.read(path, why);
  if (!bytes) {
    problem = "mesh " + shape.mesh_file + " cannot be inlined (" + why + ")";
    return nullptr;
  }
  v["type"] = "mesh";
  v["format"] = format;
  v["data"] = byteArray(*bytes, {bytes->size()});
  v["scale"] = {shape.mesh_scale.x(), shape.mesh_scale.y(), shape.mesh_scale.z()};
  return v;
}

// Every shape of a list as visuals; false (and `problem`) when one of them cannot be drawn.
bool visuals(const std::vector<ShapeOfLink>& shapes, const char* source, Context& ctx, nlohmann::json& out, std::string& problem) {
  out = nlohmann::json::array();
  for (const ShapeOfLink& shape : shapes) {
    nlohmann::json v = visual(shape, source, ctx, problem);
    if (v.is_null()) return false;
    out.push_back(std::move(v));
  }
  return true;
}

// A link's visuals: its <visual> shapes, else its <collision> shapes, else its inertia box.
nlohmann::json linkVisuals(const LinkAppearance& link, Context& ctx, std::vector<std::string>& warnings) {
  nlohmann::json out;
  std::string problem;
  if (!link.visuals.empty() && visuals(link.visuals, "visual", ctx, out, problem)) return out;
  const std::string visual_problem = problem;
  problem.clear();
  if (!link.collisions.empty() && visuals(link.collisions, "collision", ctx, out, problem)) {
    if (!visual_problem.empty()) warnings.push_back(visual_problem + ": link " + link.name + " is drawn from its collision shapes");
    return out;
  }
  out = nlohmann::json::array();
  if (link.inertia_box) {
    std::string none;
    out.push_back(visual(*link.inertia_box, "inertia", ctx, none));
  }
  const std::string why = !visual_problem.empty() ? visual_problem : problem;
  if (!why.empty())
    warnings.push_back(why + ": link " + link.name + (link.inertia_box ? " is drawn as the box of its mass and inertia" : " is not drawn"));
  return out;
}

// Pose rows x, y, z, qx, qy, qz, qw of L links, N × L × 7 in float32.
nlohmann::json poses(const Rows& position, const Rows& quaternion, size_t links) {
  const auto frames = static_cast<size_t>(position.rows());
  std::vector<float> values(frames * links * 7);
  for (size_t i = 0; i < frames; ++i)
    for (size_t l = 0; l < links; ++l) {
      float* out = &values[(i * links + l) * 7];
      for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(position(i, 3 * l + k));
      for (int k = 0; k < 4; ++k) out[3 + k] = static_cast<float>(quaternion(i, 4 * l + k));
    }
  return floatArray(values, {frames, links, 7});
}

}  // namespace

RobotPayload robotPayload(RunFile& run, std::uintmax_t& mesh_bytes_left) {
  RobotPayload out;
  MeshReader meshes{mesh_bytes_left, {}};
  Context ctx{run, meshes};
  std::optional<RobotAppearance> robot;
  if (run.urdf_text) {
    try {
      robot = readRobotAppearance(*run.urdf_text, run.urdf_path);
    } catch (const InputError& e) {
      run.warnings.push_back(run.name + ": its URDF cannot be read (" + e.what() + "): the trunk is drawn as a box");
    }
  }
  if (!robot) {
    ShapeOfLink box;
    box.size = Vec3(kFallbackTrunkSize[0], kFallbackTrunkSize[1], kFallbackTrunkSize[2]);
    std::string none;
    out.links.push_back({{"name", "trunk"}, {"visuals", nlohmann::json::array({visual(box, "inertia", ctx, none)})}});
    out.link_poses = poses(run.base_position, run.base_quaternion, 1);
    return out;
  }
  std::map<std::string, const LinkAppearance*> by_name;
  for (const LinkAppearance& link : robot->links) by_name[link.name] = &link;
  if (run.link_position) {
    for (const std::string& name : run.link_names) {
      const auto found = by_name.find(name);
      out.links.push_back({{"name", name},
                           {"visuals", found == by_name.end() ? nlohmann::json::array() : linkVisuals(*found->second, ctx, run.warnings)}});
    }
    out.link_poses = poses(*run.link_position, *run.link_quaternion, run.link_names.size());
  } else {
    const auto root = by_name.find(robot->root_link);
    out.links.push_back({{"name", robot->root_link},
                         {"visuals", root == by_name.end() ? nlohmann::json::array() : linkVisuals(*root->second, ctx, run.warnings)}});
    out.link_poses = poses(run.base_position, run.base_quaternion, 1);
  }
  return out;
}

}  // namespace nmdp::app
