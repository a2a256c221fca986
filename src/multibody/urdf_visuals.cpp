#include "multibody/urdf_visuals.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "multibody/urdf_loader.hpp"

namespace nmdp {

namespace {

// Collects urdfdom's complaints for one message instead of letting them reach stderr.
class QuietHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    std::string line = text;
    std::replace(line.begin(), line.end(), '\n', ' ');
    messages += (messages.empty() ? "" : "; ") + line;
  }
  std::string messages;
};

// Sizes beyond this (m) are not a robot's (urdf_loader bounds lengths the same way).
constexpr double kMaxLength = 1e3;

double checked(double value, const std::string& where, const std::string& element, const std::string& what) {
  if (!std::isfinite(value) || std::abs(value) > kMaxLength)
    throw InputError(where + ": " + element + ": " + what + " is not a finite number within " + std::to_string(kMaxLength));
  return value;
}

void placeShape(ShapeOfLink& shape, const urdf::Pose& origin, const std::string& where, const std::string& element) {
  shape.position = Vec3(checked(origin.position.x, where, element, "origin xyz"), checked(origin.position.y, where, element, "origin xyz"),
                        checked(origin.position.z, where, element, "origin xyz"));
  const Eigen::Quaterniond q(origin.rotation.w, origin.rotation.x, origin.rotation.y, origin.rotation.z);
  if (!q.coeffs().allFinite() || q.norm() == 0) throw InputError(where + ": " + element + ": origin rpy is not finite");
  shape.rotation = q.normalized();
}

// A shape from a URDF geometry; false for a geometry urdfdom left empty.
bool readGeometry(const urdf::Geometry* geometry, const std::string& urdf_dir, const std::string& where,
                  const std::string& element, ShapeOfLink& shape) {
  if (!geometry) return false;
  switch (geometry->type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(*geometry);
      shape.type = ShapeOfLink::Type::Box;
      shape.size = Vec3(checked(box.dim.x, where, element, "box size"), checked(box.dim.y, where, element, "box size"),
                        checked(box.dim.z, where, element, "box size"));
      return true;
    }
    case urdf::Geometry::SPHERE:
      shape.type = ShapeOfLink::Type::Sphere;
      shape.radius = checked(static_cast<const urdf::Sphere&>(*geometry).radius, where, element, "sphere radius");
      return true;
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(*geometry);
      shape.type = ShapeOfLink::Type::Cylinder;
      shape.radius = checked(cylinder.radius, where, element, "cylinder radius");
      shape.length = checked(cylinder.length, where, element, "cylinder length");
      return true;
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(*geometry);
      shape.type = ShapeOfLink::Type::Mesh;
      shape.mesh_file = mesh.filename;
      shape.mesh_path = urdf_dir.empty() && mesh.filename.rfind('/', 0) != 0 ? "" : resolveMeshFile(mesh.filename, urdf_dir);
      shape.mesh_scale = Vec3(checked(mesh.scale.x, where, element, "mesh scale"), checked(mesh.scale.y, where, element, "mesh scale"),
                              checked(mesh.scale.z, where, element, "mesh scale"));
      return true;
    }
  }
  return false;
}

std::optional<Eigen::Vector4d> colorOf(const urdf::Visual& visual, const urdf::ModelInterface& model) {
  urdf::MaterialSharedPtr material = visual.material;
  if (!visual.material_name.empty()) {  // a reference to a top-level <material>
    const auto named = model.materials_.find(visual.material_name);
    if (named != model.materials_.end() && (!material || material->color.a == 0)) material = named->second;
  }
  if (!material) return std::nullopt;
  const urdf::Color& c = material->color;
  const Eigen::Vector4d rgba(c.r, c.g, c.b, c.a);
  if (!rgba.allFinite() || (rgba.array() < 0).any() || (rgba.array() > 1).any() || rgba.isZero()) return std::nullopt;
  return rgba;
}

// The uniform box of mass m with the link's principal moments I1, I2, I3:
// I1 = m (b² + c²) / 12 and so on, so a² = 6 (I2 + I3 − I1) / m; a moment triple no box has
// (a negative square) is clamped to a thin plate.
std::optional<ShapeOfLink> inertiaBox(const urdf::Inertial& inertial) {
  const double m = inertial.mass;
  if (!std::isfinite(m) || m <= 0) return std::nullopt;
  Mat3 I;
  I << inertial.ixx, inertial.ixy, inertial.ixz, inertial.ixy, inertial.iyy, inertial.iyz, inertial.ixz, inertial.iyz, inertial.izz;
  if (!I.allFinite()) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(I);
  const Vec3 moments = eigen.eigenvalues();
  Mat3 axes = eigen.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  constexpr double kThinnest = 1e-3;  // m
  ShapeOfLink box;
  box.type = ShapeOfLink::Type::Box;
  for (int k = 0; k < 3; ++k) {
    const double square = 6.0 * (moments.sum() - 2.0 * moments[k]) / m;
    box.size[k] = std::clamp(std::sqrt(std::max(square, 0.0)), kThinnest, kMaxLength);
  }
  const urdf::Pose& o = inertial.origin;
  box.position = Vec3(o.position.x, o.position.y, o.position.z);
  const Eigen::Quaterniond frame(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z);
  if (!box.position.allFinite() || !frame.coeffs().allFinite() || frame.norm() == 0) return std::nullopt;
  box.rotation = (frame.normalized() * Eigen::Quaterniond(axes)).normalized();
  return box;
}

}  // namespace

RobotAppearance readRobotAppearance(const std::string& urdf_text, const std::string& urdf_path) {
  const std::string where = urdf_path.empty() ? std::string("the URDF") : urdf_path;
  QuietHandler handler;
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(urdf_text);
  } catch (const std::exception& e) {
    handler.messages += std::string(handler.messages.empty() ? "" : "; ") + e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) throw InputError(where + ": invalid URDF: " + (handler.messages.empty() ? "urdfdom rejected it" : handler.messages));
  if (model->links_.size() > static_cast<size_t>(limits::kMaxLinks))
    throw InputError(where + ": " + std::to_string(model->links_.size()) + " links, more than the " +
                     std::to_string(limits::kMaxLinks) + " a robot may have");
  const std::string urdf_dir = urdf_path.empty() ? "" : std::filesystem::path(urdf_path).parent_path().string();

  RobotAppearance robot;
  if (model->getRoot()) robot.root_link = model->getRoot()->name;
  std::vector<urdf::LinkSharedPtr> links;
  model->getLinks(links);
  // urdfdom keeps links in a map (sorted by name): the root first, then by name, is stable.
  std::stable_partition(links.begin(), links.end(), [&](const urdf::LinkSharedPtr& l) { return l->name == robot.root_link; });
  for (const urdf::LinkSharedPtr& link : links) {
    LinkAppearance out;
    out.name = link->name;
    const std::string element = "<link name=\"" + link->name + "\">";
    for (const urdf::VisualSharedPtr& visual : link->visual_array) {
      if (!visual) continue;
      ShapeOfLink shape;
      if (!readGeometry(visual->geometry.get(), urdf_dir, where, element + " <visual>", shape)) continue;
      placeShape(shape, visual->origin, where, element + " <visual>");
      shape.color = colorOf(*visual, *model);
      out.visuals.push_back(shape);
    }
    for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
      if (!collision) continue;
      ShapeOfLink shape;
      if (!readGeometry(collision->geometry.get(), urdf_dir, where, element + " <collision>", shape)) continue;
      placeShape(shape, collision->origin, where, element + " <collision>");
      out.collisions.push_back(shape);
    }
    if (link->inertial) out.inertia_box = inertiaBox(*link->inertial);
    robot.links.push_back(std::move(out));
  }
  return robot;
}

}  // namespace nmdp
