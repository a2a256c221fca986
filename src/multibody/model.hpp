// The immutable description of an articulated robot, built once by the URDF loader.
//
// Every movable degree of freedom owns one *body* (after fixed and locked joints are merged).
// A floating base is six massless-until-the-last virtual bodies (x, y, z translations, then three
// rotations about the axes of a reference orientation kept in Data::base_chart); a planar base is
// three (x, z, pitch). Bodies are stored depth first, so the subtree of body i is the index range
// [i, subtree_end[i]) and a parent always precedes its children.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "common/named_enum.hpp"
#include "multibody/spatial.hpp"

namespace nmdp {

enum class BaseType { Floating, Planar, Fixed };
inline constexpr EnumName<BaseType> kBaseTypes[] = {
    {BaseType::Floating, "floating"}, {BaseType::Planar, "planar"}, {BaseType::Fixed, "fixed"}};
enum class JointKind { Revolute, Prismatic };

const char* baseTypeName(BaseType b);

// A collision shape of a URDF link, kept for foot detection and (later) contact set-up.
struct CollisionGeometry {
  enum class Shape { Sphere, Box, Cylinder, Mesh };
  Shape shape = Shape::Sphere;
  Mat3 rotation = Mat3::Identity();  // in the link frame
  Vec3 translation = Vec3::Zero();
  double radius = 0.0;               // sphere, cylinder
  double length = 0.0;               // cylinder (along its local z)
  Vec3 size = Vec3::Zero();          // box edge lengths
  std::string mesh_file;             // resolved absolute path ("" if it could not be resolved)
  Vec3 mesh_scale = Vec3::Ones();
};

// One URDF link. Links merged by fixed or locked joints share a body; `placement` is the link
// frame expressed in its body's frame. body == -1 means the link is welded to the world (fixed base).
struct Link {
  std::string name;
  int body = -1;
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  double mass = 0.0;                  // this link's own mass (before merging)
  int parent_link = -1;               // URDF tree parent, -1 for the root
  std::string parent_joint;           // name of the URDF joint from the parent ("" for the root)
  bool parent_joint_movable = false;  // revolute/continuous/prismatic and not locked
  std::vector<int> child_links;
  std::vector<CollisionGeometry> collisions;
};

struct Body {
  std::string name;        // the URDF link that carries this body's frame, or "base_x" etc.
  std::string joint_name;  // name of the degree of freedom
  int parent = -1;         // -1: the world
  JointKind kind = JointKind::Revolute;
  Vec3 axis = Vec3::UnitZ();  // unit joint axis in the body frame
  // Body frame at q = 0, relative to the parent body frame.
  Mat3 placement_rotation = Mat3::Identity();
  Vec3 placement_translation = Vec3::Zero();
  bool uses_base_chart = false;  // placement rotation is Data::base_chart (first floating rotation)
  bool is_base = false;          // one of the virtual base degrees of freedom
  // Merged inertia in the body frame.
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Mat3 inertia_com = Mat3::Zero();
  Mat4 second_moment = Mat4::Zero();  // [[∫ρxxᵀ, m c], [m cᵀ, m]] in the body frame
  double armature = 0.0;
  // Position limits of the URDF joint (rad or m; revolute and prismatic joints with lower < upper,
  // else unlimited): used by leg inverse kinematics, not by the dynamics.
  double lower_limit = -std::numeric_limits<double>::infinity();
  double upper_limit = std::numeric_limits<double>::infinity();

  // False for the massless virtual base bodies: their world inertia, momentum and inertia rate
  // are zero, which the dynamics algorithms skip.
  bool hasInertia() const { return mass > 0.0 || !inertia_com.isZero(0.0); }
};

struct Model {
  std::string source;  // file the model was loaded from
  std::string robot_name;
  BaseType base = BaseType::Floating;
  int nq = 0;  // == number of bodies == number of velocity coordinates
  std::vector<Body> bodies;
  std::vector<int> subtree_end;
  std::vector<Link> links;  // every URDF link, the root first
  int root_link = 0;
  int root_body = -1;  // body carrying the root link (-1 for a fixed base)
  // Inertia welded to the world (fixed base): counts in total_mass, not in the dynamics.
  Mat4 world_second_moment = Mat4::Zero();
  std::vector<std::string> dof_names;  // = bodies[i].joint_name
  Vec3 gravity = Vec3(0, 0, -9.81);
  double total_mass = 0.0;

  int nv() const { return nq; }
  // -1 when absent.
  int linkIndex(const std::string& name) const;
  int dofIndex(const std::string& name) const;
  bool isAncestor(int ancestor, int body) const {  // ancestor-or-self
    return ancestor <= body && body < subtree_end[ancestor];
  }
};

}  // namespace nmdp
