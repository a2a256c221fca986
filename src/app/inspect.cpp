#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/input_error.hpp"
#include "control/default_gains.hpp"
#include "control/gait.hpp"
#include "multibody/feet.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/contact_kinematics.hpp"

namespace nmdp::app {

const char* const kInspectHelp =
    "usage: nmdp inspect ROBOT.urdf [--base floating|planar|fixed] [--lock JOINT=VALUE ...]\n"
    "                    [--armature JOINT=VALUE ...]\n\n"
    "Loads a URDF and prints a JSON summary: dof, joint_names (one per generalized coordinate,\n"
    "base coordinates first), total_mass, links (name, mass) and feet (link, offset, radius and\n"
    "leg_axis, the link-frame direction from the foot up the leg that the planar granular models\n"
    "read their angle off), and default_gains: the PD gains a scene gets when it gives none, per\n"
    "actuated joint (kp, kd and the inertia they are computed from), with the rule and the pose\n"
    "they are evaluated at (the built-in gaits' standing pose, or q = 0 without one).\n\n"
    "  --base TYPE         floating (default: x, y, z and three angles), planar (x, z, pitch) or fixed\n"
    "  --lock JOINT=VALUE  weld a movable joint at VALUE (rad or m); repeatable\n"
    "  --armature J=VALUE  rotor inertia added to joint J; J may be * for every actuated joint\n";

namespace {
std::pair<std::string, double> parseAssignment(const std::string& option, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(option + " expects JOINT=VALUE, got '" + text + "'");
  const std::string name = text.substr(0, eq);
  const std::string value = text.substr(eq + 1);
  try {
    size_t used = 0;
    const double v = std::stod(value, &used);
    if (used != value.size()) throw std::invalid_argument(value);
    return {name, v};
  } catch (const std::exception&) {
    throw InputError(option + " " + text + ": '" + value + "' is not a number");
  }
}
// The default gains at the pose a scene with a built-in gait starts from (its standing pose; q = 0
// for a robot that has none): what `nmdp simulate` uses when the scene gives no gains.
nlohmann::ordered_json defaultGainsSummary(const Model& model) {
  Eigen::VectorXd pose = Eigen::VectorXd::Zero(model.nq);
  std::string pose_name = "standing pose of the built-in gaits";
  try {
    pose = standingPose(model, identifyQuadrupedLegs(model), {}).q;
  } catch (const std::invalid_argument& e) {
    pose_name = std::string("q = 0 (no standing pose: ") + e.what() + ")";
  }
  const GainInertia inertia = gainInertia(model, pose);
  const PdGains gains = gainsForInertia(model, inertia.total);
  nlohmann::ordered_json out;
  out["rule"] =
      "per actuated joint j: I_j = H_jj + sum over the feet f below j of (m / n) |dp_f/dq_j|^2 (the joint's own "
      "subtree plus the load share m/n of its leg reflected through the foot Jacobian; n feet, m the total mass; "
      "no load term on a fixed base); kp = I_j w^2, kd = 2 zeta w I_j, tau_ff = 0";
  out["frequency_hz"] = kDefaultGainFrequencyHz;
  out["damping_ratio"] = kDefaultGainDampingRatio;
  out["pose"] = pose_name;
  out["feet"] = inertia.feet;
  nlohmann::ordered_json joints = nlohmann::json::array();
  for (int j = 0; j < model.nq; ++j) {
    if (model.bodies[j].is_base) continue;
    joints.push_back({{"joint", model.dof_names[j]}, {"kp", gains.kp[j]}, {"kd", gains.kd[j]},
                      {"inertia", inertia.total[j]}, {"subtree_inertia", inertia.subtree[j]},
                      {"load_inertia", inertia.load[j]}});
  }
  out["joints"] = joints;
  return out;
}
}  // namespace

int runInspect(const Args& args) {
  std::string path;
  UrdfOptions options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto next = [&]() -> const std::string& { return optionValue(args, i, "inspect"); };
    if (a == "--base") {
      const std::string& value = next();
      try {
        options.base = parseBaseType(value);
      } catch (const InputError& e) {
        throw InputError(std::string("--base: ") + e.what());
      }
    } else if (a == "--lock") {
      auto [name, value] = parseAssignment(a, next());
      options.locked_joints[name] = value;
    } else if (a == "--armature") {
      auto [name, value] = parseAssignment(a, next());
      if (name == "*") options.default_armature = value;
      else options.armature[name] = value;
    } else if (!a.empty() && a[0] == '-') {
      throw InputError("unknown option '" + a + "' (see nmdp inspect --help)");
    } else if (path.empty()) {
      path = a;
    } else {
      throw InputError("more than one robot file given ('" + path + "' and '" + a + "')");
    }
  }
  if (path.empty()) throw InputError("no robot file given (usage: nmdp inspect ROBOT.urdf)");

  const Model model = loadUrdf(path, options);
  nlohmann::ordered_json out;
  out["robot"] = model.robot_name;
  out["base"] = baseTypeName(model.base);
  out["dof"] = model.nq;
  out["joint_names"] = model.dof_names;
  out["total_mass"] = model.total_mass;
  nlohmann::ordered_json links = nlohmann::json::array();
  for (const Link& l : model.links) links.push_back({{"name", l.name}, {"mass", l.mass}});
  out["links"] = links;
  nlohmann::ordered_json feet = nlohmann::json::array();
  for (const FootContact& f : detectFeet(model)) {
    const ContactPoint& p = f.point;
    const Vec3& a = p.leg_axis;
    feet.push_back({{"link", p.name}, {"offset", {p.offset.x(), p.offset.y(), p.offset.z()}}, {"radius", p.radius},
                    {"leg_axis", {a.x(), a.y(), a.z()}}});
    if (!f.warning.empty()) std::cerr << "warning: foot " << f.point.name << ": " << f.warning << "\n";
  }
  out["feet"] = feet;
  out["default_gains"] = defaultGainsSummary(model);
  std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace nmdp::app
