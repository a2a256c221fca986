// The start pose of a scene's robot: joints by name, the standing pose a quadruped's gait solves
// by inverse kinematics, the base pose and velocity, and the default height on the terrain.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/text.hpp"
#include "config/json_params.hpp"
#include "multibody/base_chart.hpp"
#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "sim/scene_parts.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp {
namespace scene_detail {


// The coordinate index of an actuated joint; InputError naming `w` otherwise.
int actuatedIndex(const Model& model, const SceneConfig& c, const std::string& joint, const Where& w) {
  const int i = model.dofIndex(joint);
  if (i >= 0 && !model.bodies[i].is_base) return i;
  if (c.locked_joints.count(joint)) w.fail("joint '" + joint + "' is locked (robot.locked_joints); it has no coordinate");
  std::vector<std::string> names;
  for (int k = 0; k < model.nq; ++k)
    if (!model.bodies[k].is_base) names.push_back(model.dof_names[k]);
  w.fail("the robot (" + model.source + ") has no actuated joint '" + joint + "'" + suggestion(joint, names) +
         "; its joints: " + join(names));
}

void checkJointNames(const Model& model, const SceneConfig& c, const JointValues& values, const Where& w) {
  for (const auto& [name, value] : values) actuatedIndex(model, c, name, w / name);
}

int linkIndexOrThrow(const Model& model, const std::string& link, const Where& w) {
  const int i = model.linkIndex(link);
  if (i >= 0) return i;
  std::vector<std::string> names;
  for (const Link& l : model.links) names.push_back(l.name);
  w.fail("the robot (" + model.source + ") has no link '" + link + "'" + suggestion(link, names));
}

namespace {
Standing standingFrom(const Model& model, const StandParameters& stand) {
  Standing out;
  try {
    const QuadrupedLegs legs = identifyQuadrupedLegs(model, stand.nominal_q);
    out.quadruped = true;
    out.pose = standingPose(model, legs, stand);
  } catch (const std::invalid_argument& e) {
    out.error = e.what();
  }
  return out;
}
}  // namespace

// The built-in gaits' stand parameters: controller.gait.height, and robot.initial.joints as the
// nominal pose (StandParameters::nominal_q), its unlisted joints as in the standing pose without it
// (0 if there is none). A robot whose legs do not hang under it at q = 0 (RoboSimian's stretch out
// level) needs this bent pose to stand. Keyframes start from the default standing pose instead:
// there robot.initial.joints only overrides the first frame.
StandParameters standParameters(const SceneConfig& c, const Model& model) {
  StandParameters stand = c.gait.stand;
  if (c.gait_type == SceneGaitType::Keyframes || c.initial_joints.empty()) return stand;
  const Where wj{fileOf(c), "robot.initial.joints"};
  size_t actuated = 0;
  for (int i = 0; i < model.nq; ++i) actuated += !model.bodies[i].is_base;
  Eigen::VectorXd nominal = Eigen::VectorXd::Zero(model.nq);
  if (c.initial_joints.size() < actuated) {
    const Standing fill = standingFrom(model, c.gait.stand);
    if (fill.pose) nominal = fill.pose->q;
  }
  for (const auto& [name, value] : c.initial_joints) nominal[actuatedIndex(model, c, name, wj / name)] = value;
  stand.nominal_q = nominal;
  return stand;
}

Standing standing(const SceneConfig& c, const Model& model) { return standingFrom(model, standParameters(c, model)); }

// The message for a built-in gait whose standing pose cannot be built.
std::string standingFailure(const SceneConfig& c, const Standing& s) {
  std::string what = std::string("gait type '") + sceneGaitTypeName(c.gait_type) + "' cannot be built: " + s.error;
  if (s.quadruped && c.initial_joints.empty())
    what += "; give the nominal standing pose (legs bent under the trunk) in robot.initial.joints";
  return what;
}

// The pose the coordinates a keyframe file does not list hold: standing pose, or q = 0.
Eigen::VectorXd holdPose(const SceneConfig& c, const Model& model) {
  const Standing s = standing(c, model);
  if (s.pose) return s.pose->q;
  return Eigen::VectorXd::Zero(model.nq);
}

// Writes the base coordinates of q (or q̇) from a world translation and rotation vector triple.
void setBase(const Model& model, const Vec3& translation, const Vec3& angles, Eigen::VectorXd& q) {
  for (int i = 0; i < model.nq; ++i) {
    const Body& b = model.bodies[i];
    if (!b.is_base) continue;
    int axis = 0;
    for (int k = 0; k < 3; ++k)
      if (std::abs(b.axis[k]) > 0.5) axis = k;
    q[i] = b.kind == JointKind::Prismatic ? translation[axis] : angles[axis];
  }
}

int verticalBaseIndex(const Model& model) {
  for (int i = 0; i < model.nq; ++i)
    if (model.bodies[i].is_base && model.bodies[i].kind == JointKind::Prismatic && std::abs(model.bodies[i].axis.z()) > 0.5)
      return i;
  return -1;
}

// The start pose's joints (the base is set by the caller): a built-in gait's standing pose, solved
// from robot.initial.joints (standParameters); otherwise the first keyframe, or q = 0, with the
// joints of robot.initial.joints set as given.
Eigen::VectorXd startJoints(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd q;
  if (c.gait_type == SceneGaitType::Keyframes) {
    q = keyframePositions(c, model, readKeyframes(c), holdPose(c, model)).front();
  } else {
    const Standing s = standing(c, model);
    if (s.pose) return s.pose->q;
    q = Eigen::VectorXd::Zero(model.nq);
  }
  const Where wj{fileOf(c), "robot.initial.joints"};
  for (const auto& [name, value] : c.initial_joints) q[actuatedIndex(model, c, name, wj / name)] = value;
  return q;
}


}  // namespace scene_detail

using namespace scene_detail;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

Eigen::VectorXd initialConfiguration(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd q = startJoints(c, model);
  if (model.base == BaseType::Fixed) return q;

  const Vec3 angles = model.base == BaseType::Floating ? baseAnglesFromRpy(c.initial_rpy) : c.initial_rpy;
  setBase(model, Vec3(c.initial_x, c.initial_y, c.initial_height.value_or(0.0)), angles, q);
  const int z = verticalBaseIndex(model);
  if (c.initial_height || z < 0) return q;

  // Default height: shift up or down until the lowest contact sphere touches the terrain.
  const std::vector<ContactPoint> contacts = contactPointsFor(c, model);
  if (contacts.empty()) {
    const Standing s = standing(c, model);
    if (s.pose) q[z] = s.pose->height;
    return q;
  }
  const std::unique_ptr<Terrain> terrain = makeTerrain(c.terrain, ConfigContext{c.path + ": terrain", c.base_dir});
  Data data(model);
  forwardKinematics(model, data, q);
  double shift = -kInf;
  for (const ContactPoint& p : contacts) {
    const Vec3 centre = linkPoint(model, data, p.link, p.offset);
    // Solve φ(centre + s e_z) = radius for s by Newton (exact in one step for a level plane).
    double s = 0.0;
    TerrainQuery tq;
    for (int it = 0; it < 50; ++it) {
      terrain->query(centre + s * Vec3::UnitZ(), tq, true);
      const double f = tq.distance - p.radius;
      const double slope = std::max(tq.gradient.z(), 1e-3);
      const double step = -f / slope;
      s += step;
      if (std::abs(step) < 1e-13) break;
    }
    shift = std::max(shift, s);
  }
  q[z] += shift;
  return q;
}

Eigen::VectorXd initialVelocity(const SceneConfig& c, const Model& model) {
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model.nq);
  if (model.base == BaseType::Fixed) return qd;
  Vec3 rates = c.initial_angular_velocity;
  if (model.base == BaseType::Floating) {
    // ω = ȧ x + ḃ Rx(a) y + ċ Rx(a) Ry(b) z for R = Rx(a) Ry(b) Rz(c).
    const Vec3 angles = baseAnglesFromRpy(c.initial_rpy);
    const Mat3 Rx = Eigen::AngleAxisd(angles.x(), Vec3::UnitX()).toRotationMatrix();
    const Mat3 Ry = Eigen::AngleAxisd(angles.y(), Vec3::UnitY()).toRotationMatrix();
    Mat3 E;
    E.col(0) = Vec3::UnitX();
    E.col(1) = Rx * Vec3::UnitY();
    E.col(2) = Rx * Ry * Vec3::UnitZ();
    rates = E.partialPivLu().solve(c.initial_angular_velocity);
  }
  setBase(model, c.initial_linear_velocity, rates, qd);
  return qd;
}

}  // namespace nmdp
