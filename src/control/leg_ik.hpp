// Legs of a quadruped and their inverse kinematics (DESIGN.md 5).
//
// The legs come from foot detection (multibody/feet.hpp): a leg is the chain of movable joints
// from the trunk (the body carrying the root link) down to a foot link, and its end effector is
// the centre of the foot's contact sphere. Foot positions are expressed in the *trunk frame* (the
// root link frame); the trunk pose is whatever the coordinate vector says and is never changed.
//
// IK is damped least squares (Levenberg–Marquardt) on the leg's joints only: the foot position by
// forwardKinematics, the 3×k Jacobian by pointJacobian restricted to the leg's columns, started
// from a seed (the current pose) and projected onto joint limits when those are known.
//
// A *planar* leg (every joint revolute about parallel axes, e.g. RoboSimian's limbs with only
// joints 2, 4, 6 active) moves its foot in a plane: the target's component along the axes cannot
// be reached and is ignored (the foot keeps its offset along them), and the leg is singular when
// its Jacobian loses rank within that plane.
#pragma once
#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "multibody/contact_point.hpp"
#include "multibody/data.hpp"

namespace nmdp {

struct Leg {
  ContactPoint foot;          // the foot's contact sphere; its centre is the IK point
  int foot_body = -1;         // body carrying the foot link
  std::vector<int> joints;    // coordinate (= body) indices, trunk to foot
};

// Position limits per coordinate (size nq); ±∞ where a joint has none.
struct JointLimits {
  Eigen::VectorXd lower, upper;
  static JointLimits unlimited(int nq);
};

// The <limit> of every revolute or prismatic URDF joint of the model (Body::lower_limit and
// upper_limit, kept by the loader). Unlimited where the URDF has none (continuous joints, base
// coordinates, lower ≥ upper).
JointLimits readJointLimits(const Model& model);

// One leg per detected foot, in detectFeet order. A foot whose chain from the trunk has no
// movable joint is left out.
std::vector<Leg> findLegs(const Model& model);

// The four legs of a quadruped, identified by the side of the trunk frame their foot is on at the
// given pose (x forward, y left): Hind is also called "rear" (RL, RR) by some robots.
enum LegId : int { kFrontLeft = 0, kFrontRight = 1, kHindLeft = 2, kHindRight = 3 };
const char* legIdName(LegId id);  // "front left", ...

struct QuadrupedLegs {
  std::array<Leg, 4> legs;  // indexed by LegId
};

// Throws std::invalid_argument unless the model has exactly four legs, one in each quadrant of
// the trunk's horizontal plane at pose q (q = 0 if empty).
QuadrupedLegs identifyQuadrupedLegs(const Model& model, const Eigen::VectorXd& q = {});

struct LegIkOptions {
  double tolerance = 1e-11;     // m: stop when the foot is this close to the target
  int max_iterations = 100;
  double initial_damping = 1e-3;  // λ relative to the mean diagonal of JᵀJ
  double step_limit = 0.5;      // rad (or m): largest joint change per iteration, for robustness
};

struct LegIkResult {
  bool converged = false;
  int iterations = 0;
  double error = std::numeric_limits<double>::infinity();  // final ‖foot − target‖, m (in the plane of a planar leg)
};

// IK workspace for one model (which must outlive it). IK runs when gait targets are built, not
// inside the integrator, so it is not held to the no-allocation rule.
class LegIkSolver {
 public:
  explicit LegIkSolver(const Model& model, JointLimits limits = {}, LegIkOptions options = {});

  // Moves q's entries of leg.joints (q is the seed on entry) so that the foot's contact sphere
  // centre reaches target_in_trunk, given in the trunk (root link) frame of pose q (a planar leg:
  // its projection onto the plane the foot moves in).
  LegIkResult solve(const Leg& leg, const Vec3& target_in_trunk, Eigen::VectorXd& q);

  // The foot's contact sphere centre in the trunk frame at pose q.
  Vec3 footInTrunk(const Leg& leg, const Eigen::VectorXd& q);
  // Any link point in the trunk frame at pose q.
  Vec3 linkPointInTrunk(int link, const Vec3& local, const Eigen::VectorXd& q);
  // σ_r/σ_1 of the leg's 3×k foot Jacobian at pose q, r the number of directions the foot can
  // move in (3, or 2 for a planar leg; at most k): near 0 at a singular pose (a straight knee),
  // where IK cannot tell which way to bend.
  double conditioning(const Leg& leg, const Eigen::VectorXd& q);
  // The unit normal of a planar leg's plane (its joints' common axis) in the trunk frame; zero
  // for a leg whose foot moves in 3-D. It does not depend on the leg's joint angles.
  Vec3 planeNormal(const Leg& leg, const Eigen::VectorXd& q);

  const JointLimits& limits() const { return limits_; }

 private:
  const Model& model_;
  Data data_;
  JointLimits limits_;
  LegIkOptions options_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> full_jacobian_;  // 3×nq
  Eigen::MatrixXd leg_jacobian_, normal_matrix_;            // 3×k, k×k (k ≤ nq)
  Eigen::VectorXd step_, gradient_, q_trial_;

  // planeNormal in the world frame, for data_ already at the pose.
  Vec3 worldPlaneNormal(const Leg& leg) const;
};

}  // namespace nmdp
