#include "training/rft3d_foot.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/named_enum.hpp"
#include "training/rft3d_law.hpp"

namespace nmdp {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxElements = 100000;

void requireFinite(double x, const char* what) {
  if (!std::isfinite(x)) throw std::invalid_argument(std::string("rft3dWrench: ") + what + " is not finite");
}

void checkFoot(const Rft3dFoot& foot) {
  if (foot.elements < 1 || foot.elements > kMaxElements)
    throw std::invalid_argument("rft3dWrench: the element count must be in [1, 100000]");
  if (foot.shape == Rft3dShape::Sphere) {
    if (!(foot.radius > 0) || !std::isfinite(foot.radius))
      throw std::invalid_argument("rft3dWrench: the sphere radius must be positive");
  } else if (!(foot.length > 0) || !(foot.width > 0) || !std::isfinite(foot.length) || !std::isfinite(foot.width)) {
    throw std::invalid_argument("rft3dWrench: the length and width must be positive");
  }
}

// Sums element forces and their moment about the foot point.
struct Accumulator {
  const RftMedium& medium;
  Eigen::Vector3d p, v;
  Wrench6 w;

  // One element at `r` (below the surface) with unit normal `n` and area `area`.
  void add(const Eigen::Vector3d& r, const Eigen::Vector3d& n, double area) {
    if (!(r.z() < 0)) return;
    const Eigen::Vector3d f = rft3dStressPerDepth(medium, n, v) * (-r.z() * area);
    w.force += f;
    w.torque += (r - p).cross(f);
  }
};

// A thin rectangle centre + s·e1 + u·e2, s ∈ [s0, s1], u ∈ [−w/2, w/2], normal n, on cells × cells.
void integrateRectangle(Accumulator& acc, const Eigen::Vector3d& centre, const Eigen::Vector3d& e1,
                        const Eigen::Vector3d& e2, double s0, double s1, double width, const Eigen::Vector3d& n,
                        int cells) {
  const double ds = (s1 - s0) / cells, du = width / cells;
  for (int i = 0; i < cells; ++i) {
    const double s = s0 + (i + 0.5) * ds;
    for (int k = 0; k < cells; ++k) {
      const double u = -0.5 * width + (k + 0.5) * du;
      acc.add(centre + s * e1 + u * e2, n, ds * du);
    }
  }
}

// The sphere of centre c and radius r: its leading part below z = 0, as rings about the lowest
// point: n(θ, φ) = (sin θ cos φ, sin θ sin φ, −cos θ), every point of a ring at one depth.
void integrateSphere(Accumulator& acc, const Eigen::Vector3d& c, double r, int rings) {
  const double k = c.z() / r;
  if (k >= 1.0) return;  // wholly above the surface
  const double theta0 = k <= -1.0 ? kPi : std::acos(k);
  const Eigen::Vector3d& v = acc.v;
  const double h = std::hypot(v.x(), v.y()), phi_v = std::atan2(v.y(), v.x());
  const double dtheta = theta0 / rings;
  for (int i = 0; i < rings; ++i) {
    const double theta = (i + 0.5) * dtheta;
    const double st = std::sin(theta), ct = std::cos(theta);
    // Leading: st·h·cos(φ − φ_v) > ct·v_z, an arc centred on φ_v of half-width `half`.
    const double a = st * h, b = ct * v.z();
    double half;  // a ≥ 0
    if (a == 0.0)
      half = b < 0 ? kPi : 0.0;
    else if (b <= -a)
      half = kPi;
    else if (b >= a)
      half = 0.0;
    else
      half = std::acos(b / a);
    if (half <= 0.0) continue;
    const int n = std::max(1, static_cast<int>(std::ceil(2 * rings * half / kPi - 1e-9)));
    const double dphi = 2 * half / n;
    for (int j = 0; j < n; ++j) {
      const double phi = phi_v - half + (j + 0.5) * dphi;
      const Eigen::Vector3d nn(st * std::cos(phi), st * std::sin(phi), -ct);
      acc.add(c + r * nn, nn, r * r * st * dtheta * dphi);
    }
  }
}

constexpr EnumName<Rft3dShape> kShapes[] = {
    {Rft3dShape::Sphere, "sphere"}, {Rft3dShape::Plate, "plate"}, {Rft3dShape::Blade, "blade"}};
}  // namespace

const char* rft3dShapeName(Rft3dShape shape) { return nameOf(kShapes, shape); }

Eigen::Matrix3d rft3dFootFrame(double beta, double gamma) {
  return (Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(-gamma, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Wrench6 rft3dWrench(const RftMedium& medium, const Rft3dFoot& foot, double depth, double beta, double gamma,
                    const Eigen::Vector3d& velocity) {
  requireFinite(beta, "beta");
  requireFinite(gamma, "gamma");
  return rft3dWrenchInFrame(medium, foot, depth, rft3dFootFrame(beta, gamma), velocity);
}

Wrench6 rft3dWrenchInFrame(const RftMedium& medium, const Rft3dFoot& foot, double depth,
                           const Eigen::Matrix3d& foot_frame, const Eigen::Vector3d& velocity) {
  checkFoot(foot);
  requireFinite(depth, "the depth");
  requireFinite(medium.zeta, "zeta");
  if (!foot_frame.allFinite()) throw std::invalid_argument("rft3dWrench: the foot frame is not finite");
  for (int i = 0; i < 3; ++i) requireFinite(velocity[i], "the velocity");
  Accumulator acc{medium, Eigen::Vector3d(0, 0, depth), velocity, {}};
  if (velocity.isZero(0.0)) return acc.w;
  const Eigen::Vector3d t = foot_frame.col(0), l = foot_frame.col(1), a = foot_frame.col(2);
  switch (foot.shape) {
    case Rft3dShape::Sphere:
      integrateSphere(acc, acc.p + foot.radius * Eigen::Vector3d::UnitZ(), foot.radius, foot.elements);
      break;
    case Rft3dShape::Plate:
      integrateRectangle(acc, acc.p, t, l, -0.5 * foot.length, 0.5 * foot.length, foot.width, a, foot.elements);
      break;
    case Rft3dShape::Blade:
      integrateRectangle(acc, acc.p, a, l, 0.0, foot.length, foot.width, t, foot.elements);
      break;
  }
  return acc.w;
}

}  // namespace nmdp
