#include "training/rft3d_law.hpp"

#include <cmath>

namespace nmdp {

Eigen::Vector3d rft3dStressPerDepth(const RftMedium& medium, const Eigen::Vector3d& n, const Eigen::Vector3d& v) {
  if (v.x() == 0.0 && v.y() == 0.0 && v.z() == 0.0) return Eigen::Vector3d::Zero();
  // r̂: v's horizontal direction; for a vertical v, n's (any choice gives the same stress for a
  // vertical v, by the planar law's mirror symmetry); x̂ when both are vertical.
  Eigen::Vector3d r(v.x(), v.y(), 0.0);
  double h = std::hypot(v.x(), v.y());
  if (h == 0.0) {
    r = Eigen::Vector3d(n.x(), n.y(), 0.0);
    h = std::hypot(n.x(), n.y());
  }
  if (h == 0.0) {
    r = Eigen::Vector3d::UnitX();
  } else if (r.y() == 0.0) {
    r.x() = r.x() > 0 ? 1.0 : -1.0;  // exact in the x–z plane (the planar reduction is bit-identical)
  } else {
    r /= h;
  }
  const double nr = n.x() * r.x() + n.y() * r.y(), nz = n.z();
  const double vr = v.x() * r.x() + v.y() * r.y();
  double sr = 0, sz = 0;
  // |n_p|: the element's area seen by the planar law; n is unit, so it is 1 when n lies in the
  // motion plane, taken exactly so (no rounding of the normal in the planar case).
  const bool in_plane = n.y() == 0.0 && r.y() == 0.0;
  const double weight = in_plane ? 1.0 : std::hypot(nr, nz);
  if (weight == 0.0) return Eigen::Vector3d::Zero();
  if (in_plane)
    rftStressPerDepth(medium, nr, nz, vr, v.z(), &sr, &sz);
  else
    rftStressPerDepth(medium, nr / weight, nz / weight, vr, v.z(), &sr, &sz);
  return Eigen::Vector3d(weight * sr * r.x(), weight * sr * r.y(), weight * sz);
}

}  // namespace nmdp
