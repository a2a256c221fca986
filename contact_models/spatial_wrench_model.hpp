// Contact models fitted to 3-D force data (the 3-D RBF and MLP granular models): a feature function
// maps f = (φ, β, γ) to K six-dimensional wrenches, and this class places them in the world.
//
// Geometry, for a contact sphere of centre c and radius r on terrain with normal n (the planar
// models' conventions, planar_wrench_model.hpp, extended across the sagittal plane):
//  * foot point    P = c − r n, depth feature φ = φ_terrain(c) − r (negative below the surface);
//  * terrain frame y_s = the contact's lateral axis projected onto the tangent plane, normalized;
//                  x_s = y_s × n (the heading, forward); R = [x_s y_s n]. The frame turns with the
//                  foot about the normal, so a model is invariant to heading by construction;
//  * tilt features with the leg axis a (unit, from the foot up the leg) in the frame,
//                  (a_x, a_y, a_z) = Rᵀ a:  β = atan2(a_x, a_z) the sagittal lean (the planar
//                  models' β), γ = asin(a_y) the lateral lean (positive toward y_s), so
//                  a = R (cos γ sin β, sin γ, cos γ cos β);
//  * wrench        vertex j of the feature function is (τ, F) = (τ_x, τ_y, τ_z, F_x, F_y, F_z) in the
//                  frame R, the torque about the foot point P; in the world, about the sphere centre:
//                  V_j = [R τ + (P − c) × R F; R F];
//  * cut-off       the wrenches are scaled by the planar models' C² step σ(φ) (cutoffStep), zero at
//                  and above `cutoff`, so the model is exactly zero in the air.
// The derivative dV/dξ is analytic in the geometry and uses the feature function's dW/df.
// features() reports (φ, β, γ) of each contact as "depth" (m), "beta" and "gamma" (rad), computed
// by computeSpatialFrame as evaluate() computes them, so they are bit for bit what the feature
// function was given (also above the cut-off, where the function is not evaluated).
#pragma once
#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "contact_models/planar_wrench_model.hpp"

namespace nmdp {

// Entries per vertex in a spatial feature function's output row: (τ_x, τ_y, τ_z, F_x, F_y, F_z).
constexpr int kSpatialWrenchWidth = 6;
// Features of a spatial model: (φ, β, γ).
constexpr int kSpatialFeatureCount = 3;

// Row-major spatial results (see SpatialFeatureFunction::evaluateRows).
using SpatialRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Six-dimensional wrenches of K vertices for a batch of B feature points. Row b of W holds vertex
// j's (τ_x, τ_y, τ_z, F_x, F_y, F_z) in columns 6j .. 6j + 5 (frame R, torque about the foot point).
class SpatialFeatureFunction {
 public:
  virtual ~SpatialFeatureFunction() = default;
  virtual int vertexCount() const = 0;
  virtual DerivativeSupport derivative() const = 0;
  virtual std::string describe() const = 0;
  // features: B×3 rows (φ, β, γ) in (m, rad, rad). W: B×6K. dW, when non-null: ∂W/∂φ, ∂W/∂β, ∂W/∂γ,
  // each B×6K. Resizes its outputs; allocates nothing once they have the size of a previous call.
  virtual void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W,
                        std::array<Eigen::MatrixXd, 3>* dW) const = 0;
  // Optional fast path for SpatialWrenchModel, which needs each point's results contiguous:
  // evaluates the first `count` rows of `features` (B×3, count ≤ B) into `rows`, whose row r = 4b + v
  // (derivatives) or r = b (values only), v = 0 for W, 1, 2, 3 for ∂W/∂φ, ∂W/∂β, ∂W/∂γ, begins with
  // the 6K entries of row b of evaluate()'s output, i.e. a 6×K column-major matrix. `rows` may be
  // larger than needed and is sized for all B points, so a varying count never reallocates.
  // Returns false when not implemented (the caller then uses evaluate()).
  virtual bool evaluateRows(const Eigen::MatrixX3d& /*features*/, Eigen::Index /*count*/, bool /*derivatives*/,
                            SpatialRows& /*rows*/) const {
    return false;
  }
};

// The spatial models' cut-off: the planar models' PlanarGeometry with torque_centre unused (the
// torque is about the foot point).
struct SpatialGeometry {
  double cutoff = 0.0;          // m: zero wrench when φ ≥ cutoff
  double cutoff_width = 0.005;  // m: blending band below the cut-off
};

// The planar geometry with the same cut-off and no torque centre (the torque is about the foot point).
PlanarGeometry planarGeometryOf(const SpatialGeometry& g);

// Features of one contact and their derivatives along the six ξ directions: the planar frame
// (planar_wrench_model.hpp: n, x, y, a, φ, β, arm = P − c) and the lateral lean γ = asin(a·y).
struct SpatialFrame {
  PlanarFrame planar;
  double gamma = 0;
  Eigen::Matrix<double, 6, 1> dgamma;
};

void computeSpatialFrame(const ContactFrame& frame, const Terrain& terrain, const SpatialGeometry& geometry,
                         bool with_derivatives, SpatialFrame& out);

class SpatialWrenchModel : public ContactModel {
 public:
  // `source`: the configuration keys that identify the feature function ("file", ...), as the
  // factory resolved them; null for a function built in code.
  SpatialWrenchModel(std::shared_ptr<const SpatialFeatureFunction> function, SpatialGeometry geometry,
                     std::string type, nlohmann::json source = nullptr);

  int vertexCount() const override { return function_->vertexCount(); }
  DerivativeSupport derivative() const override { return function_->derivative(); }
  std::string describe() const override;
  // `source` with "type", "cutoff" and "cutoff_width"; null without a source.
  nlohmann::json configuration() const override;
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override;
  // "depth" φ (m), "beta" β and "gamma" γ (rad), the feature function's inputs.
  std::vector<ContactFeatureInfo> featureInfo() const override;
  void features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                Eigen::Ref<Eigen::MatrixXd> out) const override;

  const SpatialFeatureFunction& function() const { return *function_; }
  const SpatialGeometry& geometry() const { return geometry_; }

 private:
  std::shared_ptr<const SpatialFeatureFunction> function_;
  SpatialGeometry geometry_;
  std::string type_;
  nlohmann::json source_;
  // The frames and cut-off of every contact, and the feature function's rows (W, and with
  // derivatives ∂W/∂φ, ∂W/∂β, ∂W/∂γ) of those below the cut-off into rows_ (row_[b] says where).
  void evaluateRows(const std::vector<ContactFrame>& frames, const Terrain& terrain, bool with_derivatives) const;
  // V (and dV) of contact b from its rows.
  void assembleWrenches(Eigen::Index b, bool with_derivatives, ContactWrenches& o) const;

  // Scratch for one evaluation (a model instance serves one simulation at a time), sized by the
  // number of contacts only.
  mutable std::vector<SpatialFrame> frames_;
  mutable std::vector<double> sigma_, dsigma_;  // cut-off step and its derivative per contact
  mutable std::vector<Eigen::Index> row_;       // the contact's point in the feature batch, −1 if above the cut-off
  mutable Eigen::MatrixX3d features_;
  mutable Eigen::MatrixXd W_;                     // for functions without evaluateRows()
  mutable std::array<Eigen::MatrixXd, 3> dW_;
  mutable SpatialRows rows_;
};

}  // namespace nmdp
