#include "contact_models/spatial_wrench_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nmdp {

PlanarGeometry planarGeometryOf(const SpatialGeometry& g) {
  PlanarGeometry p;
  p.torque_centre = 0.0;
  p.cutoff = g.cutoff;
  p.cutoff_width = g.cutoff_width;
  return p;
}

void computeSpatialFrame(const ContactFrame& frame, const Terrain& terrain, const SpatialGeometry& geometry,
                         bool with_derivatives, SpatialFrame& out) {
  // The planar frame is the same (torque centre 0: its arm is P − c); γ = asin(a·y) adds the lean
  // across the sagittal plane, so a = R (cos γ sin β, sin γ, cos γ cos β).
  PlanarFrame& f = out.planar;
  computePlanarFrame(frame, terrain, planarGeometryOf(geometry), with_derivatives, f);
  const double s = std::clamp(f.a.dot(f.y), -1.0, 1.0);
  out.gamma = std::asin(s);
  if (!with_derivatives) return;
  // dγ = d(a·y) / cos γ; cos γ > 0 unless the leg lies along the lateral axis (then 0 is used).
  const double c = std::sqrt(std::max(0.0, 1.0 - s * s));
  const double inv = c > 1e-12 ? 1.0 / c : 0.0;
  for (int i = 0; i < 6; ++i) out.dgamma[i] = (f.da.col(i).dot(f.y) + f.a.dot(f.dy.col(i))) * inv;
}

SpatialWrenchModel::SpatialWrenchModel(std::shared_ptr<const SpatialFeatureFunction> function, SpatialGeometry geometry,
                                       std::string type, nlohmann::json source)
    : function_(std::move(function)), geometry_(geometry), type_(std::move(type)), source_(std::move(source)) {}

nlohmann::json SpatialWrenchModel::configuration() const {
  if (source_.is_null()) return nullptr;
  nlohmann::json out = source_;
  out["type"] = type_;
  out["cutoff"] = geometry_.cutoff;
  out["cutoff_width"] = geometry_.cutoff_width;
  return out;
}

std::string SpatialWrenchModel::describe() const {
  std::ostringstream s;
  s << type_ << " (3-D): " << function_->describe() << ", torque about the foot point, cut-off " << geometry_.cutoff
    << " m (band " << geometry_.cutoff_width << " m)";
  return s.str();
}

std::vector<ContactFeatureInfo> SpatialWrenchModel::featureInfo() const {
  return {planarDepthFeature(), planarBetaFeature(),
          {"gamma", "rad",
           "gamma: lateral leg lean asin(a.y_s), positive when the leg axis a leans toward y_s (so that "
           "a = cos(gamma) sin(beta) x_s + sin(gamma) y_s + cos(gamma) cos(beta) n)"}};
}

void SpatialWrenchModel::features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                  Eigen::Ref<Eigen::MatrixXd> out) const {
  requireFeatureShape(type_.c_str(), frames.size(), out, kSpatialFeatureCount);
  SpatialFrame f;
  for (std::size_t b = 0; b < frames.size(); ++b) {
    computeSpatialFrame(frames[b], terrain, geometry_, false, f);
    const Eigen::Index row = static_cast<Eigen::Index>(b);
    out(row, 0) = f.planar.phi;
    out(row, 1) = f.planar.beta;
    out(row, 2) = f.gamma;
  }
}

void SpatialWrenchModel::evaluateRows(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                      bool with_derivatives) const {
  const Eigen::Index B = static_cast<Eigen::Index>(frames.size());
  const int K = vertexCount();
  const PlanarGeometry cut = planarGeometryOf(geometry_);
  frames_.resize(B);
  sigma_.resize(B);
  dsigma_.resize(B);
  row_.resize(B);
  // The batch only grows: fewer contacts than before use the first rows (no reallocation).
  if (features_.rows() < B) features_.resize(B, 3);
  // Contacts at or above the cut-off (σ = dσ/dφ = 0) have V = dV = 0 exactly; the feature function
  // is evaluated for the others only, packed first (the rest of the batch is not computed).
  Eigen::Index count = 0;
  for (Eigen::Index b = 0; b < B; ++b) {
    SpatialFrame& f = frames_[b];
    computeSpatialFrame(frames[b], terrain, geometry_, with_derivatives, f);
    sigma_[b] = cutoffStep(cut, f.planar.phi, &dsigma_[b]);
    row_[b] = sigma_[b] != 0.0 || dsigma_[b] != 0.0 ? count++ : -1;
  }
  for (Eigen::Index b = 0, inactive = count; b < B; ++b) {
    const Eigen::Index r = row_[b] >= 0 ? row_[b] : inactive++;
    features_.row(r) << frames_[b].planar.phi, frames_[b].planar.beta, frames_[b].gamma;
  }
  if (function_->evaluateRows(features_, count, with_derivatives, rows_)) return;
  // Generic functions: the whole batch in contact order, repacked into rows.
  if (features_.rows() != B) features_.resize(B, 3);
  for (Eigen::Index b = 0; b < B; ++b) {
    features_.row(b) << frames_[b].planar.phi, frames_[b].planar.beta, frames_[b].gamma;
    if (row_[b] >= 0) row_[b] = b;
  }
  function_->evaluate(features_, W_, with_derivatives ? &dW_ : nullptr);
  const Eigen::Index per_point = with_derivatives ? 4 : 1;
  if (rows_.rows() < 4 * B || rows_.cols() < 6 * K) rows_.resize(4 * B, 6 * K);
  for (Eigen::Index b = 0; b < B; ++b) {
    rows_.row(per_point * b).head(6 * K) = W_.row(b);
    if (!with_derivatives) continue;
    for (int v = 0; v < 3; ++v) rows_.row(4 * b + 1 + v).head(6 * K) = dW_[v].row(b);
  }
}

void SpatialWrenchModel::evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                  std::vector<ContactWrenches>& out, bool with_derivatives) const {
  if (with_derivatives && derivative() == DerivativeSupport::None)
    throw std::logic_error(type_ + " model has no derivative: use a zeroth-order method (ne-zopgm or pbd-zopgm)");
  evaluateRows(frames, terrain, with_derivatives);
  for (Eigen::Index b = 0; b < static_cast<Eigen::Index>(frames.size()); ++b) assembleWrenches(b, with_derivatives, out[b]);
}

namespace {

using Mat6d = Eigen::Matrix<double, 6, 6>;
using Vec6d = Eigen::Matrix<double, 6, 1>;
using Wrenches = Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>>;

// The placement of a frame-R wrench (τ, F) about the foot point as a world wrench about the sphere
// centre, V = A (τ; F) with A = [R, [arm]× R; 0, R], and its derivative along one direction (the
// same formula with dR and darm: dA = [dR, [darm]× R + [arm]× dR; 0, dR]).
void placement(const Vec3& x, const Vec3& y, const Vec3& n, const Vec3& dx, const Vec3& dy, const Vec3& dn,
               const Vec3& arm, const Vec3& darm, Mat6d& A) {
  A.topLeftCorner<3, 1>() = dx;
  A.block<3, 1>(0, 1) = dy;
  A.block<3, 1>(0, 2) = dn;
  A.block<3, 1>(0, 3) = darm.cross(x) + arm.cross(dx);
  A.block<3, 1>(0, 4) = darm.cross(y) + arm.cross(dy);
  A.block<3, 1>(0, 5) = darm.cross(n) + arm.cross(dn);
  A.bottomLeftCorner<3, 3>().setZero();
  A.block<3, 1>(3, 3) = dx;
  A.block<3, 1>(3, 4) = dy;
  A.block<3, 1>(3, 5) = dn;
}

}  // namespace

void SpatialWrenchModel::assembleWrenches(Eigen::Index b, bool with_derivatives, ContactWrenches& o) const {
  if (row_[b] < 0) {
    o.V.setZero();
    if (with_derivatives)
      for (Mat6X& d : o.dV) d.setZero();
    return;
  }
  const int K = vertexCount();
  const Eigen::Index per_point = with_derivatives ? 4 : 1;
  const SpatialFrame& sf = frames_[b];
  const PlanarFrame& f = sf.planar;
  const double sigma = sigma_[b], dsigma = dsigma_[b];
  const Eigen::Index r = per_point * row_[b];
  const Wrenches W(rows_.row(r).data(), 6, K);
  Mat6d A;
  placement(f.x, f.y, f.n, f.x, f.y, f.n, f.arm, Vec3::Zero(), A);  // dA's formula at (R, arm) gives A
  if (!with_derivatives) {
    for (int k = 0; k < K; ++k) o.V.col(k).noalias() = A * (sigma * W.col(k));
    return;
  }
  // V = A σW; dV_i = dA_i σW + A (dφ_i (σ'W + σ ∂W/∂φ) + dβ_i σ ∂W/∂β + dγ_i σ ∂W/∂γ), the three
  // A-products formed once per vertex and shared by the six directions.
  const Wrenches Wphi(rows_.row(r + 1).data(), 6, K), Wbeta(rows_.row(r + 2).data(), 6, K),
      Wgamma(rows_.row(r + 3).data(), 6, K);
  Mat6d dA[6];
  for (int i = 0; i < 6; ++i)
    placement(f.x, f.y, f.n, f.dx.col(i), f.dy.col(i), f.dn.col(i), f.arm, f.darm.col(i), dA[i]);
  for (int k = 0; k < K; ++k) {
    const Vec6d w = sigma * W.col(k);
    const Vec6d ap = A * (dsigma * W.col(k) + sigma * Wphi.col(k));
    const Vec6d ab = A * (sigma * Wbeta.col(k));
    const Vec6d ag = A * (sigma * Wgamma.col(k));
    o.V.col(k).noalias() = A * w;
    for (int i = 0; i < 6; ++i)
      o.dV[i].col(k).noalias() = dA[i] * w + f.dphi[i] * ap + f.dbeta[i] * ab + sf.dgamma[i] * ag;
  }
}

}  // namespace nmdp
