#include "control/leg_ik.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/named_enum.hpp"
#include "multibody/feet.hpp"
#include "multibody/kinematics.hpp"

namespace nmdp {

namespace {

constexpr EnumName<LegId> kLegIds[] = {
    {kFrontLeft, "front left"}, {kFrontRight, "front right"}, {kHindLeft, "hind left"}, {kHindRight, "hind right"}};

Eigen::VectorXd zeroIfEmpty(const Model& model, const Eigen::VectorXd& q) {
  return q.size() == 0 ? Eigen::VectorXd::Zero(model.nq) : q;
}

}  // namespace

JointLimits JointLimits::unlimited(int nq) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {Eigen::VectorXd::Constant(nq, -inf), Eigen::VectorXd::Constant(nq, inf)};
}

JointLimits readJointLimits(const Model& model) {
  JointLimits limits = JointLimits::unlimited(model.nq);
  for (int i = 0; i < model.nq; ++i) {
    limits.lower[i] = model.bodies[i].lower_limit;
    limits.upper[i] = model.bodies[i].upper_limit;
  }
  return limits;
}

std::vector<Leg> findLegs(const Model& model) {
  std::vector<Leg> legs;
  for (const FootContact& foot : detectFeet(model)) {
    Leg leg;
    leg.foot = foot.point;
    leg.foot_body = model.links[leg.foot.link].body;
    for (int b = leg.foot_body; b >= 0 && b != model.root_body; b = model.bodies[b].parent)
      if (!model.bodies[b].is_base) leg.joints.push_back(b);
    std::reverse(leg.joints.begin(), leg.joints.end());
    if (!leg.joints.empty()) legs.push_back(std::move(leg));
  }
  return legs;
}

const char* legIdName(LegId id) { return nameOf(kLegIds, id); }

QuadrupedLegs identifyQuadrupedLegs(const Model& model, const Eigen::VectorXd& q_in) {
  std::vector<Leg> legs = findLegs(model);
  if (legs.size() != 4)
    throw std::invalid_argument(model.source + ": a quadruped gait needs 4 legs, the robot has " +
                                std::to_string(legs.size()));
  const Eigen::VectorXd q = zeroIfEmpty(model, q_in);
  LegIkSolver kinematics(model);
  QuadrupedLegs out;
  std::array<bool, 4> taken{};
  for (Leg& leg : legs) {
    const Vec3 foot = kinematics.footInTrunk(leg, q);
    const bool front = foot.x() > 0, left = foot.y() > 0;
    const LegId id = front ? (left ? kFrontLeft : kFrontRight) : (left ? kHindLeft : kHindRight);
    if (taken[id])
      throw std::invalid_argument(model.source + ": two feet (" + out.legs[id].foot.name + ", " + leg.foot.name +
                                  ") are both on the " + legIdName(id) + " of the trunk; cannot tell the legs apart");
    taken[id] = true;
    out.legs[id] = std::move(leg);
  }
  return out;
}

LegIkSolver::LegIkSolver(const Model& model, JointLimits limits, LegIkOptions options)
    : model_(model),
      data_(model),
      limits_(limits.lower.size() == model.nq && limits.upper.size() == model.nq ? std::move(limits)
                                                                                  : JointLimits::unlimited(model.nq)),
      options_(options),
      full_jacobian_(3, model.nq),
      leg_jacobian_(3, model.nq),
      normal_matrix_(model.nq, model.nq),
      step_(model.nq),
      gradient_(model.nq),
      q_trial_(model.nq) {}

Vec3 LegIkSolver::linkPointInTrunk(int link, const Vec3& local, const Eigen::VectorXd& q) {
  forwardKinematics(model_, data_, q);
  Mat3 R;
  Vec3 p;
  linkPose(model_, data_, model_.root_link, R, p);
  return R.transpose() * (linkPoint(model_, data_, link, local) - p);
}

Vec3 LegIkSolver::footInTrunk(const Leg& leg, const Eigen::VectorXd& q) {
  return linkPointInTrunk(leg.foot.link, leg.foot.offset, q);
}

Vec3 LegIkSolver::worldPlaneNormal(const Leg& leg) const {
  if (leg.joints.size() < 2) return Vec3::Zero();
  const Vec3 first = (data_.R[leg.joints.front()] * model_.bodies[leg.joints.front()].axis).normalized();
  for (int j : leg.joints) {
    if (model_.bodies[j].kind != JointKind::Revolute) return Vec3::Zero();
    const Vec3 axis = data_.R[j] * model_.bodies[j].axis;
    if (axis.cross(first).norm() > 1e-9 * axis.norm()) return Vec3::Zero();
  }
  return first;
}

Vec3 LegIkSolver::planeNormal(const Leg& leg, const Eigen::VectorXd& q) {
  forwardKinematics(model_, data_, q);
  Mat3 trunk_R;
  Vec3 trunk_p;
  linkPose(model_, data_, model_.root_link, trunk_R, trunk_p);
  return trunk_R.transpose() * worldPlaneNormal(leg);
}

double LegIkSolver::conditioning(const Leg& leg, const Eigen::VectorXd& q) {
  forwardKinematics(model_, data_, q);
  const Vec3 foot = linkPoint(model_, data_, leg.foot.link, leg.foot.offset);
  pointJacobian(model_, data_, leg.foot_body, foot, full_jacobian_);
  const int k = static_cast<int>(leg.joints.size());
  for (int c = 0; c < k; ++c) leg_jacobian_.col(c) = full_jacobian_.col(leg.joints[c]);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(leg_jacobian_.leftCols(k));
  const Eigen::VectorXd& sigma = svd.singularValues();
  // A planar leg's Jacobian always has rank ≤ 2: its third singular value says nothing.
  const int directions = std::min<int>(worldPlaneNormal(leg).isZero() ? 3 : 2, static_cast<int>(sigma.size()));
  return sigma[0] > 0 ? sigma[directions - 1] / sigma[0] : 0.0;
}

LegIkResult LegIkSolver::solve(const Leg& leg, const Vec3& target_in_trunk, Eigen::VectorXd& q) {
  const int k = static_cast<int>(leg.joints.size());
  LegIkResult result;
  for (int j : leg.joints) q[j] = std::clamp(q[j], limits_.lower[j], limits_.upper[j]);

  // The trunk does not move with the leg's joints, so the world target is fixed.
  forwardKinematics(model_, data_, q);
  Mat3 trunk_R;
  Vec3 trunk_p;
  linkPose(model_, data_, model_.root_link, trunk_R, trunk_p);
  const Vec3 target = trunk_p + trunk_R * target_in_trunk;
  // A planar leg cannot move its foot along its plane's normal: only the in-plane error counts.
  const Vec3 plane_normal = worldPlaneNormal(leg);
  auto reachable = [&plane_normal](const Vec3& e) -> Vec3 { return e - plane_normal * plane_normal.dot(e); };
  Vec3 foot = linkPoint(model_, data_, leg.foot.link, leg.foot.offset);
  Vec3 error = reachable(target - foot);
  result.error = error.norm();
  double damping = options_.initial_damping;

  auto leg_jacobian = leg_jacobian_.leftCols(k);
  auto normal = normal_matrix_.topLeftCorner(k, k);
  auto step = step_.head(k);
  auto gradient = gradient_.head(k);
  while (result.error > options_.tolerance && result.iterations < options_.max_iterations) {
    ++result.iterations;
    pointJacobian(model_, data_, leg.foot_body, foot, full_jacobian_);
    for (int c = 0; c < k; ++c) leg_jacobian.col(c) = full_jacobian_.col(leg.joints[c]);
    normal.noalias() = leg_jacobian.transpose() * leg_jacobian;
    gradient.noalias() = leg_jacobian.transpose() * error;
    const double scale = std::max(normal.diagonal().mean(), 1e-12);

    // Raise the damping until the step reduces the error (Levenberg–Marquardt).
    bool improved = false;
    for (int attempt = 0; attempt < 30 && !improved; ++attempt) {
      normal.diagonal().array() += damping * scale;
      step = normal.llt().solve(gradient);
      normal.diagonal().array() -= damping * scale;
      const double norm = step.cwiseAbs().maxCoeff();
      if (norm > options_.step_limit) step *= options_.step_limit / norm;
      q_trial_ = q;
      for (int c = 0; c < k; ++c) {
        const int j = leg.joints[c];
        q_trial_[j] = std::clamp(q[j] + step[c], limits_.lower[j], limits_.upper[j]);
      }
      forwardKinematics(model_, data_, q_trial_);
      const Vec3 trial_foot = linkPoint(model_, data_, leg.foot.link, leg.foot.offset);
      const double trial_error = reachable(target - trial_foot).norm();
      if (trial_error < result.error) {
        improved = true;
        for (int j : leg.joints) q[j] = q_trial_[j];
        foot = trial_foot;
        error = reachable(target - foot);
        result.error = trial_error;
        damping = std::max(damping / 10, 1e-15);
      } else {
        damping *= 10;
      }
    }
    if (!improved) {
      forwardKinematics(model_, data_, q);  // leave data_ at the returned pose
      break;  // a local minimum (unreachable target, or pinned by a limit)
    }
  }
  result.converged = result.error <= options_.tolerance;
  return result;
}

}  // namespace nmdp
