// A scene against its robot: the checks that need the model, the resolved scene with the defaults
// the robot decides, and the builders of the URDF options, contact points and gains.
#include "control/default_gains.hpp"
#include "common/text.hpp"
#include "multibody/feet.hpp"
#include "sim/scene_parts.hpp"
#include "solver/contact_kinematics.hpp"

namespace nmdp {

using namespace scene_detail;


void validateAgainstModel(const SceneConfig& c, const Model& model) {
  const Where top{fileOf(c), ""};
  checkJointNames(model, c, c.initial_joints, top / "robot" / "initial" / "joints");
  checkJointNames(model, c, c.armature, top / "robot" / "armature");
  checkJointNames(model, c, c.kp.joints, top / "controller" / "kp");
  checkJointNames(model, c, c.kd.joints, top / "controller" / "kd");
  checkJointNames(model, c, c.tau_ff, top / "controller" / "tau_ff");
  if (c.auto_contacts) {
    if (detectFeet(model).empty())
      (top / "contacts" / "points").fail("\"auto\" found no feet on " + model.source +
                                         " (no leg has collision geometry); list the contact points as [{\"link\": ..., \"offset\": [x, y, z], \"radius\": r}]");
  } else {
    for (size_t i = 0; i < c.contact_points.size(); ++i)
      linkIndexOrThrow(model, c.contact_points[i].link, top / "contacts" / "points" / std::to_string(i) / "link");
  }
  if (c.gait_type != SceneGaitType::Keyframes) {
    // Trot and jump need a quadruped's standing pose; stand holds the start pose of other robots.
    const Standing s = standing(c, model);
    if (!s.pose && (s.quadruped || c.gait_type != SceneGaitType::Stand)) (top / "controller" / "gait").fail(standingFailure(c, s));
  }
  if (c.gait_type == SceneGaitType::Keyframes) keyframePositions(c, model, readKeyframes(c), Eigen::VectorXd::Zero(model.nq));
}

json resolvedWithModel(const SceneConfig& c, const Model& model) {
  validateAgainstModel(c, model);
  json out = c.resolved;
  const PdGains gains = gainsFor(c, model);
  json kp = json::object(), kd = json::object(), joints = json::object();
  const Eigen::VectorXd q = initialConfiguration(c, model);
  for (int i = 0; i < model.nq; ++i) {
    if (model.bodies[i].is_base) continue;
    kp[model.dof_names[i]] = gains.kp[i];
    kd[model.dof_names[i]] = gains.kd[i];
    joints[model.dof_names[i]] = q[i];
  }
  out["controller"]["kp"] = kp;
  out["controller"]["kd"] = kd;
  json& initial = out["robot"]["initial"];
  initial["joints"] = joints;
  const int z = verticalBaseIndex(model);
  if (z >= 0) initial["height"] = q[z];

  json points = json::array();
  for (const ContactPoint& p : contactPointsFor(c, model))
    points.push_back({{"name", p.name}, {"link", model.links[p.link].name}, {"offset", toJson(p.offset)}, {"radius", p.radius}});
  out["contacts"]["points"] = points;

  const Standing s = standing(c, model);
  if (s.pose) {
    json& gait = out["controller"]["gait"];
    gait["height"] = s.pose->height;
    if (c.gait_type == SceneGaitType::Trot) {
      const TrotParameters t = withRobotDefaults(c.gait.trot, *s.pose);
      gait["stride_length"] = *t.stride_length;
      gait["step_height"] = *t.step_height;
      gait["heading_feedback"] = t.heading_feedback.value_or(model.base == BaseType::Floating);
    } else if (c.gait_type == SceneGaitType::Jump) {
      const JumpParameters j = withRobotDefaults(c.gait.jump, *s.pose);
      gait["crouch_depth"] = *j.crouch_depth;
      gait["push_off_height"] = *j.push_off_height;
    }
  }
  return out;
}

UrdfOptions urdfOptionsFor(const SceneConfig& c) {
  UrdfOptions o;
  o.base = c.base;
  o.locked_joints = c.locked_joints;
  o.armature = c.armature;
  o.default_armature = c.default_armature;
  return o;
}

std::vector<ContactPoint> contactPointsFor(const SceneConfig& c, const Model& model) {
  std::vector<ContactPoint> out;
  const Where top{fileOf(c), ""};
  if (c.auto_contacts) return footContactPoints(model);
  for (size_t i = 0; i < c.contact_points.size(); ++i) {
    const ContactPointSpec& s = c.contact_points[i];
    ContactPoint p;
    p.name = s.name;
    p.link = linkIndexOrThrow(model, s.link, top / "contacts" / "points" / std::to_string(i) / "link");
    p.offset = s.offset;
    p.radius = s.radius;
    p.leg_axis = s.leg_axis ? *s.leg_axis : legAxisOf(model, p.link, p.offset, p.radius);
    out.push_back(p);
  }
  return out;
}

PdGains gainsFor(const SceneConfig& c, const Model& model) {
  const Where top{fileOf(c), ""};
  // Default gains from the joint inertias at the pose the robot starts in (the gait's standing pose
  // for the built-in gaits): control/default_gains.hpp.
  PdGains g = defaultPdGains(model, initialConfiguration(c, model));
  auto apply = [&](const GainSpec& spec, Eigen::VectorXd& values, const Where& w) {
    for (int i = 0; i < model.nq; ++i)
      if (spec.all && !model.bodies[i].is_base) values[i] = *spec.all;
    for (const auto& [name, value] : spec.joints) values[actuatedIndex(model, c, name, w / name)] = value;
  };
  apply(c.kp, g.kp, top / "controller" / "kp");
  apply(c.kd, g.kd, top / "controller" / "kd");
  for (const auto& [name, value] : c.tau_ff) g.tau_ff[actuatedIndex(model, c, name, top / "controller" / "tau_ff" / name)] = value;
  return g;
}

}  // namespace nmdp
