// Scene files of `nmdp simulate` (DESIGN.md 11): loading, `--set` overrides, validation with
// messages a user can act on, and the builders the app needs. Pure data: no libtorch and no
// contact-model registry (the app builds the contact model from SceneConfig::contact_model).
//
// The keys of a scene, with their types, defaults, ranges and units, are declared in
// sim/scene_schema.cpp and config/integrator_options.cpp; `nmdp simulate --schema` prints them.
// Every key is optional but robot.urdf; unknown keys at any level are errors that suggest the
// closest valid key; paths are relative to the scene file's folder and stored absolute.
//
// Start pose: with a built-in gait (stand, trot, jump) on a quadruped, robot.initial.joints is the
// gait's nominal pose (StandParameters::nominal_q, control/gait.hpp; joints not listed as in the
// standing pose without it, or 0 if there is none): the standing pose keeps its feet's horizontal
// positions and knee bends and puts all four feet at controller.gait.height below the trunk (by
// default at their mean height in it), and the robot starts in that standing pose. A robot whose
// legs do not hang under it at q = 0 (RoboSimian) needs such a bent pose to stand. Otherwise
// (keyframes: over the first frame; a robot that is not a quadruped: over q = 0) the joints listed
// are set as given.
//
// Keyframe files: CSV with the header `time,<joint names...>` and one row per keyframe, or JSON
// {"times": [...], "joints": {name: [...]}}. Joints not listed hold the standing pose. With
// "cyclic": true the motion repeats with "period" (> last − first time); without "period" the
// last keyframe closes the cycle and must repeat the first.
//
// Every error is an InputError "<scene file>: <key.path>: <what is wrong>".
#pragma once
#include <Eigen/Core>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/named_enum.hpp"
#include "control/gait.hpp"
#include "control/pd_target_source.hpp"
#include "control/stable_pd.hpp"
#include "multibody/model.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/contact_kinematics.hpp"
#include "config/integrator_options.hpp"
#include "sim/scene_schema.hpp"

namespace nmdp {

using JointValues = std::map<std::string, double>;

struct ContactPointSpec {
  std::string name;  // defaults to the link name
  std::string link;
  Vec3 offset = Vec3::Zero();
  double radius = 0.0;
  std::optional<Vec3> leg_axis;  // link frame; default: legAxisOf (solver/contact_kinematics.hpp)
};

// A gain given as one number for every actuated joint and/or per joint (per joint wins).
struct GainSpec {
  std::optional<double> all;
  JointValues joints;
  bool empty() const { return !all && joints.empty(); }
};

enum class SceneGaitType { Stand, Trot, Jump, Keyframes };
inline constexpr EnumName<SceneGaitType> kSceneGaitTypes[] = {{SceneGaitType::Stand, "stand"},
                                                               {SceneGaitType::Trot, "trot"},
                                                               {SceneGaitType::Jump, "jump"},
                                                               {SceneGaitType::Keyframes, "keyframes"}};
const char* sceneGaitTypeName(SceneGaitType type);  // "stand", "trot", "jump", "keyframes"

struct SceneConfig {
  std::string path;      // the scene file as given (used in messages)
  std::string base_dir;  // its folder, absolute

  // robot
  std::string urdf;  // absolute
  BaseType base = BaseType::Floating;
  JointValues locked_joints;
  double default_armature = 0.0;
  JointValues armature;
  std::optional<double> initial_height;  // trunk origin height (base_position z included)
  JointValues initial_joints;            // the start pose, or the gait's nominal pose (see "Start pose")
  double initial_x = 0.0, initial_y = 0.0;
  Vec3 initial_rpy = Vec3::Zero();
  Vec3 initial_linear_velocity = Vec3::Zero();   // world frame
  Vec3 initial_angular_velocity = Vec3::Zero();  // world frame

  // contacts
  bool auto_contacts = true;
  std::vector<ContactPointSpec> contact_points;  // when !auto_contacts
  nlohmann::json contact_model;                  // object with a string "type"; "file" absolute

  nlohmann::json terrain;  // for makeTerrain; "file" absolute

  // integrator
  double dt = 0.05;
  IntegratorOptions integrator;

  // controller
  GainSpec kp, kd;
  JointValues tau_ff;
  SceneGaitType gait_type = SceneGaitType::Stand;
  GaitParameters gait;            // stand/trot/jump parameters (gait.type set unless keyframes)
  std::string keyframe_file;      // absolute, keyframes only
  bool keyframes_cyclic = false;
  std::optional<double> keyframe_period;

  double duration = 10.0;
  std::string output_file;  // absolute
  int output_every = 1;

  // The scene with every model-independent default filled in and paths absolute. The defaults
  // that need the robot (gains, initial height and joints, gait sizes, auto contact points) are
  // added by resolvedWithModel(); either form parses again to the same run.
  nlohmann::json resolved;
};

// Reads a scene file; InputError naming the file (and line and column for a JSON syntax error).
nlohmann::json loadSceneJson(const std::string& path);

// Applies one `--set key.path=value`: the value is JSON if it parses as JSON (numbers, true,
// false, null, arrays, objects, quoted strings), else a plain string. Missing intermediate objects
// are created; a numeric segment indexes an existing array. InputError (prefixed by `file`) for a
// malformed assignment (no '=', an empty key or key segment) or a path through a non-object.
void applyOverride(nlohmann::json& scene, const std::string& assignment, const std::string& file);

// Validates the whole scene (see the schema above) and fills every default. `path` is the scene
// file: it names the scene in messages and relative paths are resolved against its folder.
SceneConfig parseScene(const nlohmann::json& scene, const std::string& path);

// The checks that need the robot: joint names of robot.initial.joints, robot.armature,
// controller.kp/kd/tau_ff (suggesting the closest joint; a locked joint is named as such),
// contact links (suggesting the closest link), "auto" contacts finding at least one foot, a
// quadruped's standing pose for stand, trot and jump (stand on another robot holds its start
// pose), and the keyframe file's contents.
void validateAgainstModel(const SceneConfig& config, const Model& model);

// config.resolved completed with the model-dependent defaults (see SceneConfig::resolved). The
// contact model's defaults are not among them (this library builds no contact model): `nmdp
// simulate` replaces contacts.model with the built model's ContactModel::configuration().
nlohmann::json resolvedWithModel(const SceneConfig& config, const Model& model);

// Builders for the app. Each throws InputError naming the scene key on input it cannot use.
UrdfOptions urdfOptionsFor(const SceneConfig& config);
std::vector<ContactPoint> contactPointsFor(const SceneConfig& config, const Model& model);
PdGains gainsFor(const SceneConfig& config, const Model& model);
std::unique_ptr<PdTargetSource> gaitFor(const SceneConfig& config, const Model& model);
// q (nq): joints as "Start pose" above says; base from base_position, base_rpy and height
// (default: shifted so the lowest contact sphere touches the terrain).
Eigen::VectorXd initialConfiguration(const SceneConfig& config, const Model& model);
// q̇ (nq): base rates from robot.initial.velocity, joints at rest.
Eigen::VectorXd initialVelocity(const SceneConfig& config, const Model& model);

}  // namespace nmdp
