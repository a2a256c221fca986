#include "multibody/urdf_loader.hpp"

#include <tinyxml.h>

#include <algorithm>
#include <cmath>
#include <console_bridge/console.h>
#include <filesystem>
#include <cstring>
#include <map>
#include <set>
#include <urdf_parser/urdf_parser.h>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"
#include "common/utf8.hpp"
#include "multibody/urdf_joint_graph.hpp"
#include "multibody/crba.hpp"
#include "multibody/data.hpp"

namespace nmdp {
namespace fs = std::filesystem;

BaseType parseBaseType(const std::string& name) {
  if (name == "floating") return BaseType::Floating;
  if (name == "planar") return BaseType::Planar;
  if (name == "fixed") return BaseType::Fixed;
  throw InputError("unknown base type '" + name + "' (valid: floating, planar, fixed)");
}

namespace {

// Collects what urdfdom reports through console_bridge so it can go into one error message.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!messages.empty()) messages += "; ";
      std::string line = text;  // the CLI promises a one-line message
      std::replace(line.begin(), line.end(), '\n', ' ');
      messages += line;
    }
    // urdfdom 3 logs some errors (e.g. a non-numeric mass or inertia) and still returns a model
    // with the value left at 0, so any logged error must fail the load.
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) error = true;
  }
  std::string messages;
  bool error = false;
};

struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  Pose operator*(const Pose& o) const { return {R * o.R, R * o.t + t}; }
};

Pose toPose(const urdf::Pose& p) {
  Pose out;
  out.R = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  out.t = Vec3(p.position.x, p.position.y, p.position.z);
  return out;
}

Mat4 homogeneous(const Pose& p) {
  Mat4 X = Mat4::Identity();
  X.topLeftCorner<3, 3>() = p.R;
  X.topRightCorner<3, 1>() = p.t;
  return X;
}

std::string linkElement(const std::string& link) { return "<link name=\"" + link + "\">"; }
std::string jointElement(const std::string& joint) { return "<joint name=\"" + joint + "\">"; }

bool isMovable(int type) {
  return type == urdf::Joint::REVOLUTE || type == urdf::Joint::CONTINUOUS || type == urdf::Joint::PRISMATIC;
}

// Resolves package://pkg/a/b/c and relative mesh paths against the URDF's folder and its parents,
// dropping leading path components until a file exists (packages are rarely installed where the
// URDF author had them).
std::string resolveMesh(const std::string& filename, const fs::path& urdf_dir) {
  std::string rest = filename;
  bool is_package = false;
  if (rest.rfind("package://", 0) == 0) {
    rest = rest.substr(10);
    is_package = true;
  } else if (rest.rfind("file://", 0) == 0) {
    rest = rest.substr(7);
  }
  fs::path rel(rest);
  if (rel.is_absolute()) return fs::exists(rel) ? rel.string() : "";
  std::vector<fs::path> parts(rel.begin(), rel.end());
  for (fs::path dir = urdf_dir;; dir = dir.parent_path()) {
    for (size_t skip = 0; skip < parts.size(); ++skip) {
      if (!is_package && skip > 0) break;
      fs::path candidate = dir;
      for (size_t i = skip; i < parts.size(); ++i) candidate /= parts[i];
      std::error_code ec;
      if (fs::is_regular_file(candidate, ec)) return fs::weakly_canonical(candidate).string();
    }
    if (dir == dir.parent_path() || dir.empty()) break;
  }
  return "";
}

void requireFinite(double value, const std::string& file, const std::string& element, const std::string& what) {
  if (!std::isfinite(value))
    throw InputError(file + ": " + element + ": " + what + " is not a finite number");
}

// Bounds of a URDF's numbers, far beyond any robot (the heaviest link of RoboSimian is 13 kg, its
// longest offset 0.4 m) and keeping the dynamics finite: masses (kg), inertias (kg m²), lengths (m).
constexpr double kMaxMass = 1e6;
constexpr double kMaxInertia = 1e6;
constexpr double kMaxLength = 1e3;

void requireWithin(double value, double bound, const std::string& file, const std::string& element, const std::string& what) {
  requireFinite(value, file, element, what);
  if (std::abs(value) > bound)
    throw InputError(file + ": " + element + ": " + what + " " + std::to_string(value) + " is beyond " + std::to_string(bound));
}

void requirePose(const urdf::Pose& p, const std::string& file, const std::string& element) {
  for (double v : {p.position.x, p.position.y, p.position.z})
    requireWithin(v, kMaxLength, file, element + " <origin>", "xyz");
  for (double v : {p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w})
    requireFinite(v, file, element + " <origin>", "rpy");
}

// The deepest element nesting of an XML text, counted before TinyXML parses it: TinyXML recurses
// once per level, so a file nested 10^5 deep would overflow the stack. Comments, CDATA, declarations
// and quoted attribute values are skipped as TinyXML skips them. Returns the offset of the first
// element deeper than limits::kMaxXmlDepth, or npos.
size_t firstTooDeepElement(const std::string& xml) {
  int depth = 0;
  size_t i = 0;
  const auto skipPast = [&](const char* end) {
    const size_t at = xml.find(end, i);
    i = at == std::string::npos ? xml.size() : at + std::strlen(end);
  };
  while ((i = xml.find('<', i)) != std::string::npos) {
    const size_t start = i;
    if (xml.compare(i, 4, "<!--") == 0) {
      skipPast("-->");
    } else if (xml.compare(i, 9, "<![CDATA[") == 0) {
      skipPast("]]>");
    } else if (xml.compare(i, 2, "<!") == 0 || xml.compare(i, 2, "<?") == 0) {
      skipPast(">");
    } else if (xml.compare(i, 2, "</") == 0) {
      --depth;
      skipPast(">");
    } else {
      char quote = 0, previous = 0;
      for (++i; i < xml.size(); ++i) {
        const char c = xml[i];
        if (quote) {
          if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
          quote = c;
        } else if (c == '>') {
          break;
        }
        if (!quote && c != ' ' && c != '\t' && c != '\n' && c != '\r') previous = c;
      }
      const bool self_closing = previous == '/';
      if (!self_closing && ++depth > limits::kMaxXmlDepth) return start;
      ++i;
    }
  }
  return std::string::npos;
}

int lineOf(const std::string& text, size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(std::min(offset, text.size())), '\n'));
}

class Builder {
 public:
  Builder(const std::string& path, const UrdfOptions& options) : path_(path), options_(options) {}

  Model build() {
    const std::string xml = readInputFile(path_, "URDF file");
    const std::vector<std::string> joint_order = prescan(xml);
    urdf::ModelInterfaceSharedPtr urdf = parse(xml);
    checkTree(*urdf);

    for (size_t i = 0; i < joint_order.size(); ++i) joint_rank_[joint_order[i]] = static_cast<int>(i);
    for (const auto& [name, value] : options_.locked_joints) {
      auto joint = urdf->getJoint(name);
      if (!joint) throw InputError(path_ + ": locked joint '" + name + "' does not exist (joints: " + listJoints(*urdf) + ")");
      if (!isMovable(joint->type)) throw InputError(path_ + ": locked joint '" + name + "' is not a movable joint");
      if (!std::isfinite(value)) throw InputError(path_ + ": locked joint '" + name + "': value is not a finite number");
    }
    for (const auto& [name, value] : options_.armature) {
      auto joint = urdf->getJoint(name);
      if (!joint || !isMovable(joint->type))
        throw InputError(path_ + ": armature given for '" + name + "', which is not a movable joint (joints: " + listJoints(*urdf) + ")");
      if (!(value >= 0.0) || !std::isfinite(value)) throw InputError(path_ + ": armature of '" + name + "' must be a finite value >= 0");
    }

    model_.source = path_;
    model_.robot_name = urdf->getName();
    model_.base = options_.base;
    model_.gravity = options_.gravity;
    addBaseBodies();

    urdf::LinkConstSharedPtr root = urdf->getRoot();
    if (!root) throw InputError(path_ + ": the URDF has no root link");
    visitTree(*urdf, root);
    finish();
    return std::move(model_);
  }

 private:
  // TinyXML first, so a malformed file or an unknown joint type is reported with its line and
  // element instead of urdfdom's generic failure. Returns the joint names in file order.
  std::vector<std::string> prescan(const std::string& xml) {
    if (xml.find('\0') != std::string::npos)
      throw InputError(path_ + ":" + std::to_string(lineOf(xml, xml.find('\0'))) + ": a NUL byte: this is not an XML text file");
    if (const size_t deep = firstTooDeepElement(xml); deep != std::string::npos)
      throw InputError(path_ + ":" + std::to_string(lineOf(xml, deep)) + ": malformed URDF: elements nested more than " +
                       std::to_string(limits::kMaxXmlDepth) + " levels deep");
    TiXmlDocument doc;
    doc.Parse(xml.c_str());
    if (doc.Error())
      throw InputError(path_ + ":" + std::to_string(doc.ErrorRow()) + ": malformed XML: " + doc.ErrorDesc());
    TiXmlElement* robot = doc.FirstChildElement("robot");
    if (!robot) throw InputError(path_ + ": no <robot> element: this is not a URDF file");
    int links = 0, joints = 0;
    for (TiXmlElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) ++links;
    for (TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) ++joints;
    if (links > limits::kMaxLinks || joints > limits::kMaxJoints)
      throw InputError(path_ + ": " + std::to_string(links) + " links and " + std::to_string(joints) +
                       " joints, more than the " + std::to_string(limits::kMaxLinks) + " links and " +
                       std::to_string(limits::kMaxJoints) + " joints a robot may have");
    checkUrdfJointGraph(*robot, path_);
    static const std::set<std::string> known = {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"};
    std::vector<std::string> order;
    for (TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
      const char* name = j->Attribute("name");
      const char* type = j->Attribute("type");
      const std::string element = jointElement(name ? name : "?") + " (line " + std::to_string(j->Row()) + ")";
      if (!name) throw InputError(path_ + ": <joint> at line " + std::to_string(j->Row()) + " has no name");
      if (!type) throw InputError(path_ + ": " + element + " has no type (valid: revolute, continuous, prismatic, fixed)");
      if (!known.count(type))
        throw InputError(path_ + ": " + element + ": unknown joint type \"" + type +
                         "\" (valid: revolute, continuous, prismatic, fixed)");
      if (std::string(type) == "floating" || std::string(type) == "planar")
        throw InputError(path_ + ": " + element + ": joint type \"" + type +
                         "\" inside the robot is not supported; choose the base with --base floating|planar|fixed");
      order.push_back(name);
    }
    return order;
  }

  urdf::ModelInterfaceSharedPtr parse(const std::string& xml) {
    CapturingHandler handler;
    console_bridge::useOutputHandler(&handler);
    urdf::ModelInterfaceSharedPtr urdf;
    try {
      urdf = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      handler.messages += std::string(handler.messages.empty() ? "" : "; ") + e.what();
    }
    console_bridge::restorePreviousOutputHandler();
    if (!urdf || handler.error) throw InputError(path_ + ": invalid URDF: " + (handler.messages.empty() ? "urdfdom rejected it" : handler.messages));
    return urdf;
  }

  static std::string listJoints(const urdf::ModelInterface& urdf) {
    std::string out;
    for (const auto& [name, joint] : urdf.joints_)
      if (isMovable(joint->type)) out += (out.empty() ? "" : ", ") + name;
    return out.empty() ? "none" : out;
  }

  int addBody(const std::string& name, const std::string& joint, int parent, JointKind kind, const Vec3& axis, const Pose& placement) {
    Body b;
    b.name = name;
    b.joint_name = joint;
    b.parent = parent;
    b.kind = kind;
    b.axis = axis;
    b.placement_rotation = placement.R;
    b.placement_translation = placement.t;
    model_.bodies.push_back(b);
    return static_cast<int>(model_.bodies.size()) - 1;
  }

  void addBaseBodies() {
    int parent = -1;
    auto add = [&](const char* name, JointKind kind, const Vec3& axis) {
      parent = addBody(name, name, parent, kind, axis, Pose{});
      model_.bodies.back().is_base = true;
    };
    if (options_.base == BaseType::Floating) {
      add("base_x", JointKind::Prismatic, Vec3::UnitX());
      add("base_y", JointKind::Prismatic, Vec3::UnitY());
      add("base_z", JointKind::Prismatic, Vec3::UnitZ());
      add("base_roll", JointKind::Revolute, Vec3::UnitX());
      model_.bodies.back().uses_base_chart = true;
      add("base_pitch", JointKind::Revolute, Vec3::UnitY());
      add("base_yaw", JointKind::Revolute, Vec3::UnitZ());
    } else if (options_.base == BaseType::Planar) {
      add("base_x", JointKind::Prismatic, Vec3::UnitX());
      add("base_z", JointKind::Prismatic, Vec3::UnitZ());
      add("base_pitch", JointKind::Revolute, Vec3::UnitY());
    }
    model_.root_body = parent;
  }

  // Before the tree is walked: names and numbers (the joint graph was checked in the prescan; the
  // two-parent check stays here because urdfdom's own model is what the walk follows).
  void checkTree(const urdf::ModelInterface& urdf) {
    if (!isValidUtf8(urdf.getName())) throw InputError(path_ + ": the robot's name is not UTF-8 text");
    for (const auto& [name, link] : urdf.links_)
      if (name.empty() || !isValidUtf8(name)) throw InputError(path_ + ": a <link> name is empty or not UTF-8 text");
    std::map<std::string, std::string> parent_joint_of;  // child link → joint
    for (const auto& [name, joint] : urdf.joints_) {
      const std::string element = jointElement(name);
      if (name.empty() || !isValidUtf8(name)) throw InputError(path_ + ": a <joint> name is empty or not UTF-8 text");
      if (joint->child_link_name == joint->parent_link_name)
        throw InputError(path_ + ": " + element + ": its parent and child are the same link '" + joint->child_link_name + "'");
      const auto [it, first] = parent_joint_of.emplace(joint->child_link_name, name);
      if (!first)
        throw InputError(path_ + ": link '" + joint->child_link_name + "' is the child of two joints, " + jointElement(it->second) +
                         " and " + element + ": a URDF is a tree (each link has at most one parent joint)");
      requirePose(joint->parent_to_joint_origin_transform, path_, element);
      if (joint->limits) {
        for (double v : {joint->limits->lower, joint->limits->upper, joint->limits->effort, joint->limits->velocity})
          requireFinite(v, path_, element + " <limit>", "lower, upper, effort and velocity");
      }
    }
  }

  // Depth first from the root, in the joints' file order: bodies come out in preorder (a parent
  // before its children, each subtree contiguous). An explicit stack, so a long chain cannot
  // overflow the call stack.
  struct Visit {
    urdf::LinkConstSharedPtr link;
    int parent_link = -1;
    int body = -1;           // the body the link belongs to (created when the visit is taken)
    Pose placement;          // link frame in that body's frame
    urdf::JointConstSharedPtr joint;  // the movable joint that creates `body`, or null
    Vec3 axis = Vec3::UnitZ();
  };

  void visitTree(const urdf::ModelInterface& urdf, const urdf::LinkConstSharedPtr& root) {
    std::vector<Visit> stack;
    stack.push_back({root, -1, model_.root_body, Pose{}, nullptr, Vec3::UnitZ()});
    std::set<std::string> visited;
    while (!stack.empty()) {
      Visit v = std::move(stack.back());
      stack.pop_back();
      if (!visited.insert(v.link->name).second)
        throw InputError(path_ + ": link '" + v.link->name + "' is reached twice from the root: the joints form a cycle");
      if (v.joint) {  // a movable joint: its body now, so bodies are numbered in preorder
        v.body = addBody(v.link->name, v.joint->name, v.body, v.joint->type == urdf::Joint::PRISMATIC ? JointKind::Prismatic : JointKind::Revolute,
                         v.axis, v.placement);
        Body& b = model_.bodies[v.body];
        auto arm = options_.armature.find(v.joint->name);
        b.armature = arm != options_.armature.end() ? arm->second : options_.default_armature;
        if (v.joint->limits && (v.joint->type == urdf::Joint::REVOLUTE || v.joint->type == urdf::Joint::PRISMATIC) &&
            v.joint->limits->lower < v.joint->limits->upper) {  // URDF's "no limit" is 0, 0
          b.lower_limit = v.joint->limits->lower;
          b.upper_limit = v.joint->limits->upper;
        }
        v.placement = Pose{};
      }
      const int index = addLink(*v.link, v.parent_link, v.body, v.placement);

      std::vector<urdf::JointSharedPtr> joints = v.link->child_joints;
      std::sort(joints.begin(), joints.end(), [&](const auto& a, const auto& b) { return joint_rank_[a->name] < joint_rank_[b->name]; });
      for (auto it = joints.rbegin(); it != joints.rend(); ++it) {  // reversed: the first joint is taken first
        const urdf::JointSharedPtr& joint = *it;
        urdf::LinkConstSharedPtr child = urdf.getLink(joint->child_link_name);
        if (!child) throw InputError(path_ + ": " + jointElement(joint->name) + ": child link '" + joint->child_link_name + "' does not exist");
        const Pose origin = v.placement * toPose(joint->parent_to_joint_origin_transform);
        Vec3 axis(joint->axis.x, joint->axis.y, joint->axis.z);
        if (isMovable(joint->type)) {
          requireFinite(axis.x() + axis.y() + axis.z(), path_, jointElement(joint->name) + " <axis>", "xyz");
          if (axis.norm() < 1e-12) throw InputError(path_ + ": " + jointElement(joint->name) + " <axis>: the axis is zero");
          axis.normalize();
        }
        auto locked = options_.locked_joints.find(joint->name);
        if (!isMovable(joint->type) || locked != options_.locked_joints.end()) {
          Pose motion;
          if (locked != options_.locked_joints.end()) {
            if (joint->type != urdf::Joint::PRISMATIC) motion.R = rotationAbout(axis, locked->second);
            else motion.t = axis * locked->second;
          }
          stack.push_back({child, index, v.body, origin * motion, nullptr, axis});
        } else {
          stack.push_back({child, index, v.body, origin, joint, axis});
        }
      }
    }
    if (visited.size() != urdf.links_.size()) {
      std::string unreachable;
      for (const auto& [name, link] : urdf.links_)
        if (!visited.count(name)) unreachable += (unreachable.empty() ? "'" : ", '") + name + "'";
      throw InputError(path_ + ": links " + unreachable + " are not connected to the root link '" + root->name +
                       "': a URDF is one tree");
    }
  }

  // The link's own record (collision shapes, placement in its body) and inertia; returns its index.
  int addLink(const urdf::Link& link, int parent_link, int body, const Pose& placement) {
    checkInertial(link);
    Link out;
    out.name = link.name;
    out.body = body;
    out.rotation = placement.R;
    out.translation = placement.t;
    out.parent_link = parent_link;
    if (link.inertial) out.mass = link.inertial->mass;
    if (auto joint = link.parent_joint) {
      out.parent_joint = joint->name;
      out.parent_joint_movable = isMovable(joint->type) && !options_.locked_joints.count(joint->name);
    }
    const fs::path dir = fs::path(path_).parent_path();
    const std::string element = linkElement(link.name) + " <collision>";
    for (const auto& c : link.collision_array) {
      if (!c || !c->geometry) continue;
      requirePose(c->origin, path_, element);
      CollisionGeometry g;
      const Pose origin = toPose(c->origin);
      g.rotation = origin.R;
      g.translation = origin.t;
      switch (c->geometry->type) {
        case urdf::Geometry::SPHERE:
          g.shape = CollisionGeometry::Shape::Sphere;
          g.radius = static_cast<const urdf::Sphere&>(*c->geometry).radius;
          requireSize(g.radius, element + " <sphere>", "radius");
          break;
        case urdf::Geometry::BOX: {
          const auto& b = static_cast<const urdf::Box&>(*c->geometry);
          g.shape = CollisionGeometry::Shape::Box;
          g.size = Vec3(b.dim.x, b.dim.y, b.dim.z);
          for (int k = 0; k < 3; ++k) requireSize(g.size[k], element + " <box>", "size");
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& cy = static_cast<const urdf::Cylinder&>(*c->geometry);
          g.shape = CollisionGeometry::Shape::Cylinder;
          g.radius = cy.radius;
          g.length = cy.length;
          requireSize(g.radius, element + " <cylinder>", "radius");
          requireSize(g.length, element + " <cylinder>", "length");
          break;
        }
        case urdf::Geometry::MESH: {
          const auto& m = static_cast<const urdf::Mesh&>(*c->geometry);
          g.shape = CollisionGeometry::Shape::Mesh;
          g.mesh_file = resolveMesh(m.filename, dir);
          g.mesh_scale = Vec3(m.scale.x, m.scale.y, m.scale.z);
          for (int k = 0; k < 3; ++k) requireWithin(g.mesh_scale[k], kMaxLength, path_, element + " <mesh>", "scale");
          break;
        }
      }
      out.collisions.push_back(g);
    }
    const int index = static_cast<int>(model_.links.size());
    model_.links.push_back(out);
    if (parent_link >= 0) model_.links[parent_link].child_links.push_back(index);
    addInertia(link, body, placement);
    return index;
  }

  void requireSize(double value, const std::string& element, const std::string& what) {
    requireWithin(value, kMaxLength, path_, element, what);
    if (value < 0) throw InputError(path_ + ": " + element + ": " + what + " is negative");
  }

  void checkInertial(const urdf::Link& link) {
    if (!link.inertial) return;
    const urdf::Inertial& in = *link.inertial;
    const std::string el = linkElement(link.name) + " <inertial>";
    requireWithin(in.mass, kMaxMass, path_, el + " <mass>", "value");
    if (in.mass < 0) throw InputError(path_ + ": " + el + " <mass>: value is negative");
    const double values[6] = {in.ixx, in.ixy, in.ixz, in.iyy, in.iyz, in.izz};
    const char* names[6] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
    for (int i = 0; i < 6; ++i) requireWithin(values[i], kMaxInertia, path_, el + " <inertia>", names[i]);
    requirePose(in.origin, path_, el);
    Mat3 I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Vec3 eig = Eigen::SelfAdjointEigenSolver<Mat3>(I).eigenvalues();
    const double tol = 1e-9 * std::max(1.0, I.norm());
    if (eig.minCoeff() < -tol) throw InputError(path_ + ": " + el + " <inertia>: the inertia matrix is not positive semi-definite");
  }

  void addInertia(const urdf::Link& link, int body, const Pose& placement) {
    if (!link.inertial) return;
    const urdf::Inertial& in = *link.inertial;
    const Pose inertial = toPose(in.origin);
    Mat3 Icom;
    Icom << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const double m = in.mass;
    Mat4 Mbar = Mat4::Zero();
    Mbar.topLeftCorner<3, 3>() = inertial.R * (0.5 * Icom.trace() * Mat3::Identity() - Icom) * inertial.R.transpose() +
                                 m * inertial.t * inertial.t.transpose();
    Mbar.topRightCorner<3, 1>() = m * inertial.t;
    Mbar.bottomLeftCorner<1, 3>() = m * inertial.t.transpose();
    Mbar(3, 3) = m;
    const Mat4 X = homogeneous(placement);
    if (body < 0) model_.world_second_moment += X * Mbar * X.transpose();
    else model_.bodies[body].second_moment += X * Mbar * X.transpose();
    model_.total_mass += m;
  }

  void finish() {
    Model& m = model_;
    m.nq = static_cast<int>(m.bodies.size());
    m.subtree_end.assign(m.nq, 0);
    for (int i = m.nq - 1; i >= 0; --i) {
      m.subtree_end[i] = std::max(m.subtree_end[i], i + 1);
      if (m.bodies[i].parent >= 0) m.subtree_end[m.bodies[i].parent] = std::max(m.subtree_end[m.bodies[i].parent], m.subtree_end[i]);
    }
    m.dof_names.clear();
    for (Body& b : m.bodies) {
      m.dof_names.push_back(b.joint_name);
      const Mat4& M = b.second_moment;
      b.mass = M(3, 3);
      if (b.mass > 0) {
        b.com = M.topRightCorner<3, 1>() / b.mass;
        const Mat3 S = M.topLeftCorner<3, 3>() - b.mass * b.com * b.com.transpose();  // about the com
        b.inertia_com = S.trace() * Mat3::Identity() - S;
      } else {
        b.com.setZero();
        const Mat3 S = M.topLeftCorner<3, 3>();
        b.inertia_com = S.trace() * Mat3::Identity() - S;
      }
    }
    if (m.nq == 0) return;
    // A movable joint whose motion carries no mass or inertia makes H singular.
    Data data(m);
    crba(m, data, Eigen::VectorXd::Zero(m.nq));
    const double scale = data.H.diagonal().maxCoeff();
    for (int i = 0; i < m.nq; ++i) {
      if (data.H(i, i) > 1e-12 * std::max(scale, 1e-300)) continue;
      const Body& b = m.bodies[i];
      if (b.is_base)
        throw InputError(path_ + ": the robot has no mass or inertia, so its " + baseTypeName(m.base) + " base cannot move");
      throw InputError(path_ + ": " + jointElement(b.joint_name) +
                       ": moves no mass or inertia (everything beyond it is massless), so the mass matrix would be singular; "
                       "lock it (--lock " + b.joint_name + "=0) or give it an armature");
    }
  }

  std::string path_;
  UrdfOptions options_;
  Model model_;
  std::map<std::string, int> joint_rank_;
};

}  // namespace

Model loadUrdf(const std::string& path, const UrdfOptions& options) { return Builder(path, options).build(); }

std::string resolveMeshFile(const std::string& filename, const std::string& urdf_dir) {
  return resolveMesh(filename, fs::path(urdf_dir));
}

}  // namespace nmdp
