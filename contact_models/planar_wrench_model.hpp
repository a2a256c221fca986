// Contact models fitted to planar force data (the RBF granular model, the MLP): a feature function
// maps f = (φ, β) to K planar wrenches (F_x, F_z, τ_y), and this class places them in the world.
//
// Geometry (DESIGN.md §7.2), for a contact sphere of centre c and radius r on terrain with normal n:
//  * foot point    c − r n, depth feature φ = φ_terrain(c) − r (negative below the surface);
//  * sagittal frame  y_s = the contact's lateral axis projected onto the tangent plane, normalized
//                  (for a planar robot: the world y axis; for a 3-D robot: a link-fixed axis, by
//                  default the foot link's y axis), x_s = y_s × n (forward), so (x_s, y_s, n) is
//                  right-handed and, on flat ground with y_s = y, equals the world axes;
//  * angle feature β = atan2(a·x_s, a·n): the rotation about y_s taking n to the leg axis a (unit,
//                  from the foot up the leg); positive when the leg leans toward x_s;
//  * wrench        F = F_x x_s + F_z n, applied so that the planar moment τ_y about y_s is taken
//                  about the torque centre Q = c − r n + L a (L up the leg from the foot point);
//                  about the sphere centre the torque is τ_y y_s + (Q − c) × F;
//  * cut-off       the wrenches are scaled by a C² quintic step σ(φ) that is 1 below
//                  cutoff − cutoff_width and 0 above cutoff, so the model is exactly zero in the air
//                  and continuous everywhere. Contacts at or above the cut-off get V = dV = 0
//                  without evaluating the feature function (when it has evaluateRows()).
// The derivative dV/dξ is analytic in the geometry and uses the feature function's dW/df.
// features() reports (φ, β) of each contact as "depth" (m) and "beta" (rad), computed by
// computePlanarFrame as evaluate() computes them, so they are bit for bit what the feature
// function was given (also above the cut-off, where the function is not evaluated).
#pragma once
#include <memory>

#include "contact_models/contact_model.hpp"

namespace nmdp {

// Row-major planar results (see FeatureWrenchFunction::evaluateRows).
using PlanarRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Planar wrenches of K vertices for a batch of B feature points. Row b of W holds vertex j's
// (F_x, F_z, τ_y) in columns 3j, 3j+1, 3j+2.
class FeatureWrenchFunction {
 public:
  virtual ~FeatureWrenchFunction() = default;
  virtual int vertexCount() const = 0;
  virtual DerivativeSupport derivative() const = 0;
  virtual std::string describe() const = 0;
  // features: B×2 rows (φ, β). W: B×3K. dW_dphi, dW_dbeta: B×3K, only when non-null.
  virtual void evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                        Eigen::MatrixXd* dW_dbeta) const = 0;
  // Optional fast path for PlanarWrenchModel, which needs each point's results contiguous: evaluates
  // the first `count` rows of `features` (B×2, count ≤ B) into `rows`, whose row r = 3b + v
  // (derivatives) or r = b (values only), v = 0 for W, 1 for dW/dφ, 2 for dW/dβ, begins with the
  // 3K entries of row b of evaluate()'s output, i.e. a 3×K column-major matrix. `rows` may be
  // larger than needed and is sized for all B points, so a varying count never reallocates.
  // Returns false when not implemented (the caller then uses evaluate()).
  virtual bool evaluateRows(const Eigen::MatrixX2d& /*features*/, Eigen::Index /*count*/, bool /*derivatives*/,
                            PlanarRows& /*rows*/) const {
    return false;
  }
};

struct PlanarGeometry {
  double torque_centre = 0.0;   // L, m up the leg from the foot point
  double cutoff = 0.1;          // m: zero wrench when φ ≥ cutoff
  double cutoff_width = 0.02;   // m: blending band below the cut-off
};

// The largest |torque_centre|, |cutoff| and cutoff_width a model file or configuration may give (m):
// RoboSimian's torque centre is 0.16 m up the leg.
constexpr double kMaxGeometryLength = 100.0;
// Why `g` cannot be used ("" when it can): a non-finite value, a length beyond kMaxGeometryLength,
// or a cut-off band that is not positive.
std::string planarGeometryProblem(const PlanarGeometry& g);

// C² step: 1 for φ ≤ cutoff − width, 0 for φ ≥ cutoff. Returns σ and writes dσ/dφ.
double cutoffStep(const PlanarGeometry& g, double phi, double* dsigma);

// Features of one contact and their derivatives along the six ξ directions.
struct PlanarFrame {
  double phi = 0, beta = 0;
  Vec3 n, x, y, a;     // terrain normal, sagittal forward and lateral axes, leg axis
  Vec3 arm;            // Q − c
  // Along ξ_i (i = 0..5):
  Eigen::Matrix<double, 6, 1> dphi, dbeta;
  Eigen::Matrix<double, 3, 6> dn, dx, dy, da, darm;
};

void computePlanarFrame(const ContactFrame& frame, const Terrain& terrain, const PlanarGeometry& geometry,
                        bool with_derivatives, PlanarFrame& out);

// The descriptions of the granular models' features φ ("depth") and β ("beta"), shared with the
// spatial models (spatial_wrench_model.hpp), whose first two features are the same.
ContactFeatureInfo planarDepthFeature();
ContactFeatureInfo planarBetaFeature();

class PlanarWrenchModel : public ContactModel {
 public:
  // `source`: the configuration keys that identify the feature function ("file", "format", ...), as
  // the factory (rbf_model.hpp, mlp_model.hpp) resolved them; null for a function built in code.
  PlanarWrenchModel(std::shared_ptr<const FeatureWrenchFunction> function, PlanarGeometry geometry, std::string type,
                    nlohmann::json source = nullptr);

  int vertexCount() const override { return function_->vertexCount(); }
  DerivativeSupport derivative() const override { return function_->derivative(); }
  std::string describe() const override;
  // `source` with "type" and the geometry keys torque_centre, cutoff, cutoff_width; null without a source.
  nlohmann::json configuration() const override;
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override;
  // "depth" φ (m) and "beta" β (rad), the feature function's inputs.
  std::vector<ContactFeatureInfo> featureInfo() const override;
  void features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                Eigen::Ref<Eigen::MatrixXd> out) const override;

  const FeatureWrenchFunction& function() const { return *function_; }
  const PlanarGeometry& geometry() const { return geometry_; }

 private:
  // The planar frames and cut-off of every contact, and the feature function's rows (W, and with
  // derivatives ∂W/∂φ, ∂W/∂β) of those below the cut-off into rows_ (row_[b] says where).
  void evaluateRows(const std::vector<ContactFrame>& frames, const Terrain& terrain, bool with_derivatives) const;
  // V (and dV) of contact b from its rows.
  void assembleWrenches(Eigen::Index b, bool with_derivatives, ContactWrenches& o) const;

  std::shared_ptr<const FeatureWrenchFunction> function_;
  PlanarGeometry geometry_;
  std::string type_;
  nlohmann::json source_;
  // Scratch for one evaluation (a model instance serves one simulation at a time), sized by the
  // number of contacts only.
  mutable std::vector<PlanarFrame> frames_;
  mutable std::vector<double> sigma_, dsigma_;  // cut-off step and its derivative per contact
  mutable std::vector<Eigen::Index> row_;       // the contact's point in the feature batch, −1 if above the cut-off
  mutable Eigen::MatrixX2d features_;
  mutable Eigen::MatrixXd W_, dW_dphi_, dW_dbeta_;  // for functions without evaluateRows()
  mutable PlanarRows rows_;
};

}  // namespace nmdp
