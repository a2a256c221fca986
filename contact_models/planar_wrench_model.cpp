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

  for (int b = 0; b < B; ++b) {
    const PlanarFrame& f = frames_[b];
    ContactWrenches& o = out[b];
    double dsigma = 0.0;
    const double sigma = cutoffStep(geometry_, f.phi, &dsigma);
    for (int j = 0; j < K; ++j) {
      const double Fx = sigma * W_(b, 3 * j), Fz = sigma * W_(b, 3 * j + 1), ty = sigma * W_(b, 3 * j + 2);
      const Vec3 F = Fx * f.x + Fz * f.n;
      o.V.col(j).head<3>() = ty * f.y + f.arm.cross(F);
      o.V.col(j).tail<3>() = F;
      if (!with_derivatives) continue;
      const Vec3 w(W_(b, 3 * j), W_(b, 3 * j + 1), W_(b, 3 * j + 2));
      const Vec3 w_phi(dW_dphi_(b, 3 * j), dW_dphi_(b, 3 * j + 1), dW_dphi_(b, 3 * j + 2));
      const Vec3 w_beta(dW_dbeta_(b, 3 * j), dW_dbeta_(b, 3 * j + 1), dW_dbeta_(b, 3 * j + 2));
      for (int i = 0; i < 6; ++i) {
        // (δF_x, δF_z, δτ_y) from the features, the cut-off step included.
        const Vec3 dw = (dsigma * f.dphi[i]) * w + sigma * (f.dphi[i] * w_phi + f.dbeta[i] * w_beta);
        const Vec3 dF = dw[0] * f.x + Fx * f.dx.col(i) + dw[1] * f.n + Fz * f.dn.col(i);
        o.dV[i].col(j).head<3>() = dw[2] * f.y + ty * f.dy.col(i) + f.darm.col(i).cross(F) + f.arm.cross(dF);
        o.dV[i].col(j).tail<3>() = dF;
      }
    }
  }
}

}  // namespace nmdp
