// The parts of the scene reader that its files share (not part of the scene's API): the start pose
// and standing pose of a scene's robot, its keyframes, and the JSON forms of its values.
#pragma once
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/json_reader.hpp"
#include "control/gait.hpp"
#include "multibody/model.hpp"
#include "sim/scene.hpp"

namespace nmdp::scene_detail {

using json = nlohmann::json;
using Where = KeyPath;

inline std::string fileOf(const SceneConfig& c) { return c.path; }
json toJson(const JointValues& values);
json toJson(const Vec3& v);

// The coordinate index of an actuated joint; InputError naming `w` otherwise.
int actuatedIndex(const Model& model, const SceneConfig& c, const std::string& joint, const Where& w);
void checkJointNames(const Model& model, const SceneConfig& c, const JointValues& values, const Where& w);
int linkIndexOrThrow(const Model& model, const std::string& link, const Where& w);

// Standing pose and legs, if the robot is a quadruped and the pose can be built; the error otherwise.
struct Standing {
  std::optional<StandingPose> pose;
  bool quadruped = false;
  std::string error;
};
StandParameters standParameters(const SceneConfig& c, const Model& model);
Standing standing(const SceneConfig& c, const Model& model);
// The message for a built-in gait whose standing pose cannot be built.
std::string standingFailure(const SceneConfig& c, const Standing& s);
// The pose the coordinates a keyframe file does not list hold: standing pose, or q = 0.
Eigen::VectorXd holdPose(const SceneConfig& c, const Model& model);

// A keyframe file's contents (scene_keyframes.cpp).
struct Keyframes {
  std::vector<double> times;
  std::vector<std::string> joints;
  std::vector<std::vector<double>> columns;  // per joint, per keyframe
};
Keyframes readKeyframes(const SceneConfig& c);
[[noreturn]] void keyframeFail(const SceneConfig& c, const std::string& what);
// Keyframe positions (nq each) from the file over the base pose.
std::vector<Eigen::VectorXd> keyframePositions(const SceneConfig& c, const Model& model, const Keyframes& k,
                                               const Eigen::VectorXd& base);

// Writes the base coordinates of q (or q̇) from a world translation and rotation vector triple.
void setBase(const Model& model, const Vec3& translation, const Vec3& angles, Eigen::VectorXd& q);
int verticalBaseIndex(const Model& model);

}  // namespace nmdp::scene_detail
