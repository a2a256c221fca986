#include "contact_models/planar_wrench_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nmdp {

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

PlanarWrenchModel::PlanarWrenchModel(std::shared_ptr<const FeatureWrenchFunction> function, PlanarGeometry geometry,
                                     std::string type)
    : function_(std::move(function)), geometry_(geometry), type_(std::move(type)) {}

std::string PlanarWrenchModel::describe() const {
  std::ostringstream s;
  s << type_ << ": " << function_->describe() << ", torque centre " << geometry_.torque_centre << " m, cut-off "
    << geometry_.cutoff << " m (band " << geometry_.cutoff_width << " m)";
  return s.str();
}

void PlanarWrenchModel::evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                                 std::vector<ContactWrenches>& out, bool with_derivatives) const {
  if (with_derivatives && derivative() == DerivativeSupport::None)
    throw std::logic_error(type_ + " model has no derivative: use a zeroth-order method (ne-zopgm or pbd-zopgm)");
  const int B = static_cast<int>(frames.size());
  const int K = vertexCount();
  frames_.resize(B);
  features_.resize(B, 2);
  for (int b = 0; b < B; ++b) {
    computePlanarFrame(frames[b], terrain, geometry_, with_derivatives, frames_[b]);
    features_(b, 0) = frames_[b].phi;
    features_(b, 1) = frames_[b].beta;
  }
  function_->evaluate(features_, W_, with_derivatives ? &dW_dphi_ : nullptr, with_derivatives ? &dW_dbeta_ : nullptr);

  // Per contact, in matrix form over the K vertices (rows of Wb: F_x, F_z, τ_y):
  //   F = [x n] Wb(0:1),  τ = y Wb(2) + [arm]× F,
  //   dF = [x n] dWb(0:1) + [dx dn] Wb(0:1),  dτ = y dWb(2) + dy Wb(2) + [darm]× F + [arm]× dF.
  Eigen::Matrix<double, 3, Eigen::Dynamic>& Wb = planar_;
  Eigen::Matrix<double, 3, Eigen::Dynamic>& dWb = planar_d_;
  Eigen::Matrix<double, 3, Eigen::Dynamic>& F = force_;
  Eigen::Matrix<double, 3, Eigen::Dynamic>& dF = force_d_;
  Wb.resize(3, K);
  dWb.resize(3, K);
  F.resize(3, K);
  dF.resize(3, K);
  for (int b = 0; b < B; ++b) {
    const PlanarFrame& f = frames_[b];
    ContactWrenches& o = out[b];
    double dsigma = 0.0;
    const double sigma = cutoffStep(geometry_, f.phi, &dsigma);
    Wb = sigma * Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>, 0, Eigen::InnerStride<>>(
                     W_.data() + b, 3, K, Eigen::InnerStride<>(static_cast<Eigen::Index>(W_.rows())));
    Eigen::Matrix<double, 3, 2> xn;
    xn << f.x, f.n;
    F.noalias() = xn * Wb.topRows<2>();
    o.V.topRows<3>().noalias() = f.y * Wb.row(2);
    o.V.topRows<3>().noalias() += skew(f.arm) * F;
    o.V.bottomRows<3>() = F;
    if (!with_derivatives) continue;
    // Contiguous copies of this contact's rows, so the six direction updates vectorize.
    using Strided = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>, 0, Eigen::InnerStride<>>;
    const Eigen::InnerStride<> stride(static_cast<Eigen::Index>(W_.rows()));
    raw_.resize(3, K);
    raw_phi_.resize(3, K);
    raw_beta_.resize(3, K);
    raw_ = Strided(W_.data() + b, 3, K, stride);
    raw_phi_ = Strided(dW_dphi_.data() + b, 3, K, stride);
    raw_beta_ = Strided(dW_dbeta_.data() + b, 3, K, stride);
    const auto& Wraw = raw_;
    const auto& Wphi = raw_phi_;
    const auto& Wbeta = raw_beta_;
    const Mat3 arm_x = skew(f.arm);
    for (int i = 0; i < 6; ++i) {
      // (δF_x, δF_z, δτ_y) from the features, the cut-off step included.
      dWb = (dsigma * f.dphi[i]) * Wraw + (sigma * f.dphi[i]) * Wphi + (sigma * f.dbeta[i]) * Wbeta;
      Eigen::Matrix<double, 3, 2> dxn;
      dxn << f.dx.col(i), f.dn.col(i);
      dF.noalias() = xn * dWb.topRows<2>();
      dF.noalias() += dxn * Wb.topRows<2>();
      Mat6X& d = o.dV[i];
      d.topRows<3>().noalias() = f.y * dWb.row(2);
      d.topRows<3>().noalias() += f.dy.col(i) * Wb.row(2);
      d.topRows<3>().noalias() += skew(f.darm.col(i)) * F;
      d.topRows<3>().noalias() += arm_x * dF;
      d.bottomRows<3>() = dF;
    }
  }
}

}  // namespace nmdp
