#include "contact_models/planar_wrench_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nmdp {

std::string planarGeometryProblem(const PlanarGeometry& g) {
  const auto bad = [](double x) { return !std::isfinite(x) || std::abs(x) > kMaxGeometryLength; };
  const std::string bound = std::to_string(static_cast<int>(kMaxGeometryLength));
  if (bad(g.torque_centre)) return "torque_centre must be a finite length of at most " + bound + " m";
  if (bad(g.cutoff)) return "cutoff must be a finite height of at most " + bound + " m";
  if (bad(g.cutoff_width) || !(g.cutoff_width > 0.0))
    return "cutoff_width must be a positive length of at most " + bound + " m (the band below the cut-off)";
  return "";
}

double cutoffStep(const PlanarGeometry& g, double phi, double* dsigma) {
  if (!(g.cutoff_width > 0.0)) {  // a hard cut-off, as the published model has
    if (dsigma) *dsigma = 0.0;
    return phi < g.cutoff ? 1.0 : 0.0;
  }
  const double t = (g.cutoff - phi) / g.cutoff_width;  // 0 at the cut-off, 1 at the band's bottom
  if (t >= 1.0) {
    if (dsigma) *dsigma = 0.0;
    return 1.0;
  }
  if (t <= 0.0) {
    if (dsigma) *dsigma = 0.0;
    return 0.0;
  }
  const double t2 = t * t, t3 = t2 * t;
  if (dsigma) *dsigma = -(30.0 * t2 * t2 - 60.0 * t3 + 30.0 * t2) / g.cutoff_width;
  return t3 * (10.0 - 15.0 * t + 6.0 * t2);
}

void computePlanarFrame(const ContactFrame& frame, const Terrain& terrain, const PlanarGeometry& geometry,
                        bool with_derivatives, PlanarFrame& out) {
  TerrainQuery q;
  terrain.query(frame.position, q, with_derivatives);
  const Vec3& n = q.normal;
  const Vec3& a = frame.leg_axis;
  const Vec3& l = frame.lateral;
  const Vec3 y_raw = l - l.dot(n) * n;
  const double y_norm = y_raw.norm();
  if (!(y_norm > 1e-9))
    throw std::domain_error("contact lateral axis is parallel to the terrain normal: the sagittal plane is undefined");
  out.n = n;
  out.a = a;
  out.y = y_raw / y_norm;
  out.x = out.y.cross(n);
  out.phi = q.distance - frame.radius;
  const double s = a.dot(out.x), t = a.dot(n);
  out.beta = std::atan2(s, t);
  out.arm = -frame.radius * n + geometry.torque_centre * a;
  if (!with_derivatives) return;

  for (int i = 0; i < 6; ++i) {
    Vec3 dn = Vec3::Zero(), da = Vec3::Zero(), dl = Vec3::Zero();
    double dphi = 0.0;
    if (i < 3) {  // rotation δω = e_i about the sphere centre: link-fixed axes turn
      const Vec3 w = Vec3::Unit(i);
      da = w.cross(a);
      if (frame.lateral_rotates) dl = w.cross(l);
    } else {      // translation δp = e_{i−3}: the terrain seen by the contact changes
      dn = q.normal_jacobian.col(i - 3);
      dphi = q.gradient[i - 3];
    }
    const Vec3 dy_raw = dl - dl.dot(n) * n - dn * n.dot(l) - n * dn.dot(l);
    const Vec3 dy = (dy_raw - out.y * out.y.dot(dy_raw)) / y_norm;
    const Vec3 dx = dy.cross(n) + out.y.cross(dn);
    const double ds = da.dot(out.x) + a.dot(dx);
    const double dt = da.dot(n) + a.dot(dn);
    out.dphi[i] = dphi;
    out.dbeta[i] = (t * ds - s * dt) / (s * s + t * t);
    out.dn.col(i) = dn;
    out.da.col(i) = da;
    out.dx.col(i) = dx;
    out.dy.col(i) = dy;
    out.darm.col(i) = -frame.radius * dn + geometry.torque_centre * da;
  }
}

ContactFeatureInfo planarDepthFeature() {
  return {"depth", "m",
          "phi: signed distance of the foot sphere's surface to the terrain (the terrain distance of the sphere "
          "centre minus the radius), negative below it"};
}

ContactFeatureInfo planarBetaFeature() {
  return {"beta", "rad",
          "beta: sagittal leg angle atan2(a.x_s, a.n), the rotation about y_s taking the terrain normal n to the leg "
          "axis a (from the foot up the leg); y_s = the contact's lateral axis projected onto the tangent plane, "
          "x_s = y_s x n; positive when the leg leans toward x_s (forward)"};
}

PlanarWrenchModel::PlanarWrenchModel(std::shared_ptr<const FeatureWrenchFunction> function, PlanarGeometry geometry,
                                     std::string type, nlohmann::json source)
    : function_(std::move(function)), geometry_(geometry), type_(std::move(type)), source_(std::move(source)) {}

nlohmann::json PlanarWrenchModel::configuration() const {
  if (source_.is_null()) return nullptr;
  nlohmann::json out = source_;
  out["type"] = type_;
  out["torque_centre"] = geometry_.torque_centre;
  out["cutoff"] = geometry_.cutoff;
  out["cutoff_width"] = geometry_.cutoff_width;
  return out;
}

std::string PlanarWrenchModel::describe() const {
  std::ostringstream s;
  s << type_ << ": " << function_->describe() << ", torque centre " << geometry_.torque_centre << " m, cut-off "
    << geometry_.cutoff << " m (band " << geometry_.cutoff_width << " m)";
  return s.str();
}

std::vector<ContactFeatureInfo> PlanarWrenchModel::featureInfo() const {
  return {planarDepthFeature(), planarBetaFeature()};
}

void PlanarWrenchModel::features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                 Eigen::Ref<Eigen::MatrixXd> out) const {
  requireFeatureShape(type_.c_str(), frames.size(), out, 2);
  PlanarFrame f;
  for (std::size_t b = 0; b < frames.size(); ++b) {
    computePlanarFrame(frames[b], terrain, geometry_, false, f);
    out(static_cast<Eigen::Index>(b), 0) = f.phi;
    out(static_cast<Eigen::Index>(b), 1) = f.beta;
  }
}

void PlanarWrenchModel::evaluateRows(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                     bool with_derivatives) const {
  const Eigen::Index B = static_cast<Eigen::Index>(frames.size());
  const int K = vertexCount();
  frames_.resize(B);
  sigma_.resize(B);
  dsigma_.resize(B);
  row_.resize(B);
  features_.resize(B, 2);
  // Contacts at or above the cut-off (σ = dσ/dφ = 0) have V = dV = 0 exactly; the feature function
  // is evaluated for the others only, packed first (the rest of the batch is not computed).
  Eigen::Index count = 0;
  for (Eigen::Index b = 0; b < B; ++b) {
    PlanarFrame& f = frames_[b];
    computePlanarFrame(frames[b], terrain, geometry_, with_derivatives, f);
    sigma_[b] = cutoffStep(geometry_, f.phi, &dsigma_[b]);
    row_[b] = sigma_[b] != 0.0 || dsigma_[b] != 0.0 ? count++ : -1;
  }
  for (Eigen::Index b = 0, inactive = count; b < B; ++b) {
    const Eigen::Index r = row_[b] >= 0 ? row_[b] : inactive++;
    features_(r, 0) = frames_[b].phi;
    features_(r, 1) = frames_[b].beta;
  }
  const Eigen::Index per_point = with_derivatives ? 3 : 1;
  if (function_->evaluateRows(features_, count, with_derivatives, rows_)) return;
  // Generic functions: the whole batch in contact order, repacked into rows.
  for (Eigen::Index b = 0; b < B; ++b) {
    features_(b, 0) = frames_[b].phi;
    features_(b, 1) = frames_[b].beta;
    if (row_[b] >= 0) row_[b] = b;
  }
  function_->evaluate(features_, W_, with_derivatives ? &dW_dphi_ : nullptr, with_derivatives ? &dW_dbeta_ : nullptr);
  rows_.resize(3 * B, 3 * K);
  for (Eigen::Index b = 0; b < B; ++b) {
    rows_.row(per_point * b) = W_.row(b);
    if (!with_derivatives) continue;
    rows_.row(3 * b + 1) = dW_dphi_.row(b);
    rows_.row(3 * b + 2) = dW_dbeta_.row(b);
  }
}

void PlanarWrenchModel::evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                 std::vector<ContactWrenches>& out, bool with_derivatives) const {
  if (with_derivatives && derivative() == DerivativeSupport::None)
    throw std::logic_error(type_ + " model has no derivative: use a zeroth-order method (ne-zopgm or pbd-zopgm)");
  evaluateRows(frames, terrain, with_derivatives);
  for (Eigen::Index b = 0; b < static_cast<Eigen::Index>(frames.size()); ++b) assembleWrenches(b, with_derivatives, out[b]);
}

namespace {

// Per contact, with the planar rows Wb = σ W (F_x, F_z, τ_y of each vertex) and
//   A = [[arm]× x, [arm]× n, y; x, n, 0]   (6×3: F = x F_x + n F_z, τ = y τ_y + arm × F):
//   V = A Wb,
//   dV_i = dA_i Wb + A dWb_i,  dWb_i = dφ_i (σ' W + σ ∂W/∂φ) + dβ_i σ ∂W/∂β,
// so A (σ' W + σ ∂W/∂φ) and A σ ∂W/∂β are formed once per vertex and shared by the six directions.
// Columns of 6 are split 4 + 2 so that each maps onto whole SIMD registers.
using V4 = Eigen::Vector4d;
using V2 = Eigen::Vector2d;
using Planar = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>;
struct Columns {  // a 6×3 matrix whose (5, 2) entry is 0, rows 0..3 and 4..5
  V4 h[3];
  V2 t[2];
  void set(const Vec3& arm, const Vec3& darm, const Vec3& x, const Vec3& dx, const Vec3& n, const Vec3& dn,
           const Vec3& y) {
    const Vec3 c0 = darm.cross(x) + arm.cross(dx), c1 = darm.cross(n) + arm.cross(dn);
    h[0] = V4(c0[0], c0[1], c0[2], dx[0]);
    h[1] = V4(c1[0], c1[1], c1[2], dn[0]);
    h[2] = V4(y[0], y[1], y[2], 0.0);
    t[0] = V2(dx[1], dx[2]);
    t[1] = V2(dn[1], dn[2]);
  }
};

}  // namespace

void PlanarWrenchModel::assembleWrenches(Eigen::Index b, bool with_derivatives, ContactWrenches& o) const {
  if (row_[b] < 0) {
    o.V.setZero();
    if (with_derivatives)
      for (Mat6X& d : o.dV) d.setZero();
    return;
  }
  const int K = vertexCount();
  const Eigen::Index per_point = with_derivatives ? 3 : 1;
  const PlanarFrame& f = frames_[b];
  const double sigma = sigma_[b], dsigma = dsigma_[b];
  const Eigen::Index r = per_point * row_[b];
  const Planar W(rows_.row(r).data(), 3, K);
  Columns A;
  A.set(f.arm, Vec3::Zero(), f.x, f.x, f.n, f.n, f.y);  // dA's formula at (arm, x, n) gives A
  double* v = o.V.data();
  if (!with_derivatives) {
    for (int k = 0; k < K; ++k, v += 6) {
      const double w0 = sigma * W(0, k), w1 = sigma * W(1, k), w2 = sigma * W(2, k);
      V4::Map(v) = A.h[0] * w0 + A.h[1] * w1 + A.h[2] * w2;
      V2::Map(v + 4) = A.t[0] * w0 + A.t[1] * w1;
    }
    return;
  }
  const Planar Wphi(rows_.row(r + 1).data(), 3, K), Wbeta(rows_.row(r + 2).data(), 3, K);
  Columns dA[6];
  double* dv[6];
  for (int i = 0; i < 6; ++i) {
    dA[i].set(f.arm, f.darm.col(i), f.x, f.dx.col(i), f.n, f.dn.col(i), f.dy.col(i));
    dv[i] = o.dV[i].data();
  }
  for (int k = 0; k < K; ++k) {
    const double w0 = sigma * W(0, k), w1 = sigma * W(1, k), w2 = sigma * W(2, k);
    const double p0 = dsigma * W(0, k) + sigma * Wphi(0, k), p1 = dsigma * W(1, k) + sigma * Wphi(1, k),
                 p2 = dsigma * W(2, k) + sigma * Wphi(2, k);
    const double q0 = sigma * Wbeta(0, k), q1 = sigma * Wbeta(1, k), q2 = sigma * Wbeta(2, k);
    const V4 aph = A.h[0] * p0 + A.h[1] * p1 + A.h[2] * p2, aqh = A.h[0] * q0 + A.h[1] * q1 + A.h[2] * q2;
    const V2 apt = A.t[0] * p0 + A.t[1] * p1, aqt = A.t[0] * q0 + A.t[1] * q1;
    V4::Map(v + 6 * k) = A.h[0] * w0 + A.h[1] * w1 + A.h[2] * w2;
    V2::Map(v + 6 * k + 4) = A.t[0] * w0 + A.t[1] * w1;
    for (int i = 0; i < 6; ++i) {
      const Columns& d = dA[i];
      V4::Map(dv[i] + 6 * k) = d.h[0] * w0 + d.h[1] * w1 + d.h[2] * w2 + f.dphi[i] * aph + f.dbeta[i] * aqh;
      V2::Map(dv[i] + 6 * k + 4) = d.t[0] * w0 + d.t[1] * w1 + f.dphi[i] * apt + f.dbeta[i] * aqt;
    }
  }
}

}  // namespace nmdp
