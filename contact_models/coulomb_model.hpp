// The smooth, linearized Coulomb cone (DESIGN.md §7.1; the paper's remarks on Assumptions
// "V smooth" and "∂G/∂w full rank"):
//
//     V_i = k (d^p + ζ) (n + μ (cos φ_i t₁ + sin φ_i t₂)),   φ_i = 2πi/K,  i = 0..K−1,
//
// for a foot sphere of centre c (ContactFrame::position) and radius r (ContactFrame::radius):
//  * d = max(0, r − φ(c)) is the penetration of the sphere, φ the terrain's signed distance;
//  * n = n(c) is the terrain normal at the centre; the force acts at the sphere's lowest point
//    c − r n, so the torque row (about c) of every vertex is (−r n) × F_i;
//  * (t₁, t₂, n) is a right-handed orthonormal frame, a smooth function of n (see tangentBasis);
//  * every vertex has the same normal component k (d^p + ζ) and a tangential part of norm
//    μ k (d^p + ζ): with the weights w ≥ 0, 1ᵀw ≤ 1 of the solver, the largest normal force a
//    contact can carry is k (d^p + ζ), and the friction it can add is bounded by μ times that.
//
// Its one feature is the ContactModel default, "depth" = φ(c) − r (so d = max(0, −depth)): the
// cone reads nothing else (not the leg axis).
//
// p ≥ 2 makes V C¹ in the contact position (d^p has a zero derivative at d = 0); ζ > 0 leaves a
// tiny force in the air so ∂G/∂w keeps full rank (ZOPGM). The model depends on the contact point
// only (not on the link orientation), so dV/dξ is zero along the three rotations; along the
// translations it is analytic in ∇φ, ∂n/∂p and the derivative of the tangent basis.
//
// Defaults and their arithmetic (the project quadruped, models/quadruped: 17.41 kg, 4 feet):
//  * mu = 0.7, K = 6 (the original code's values), p = 3 (the paper's exponent).
//  * k = 1e9 N/m³: standing still, each foot carries m g / 4 = 17.41 · 9.81 / 4 = 42.7 N, which
//    the contact can only supply once k (d³ + ζ) ≥ 42.7 N, i.e. with all its weight on the
//    cone (1ᵀw = 1) at d = (42.7 / 1e9)^{1/3} = 3.5 mm. (A1, 13.7 kg: 3.2 mm; RoboSimian, 99.9 kg:
//    6.3 mm; Solo-12, 2.5 kg: 1.8 mm.) The vertical stiffness there, 3 k d² = 3.7e4 N/m per
//    foot, gives the standing robot a bounce of about 15 Hz.
//  * zeta = 1e-10 m³ (its unit is m^p: it is added to d^p; change it with p): the force a contact
//    can give in the air is k ζ = 0.1 N per foot, 0.23 % of a standing foot's load and 0.06 % of
//    the robot's weight; it equals the force of a penetration ζ^{1/3} = 0.46 mm, and makes the
//    standing depth 3 µm shallower. (The paper's ζ = 1e-3 is
//    for its unscaled v = (d³ + ζ)(n + μ t), which has no stiffness k.)
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "config/json_params.hpp"

namespace nmdp {

struct CoulombParameters {
  double mu = 0.7;      // friction coefficient, > 0
  int K = 6;            // number of vertices (edges of the linearized cone), ≥ 3
  double k = 1e9;       // stiffness, N/m^p, > 0
  double p = 3.0;       // exponent of the penetration, ≥ 2 (C¹)
  double zeta = 1e-10;  // m^p, > 0: force in the air is k ζ
};

// Orthonormal tangents of the unit normal n with (t₁, t₂, n) right-handed. For n_z > −1/2 it is
// the image of the world (x, y) under the smallest rotation taking z to n: t₁ = x, t₂ = y on flat
// ground, and the frame is smooth (rational) in n over the whole region n_z > −1/2, steep slopes
// and walls included. (A projected fixed axis, t₁ ∝ e − (e·n) n, would need a switch of e near
// n ∥ e, i.e. on steep terrain; this frame has no such switch where terrain normals live.) For
// n_z ≤ −1/2 (overhangs, which no height-field terrain produces) the frame built the same way
// around −z (t₁ = x, t₂ = −y at n = −z; Duff et al. 2017); the switch at n_z = −1/2 is the only
// discontinuity. When dt1/dt2 are given they receive ∂t₁/∂n and ∂t₂/∂n (3×3, exact derivatives of
// the formula, which is defined for any n with 1 + σ n_z ≠ 0; applied to the tangent dn = ∂n/∂p δp
// they give the derivative of the frame along the terrain).
void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2, Mat3* dt1 = nullptr, Mat3* dt2 = nullptr);

class CoulombModel : public ContactModel {
 public:
  explicit CoulombModel(const CoulombParameters& params = {});  // throws std::invalid_argument

  int vertexCount() const override { return params_.K; }
  DerivativeSupport derivative() const override { return DerivativeSupport::Analytic; }
  std::string describe() const override;
  nlohmann::json configuration() const override;  // {"type": "coulomb", "mu", "K", "k", "p", "zeta"}
  // Allocates nothing once `out` holds frames.size() entries of K columns (it is sized if not).
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override;

  const CoulombParameters& parameters() const { return params_; }
  // k (d^p + ζ): the normal component shared by every vertex (the largest normal force).
  double normalForce(double depth) const;

 private:
  CoulombParameters params_;
  std::vector<double> cos_, sin_;  // cos φ_i, sin φ_i
};

// Every key the "coulomb" type accepts besides "type".
extern const std::vector<std::string> kCoulombParameters;

// Builds the model from {"type": "coulomb", "mu": .., "K": .., "k": .., "p": .., "zeta": ..}
// ("type" optional here); a bad or unknown key throws InputError naming it (ctx.where + "." + key).
std::unique_ptr<ContactModel> makeCoulombModel(const nlohmann::json& params, const ConfigContext& ctx);

}  // namespace nmdp
