// The gait of a scene: keyframes through a spline, a quadruped's built-in gait about its standing
// pose, or the start pose held by a robot that is not a quadruped.
#include <stdexcept>

#include "control/hermite_spline.hpp"
#include "sim/scene_parts.hpp"

namespace nmdp {

using namespace scene_detail;

std::unique_ptr<PdTargetSource> gaitFor(const SceneConfig& c, const Model& model) {
  const Where wg{fileOf(c), "controller.gait"};
  if (c.gait_type == SceneGaitType::Keyframes) {
    const Keyframes k = readKeyframes(c);
    std::vector<double> times = k.times;
    std::vector<Eigen::VectorXd> positions = keyframePositions(c, model, k, holdPose(c, model));
    SplineEndMode mode = SplineEndMode::HoldEnds;
    double period = 0.0;
    if (c.keyframes_cyclic) {
      mode = SplineEndMode::Periodic;
      if (c.keyframe_period) {
        period = *c.keyframe_period;
        if (!(period > times.back() - times.front()))
          (wg / "period").fail("must exceed the keyframes' time span " + numberText(times.back() - times.front()) + " s, got " + numberText(period));
      } else {
        if (times.size() < 3)
          keyframeFail(c, "a cyclic motion without controller.gait.period needs at least 3 keyframes, the last repeating the first");
        if ((positions.back() - positions.front()).cwiseAbs().maxCoeff() > 1e-6)
          keyframeFail(c, "with \"cyclic\": true the last keyframe must repeat the first (it closes the cycle), or give controller.gait.period");
        period = times.back() - times.front();
        times.pop_back();
        positions.pop_back();
      }
    }
    try {
      return std::make_unique<KeyframePdTarget>(std::move(times), positions, std::vector<Eigen::VectorXd>{}, mode, period);
    } catch (const std::invalid_argument& e) {
      keyframeFail(c, e.what());
    }
  }
  const Standing s = standing(c, model);
  if (!s.pose) {
    if (c.gait_type != SceneGaitType::Stand || s.quadruped) wg.fail(standingFailure(c, s));
    // Not a quadruped: hold the initial joint pose.
    if (c.gait.stand.height) (wg / "height").fail("needs a quadruped to build a standing pose: " + s.error);
    return std::make_unique<ConstantPdTarget>(initialConfiguration(c, model));
  }
  GaitParameters gait = c.gait;
  gait.stand = standParameters(c, model);
  if (gait.type == GaitType::Trot && gait.trot.heading_feedback.value_or(false) && model.base != BaseType::Floating)
    (wg / "heading_feedback").fail(std::string("needs a floating base (a ") + baseTypeName(model.base) +
                                   " base can neither yaw nor drift sideways); set it to false or remove it");
  try {
    return makeGaitTarget(model, gait);
  } catch (const std::invalid_argument& e) {
    wg.fail(std::string("gait type '") + sceneGaitTypeName(c.gait_type) + "' cannot be built: " + e.what());
  }
}


}  // namespace nmdp
