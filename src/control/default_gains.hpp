// Default PD gains from the robot itself: each actuated joint gets a stated natural frequency and
// critical damping about the inertia it moves at a given pose (the standing pose), so that a robot
// the project has never seen gets a usable controller without tuning.
//
// Per actuated joint j at the pose q:
//   I_j   = H_jj(q) + Σ_{feet f below j} (m / n) ‖∂p_f/∂θ_j‖²     (kg m², or kg for a prismatic joint)
//   K_p,j = I_j ω²,   K_d,j = 2 ζ ω I_j,   ω = 2π · 8 Hz,  ζ = 1,   τ_ff = 0
// H_jj (CRBA) is the joint's own subtree: a swinging leg. The second term is the load a stance leg
// carries: its foot pinned, turning joint j moves the leg's share m/n of the robot's mass m (n feet,
// detectFeet, foot sphere centres) at ‖∂p_f/∂θ_j‖ per rad/s relative to the foot, the reflected
// inertia of a point load at the foot. So a stance leg is critically damped at ω under its share
// of the weight and sags about g/ω² (4 mm at 8 Hz) whatever the robot's size.
// 8 Hz is four times the built-in trot's 2 Hz cycle: a swinging leg, over-damped about its own
// small inertia, still follows its targets with its slow pole at K_p/K_d = ω/2ζ = 4 Hz. With softer
// gains the trot's path depends on the gains and on the contact model (docs/notes, default gains).
// Such damping needs an implicit PD: explicit PD is stable only for h < 2/λ_max(H⁻¹K_d), a fraction
// of a millisecond on A1. nmdp's stable PD is implicit; in MuJoCo, K_d belongs in the joints' damping.
//
// Fallbacks, so that every robot that loads gets gains: a fixed base carries no load (I_j = H_jj);
// a robot without feet gets H_jj alone; base coordinates get zero. H_jj > 0 on every actuated joint
// (the URDF loader refuses a joint that moves no mass and has no armature), so every gain is positive.
#pragma once
#include <Eigen/Core>

#include "control/stable_pd.hpp"
#include "multibody/model.hpp"

namespace nmdp {

constexpr double kDefaultGainFrequencyHz = 8.0;  // ω / 2π, Hz
constexpr double kDefaultGainDampingRatio = 1.0;  // ζ: critical damping

// The inertia each coordinate's default gains are computed from, all sized nq, zero on base
// coordinates.
struct GainInertia {
  Eigen::VectorXd subtree;  // H_jj(q)
  Eigen::VectorXd load;     // Σ_f (m / n) ‖∂p_f/∂θ_j‖²
  Eigen::VectorXd total;    // I_j the gains use: subtree + load
  int feet = 0;             // n (0: no load term)
};

// I_j at the pose q (nq, finite); throws std::invalid_argument for a pose of the wrong size or
// with a non-finite entry.
GainInertia gainInertia(const Model& model, const Eigen::VectorXd& q);

// K_p = I ω², K_d = 2 ζ ω I on actuated coordinates for the given inertias (nq, ≥ 0), zero on base
// coordinates, τ_ff = 0.
PdGains gainsForInertia(const Model& model, const Eigen::VectorXd& inertia,
                        double frequency_hz = kDefaultGainFrequencyHz, double damping_ratio = kDefaultGainDampingRatio);

// The default gains at the pose q: gainsForInertia(model, gainInertia(model, q).total).
PdGains defaultPdGains(const Model& model, const Eigen::VectorXd& q);

}  // namespace nmdp
