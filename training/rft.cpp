#include "training/rft.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/named_enum.hpp"

namespace nmdp {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kNewtonPerCubicCentimetre = 1e6;  // N/cm³ → N/m³

void requireFinite(double x, const char* what) {
  if (!std::isfinite(x)) throw std::invalid_argument(std::string("rftWrench: ") + what + " is not finite");
}

void checkFoot(const RftFoot& foot) {
  if (!(foot.width > 0)) throw std::invalid_argument("rftWrench: the foot width must be positive");
  if (foot.elements < 1) throw std::invalid_argument("rftWrench: the foot needs at least one element");
  if (foot.shape == RftShape::Disc ? !(foot.radius > 0) : !(foot.length > 0))
    throw std::invalid_argument("rftWrench: the foot size (length or radius) must be positive");
  requireFinite(foot.torque_centre, "the torque centre");
}

// Sums element forces and their moment about the torque centre.
struct Accumulator {
  const RftMedium& medium;
  double width, qx, qz;  // out-of-plane extent; torque centre
  RftTwist twist;
  PlanarWrench w;

  // One midpoint element at (rx, rz) below the surface, normal (nx, nz), length ds.
  void add(double rx, double rz, double nx, double nz, double ds) {
    const double dx = rx - qx, dz = rz - qz;
    const double vx = twist.vx + twist.omega * dz, vz = twist.vz - twist.omega * dx;
    double sx = 0, sz = 0;
    rftStressPerDepth(medium, nx, nz, vx, vz, &sx, &sz);
    const double scale = -rz * ds * width;  // |z| dA
    const double fx = sx * scale, fz = sz * scale;
    w.fx += fx;
    w.fz += fz;
    w.wy += dz * fx - dx * fz;
  }
};

// A thin flat plate from (x0, z0) to (x1, z1) with unit normal (nx, nz) (either side): its part
// below z = 0, on `elements` midpoint elements.
void integrateSegment(Accumulator& acc, double x0, double z0, double x1, double z1, double nx, double nz,
                      int elements) {
  if (z0 >= 0 && z1 >= 0) return;
  double s0 = 0, s1 = 1;  // the submerged part, as fractions of the segment
  if (z0 >= 0) s0 = z0 / (z0 - z1);
  if (z1 >= 0) s1 = z0 / (z0 - z1);
  const double length = std::hypot(x1 - x0, z1 - z0) * (s1 - s0);
  const double ds = length / elements;
  for (int i = 0; i < elements; ++i) {
    const double s = s0 + (s1 - s0) * (i + 0.5) / elements;
    acc.add(x0 + s * (x1 - x0), z0 + s * (z1 - z0), nx, nz, ds);
  }
}

// The circle of centre (cx, cz) and radius r, a closed body: its leading arc below z = 0. Points
// are c + r (sin φ, −cos φ), φ = 0 at the lowest point.
void integrateDisc(Accumulator& acc, double cx, double cz, double r, int elements) {
  const double c = cz / r;
  if (c >= 1.0) return;                            // wholly above the surface
  const double phi0 = c <= -1.0 ? kPi : std::acos(c);  // submerged: |φ| < φ0
  // On a circle n·v(point) = n·v(centre), so the leading side is the half circle around the
  // centre's direction of motion ψ (n(ψ) = v_c / |v_c|).
  const double vcx = acc.twist.vx + acc.twist.omega * (cz - acc.qz);
  const double vcz = acc.twist.vz - acc.twist.omega * (cx - acc.qx);
  if (vcx == 0.0 && vcz == 0.0) return;  // spinning in place: no side leads
  const double psi = std::atan2(vcx, -vcz);
  for (int shift = -1; shift <= 1; ++shift) {
    const double lo = std::max(-phi0, psi - kPi / 2 + 2 * kPi * shift);
    const double hi = std::min(phi0, psi + kPi / 2 + 2 * kPi * shift);
    if (!(hi > lo)) continue;
    const int n = std::max(1, static_cast<int>(std::ceil(elements * (hi - lo) / (2 * phi0) - 1e-9)));
    const double dphi = (hi - lo) / n;
    for (int i = 0; i < n; ++i) {
      const double phi = lo + (i + 0.5) * dphi;
      const double nx = std::sin(phi), nz = -std::cos(phi);
      acc.add(cx + r * nx, cz + r * nz, nx, nz, r * dphi);
    }
  }
}

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}
constexpr EnumName<RftShape> kRftShapes[] = {{RftShape::Plate, "plate"}, {RftShape::Blade, "blade"}, {RftShape::Disc, "disc"}};
}  // namespace

const char* rftShapeName(RftShape shape) { return nameOf(kRftShapes, shape); }

RftAlpha rftAlpha(const RftCoefficients& c, double beta, double gamma) {
  RftAlpha a;
  a.z = c.A00 + c.A10 * std::cos(2 * beta) + c.B11 * std::sin(2 * beta + gamma) + c.B01 * std::sin(gamma) +
        c.Bm11 * std::sin(-2 * beta + gamma);
  a.x = c.C11 * std::cos(2 * beta + gamma) + c.C01 * std::cos(gamma) + c.Cm11 * std::cos(-2 * beta + gamma) +
        c.D10 * std::sin(2 * beta);
  return a;
}

void rftStressPerDepth(const RftMedium& medium, double nx, double nz, double vx, double vz, double* sx, double* sz) {
  *sx = *sz = 0.0;
  if (vx == 0.0 && vz == 0.0) return;
  // e = ±x̂ toward n's horizontal part; for a horizontal element either choice gives the same
  // stress (the mirror invariance), so take v's side.
  const double ex = nx > 0 ? 1.0 : nx < 0 ? -1.0 : (vx >= 0 ? 1.0 : -1.0);
  const double beta = std::atan2(nz, nx * ex) + kPi / 2;
  const double gamma = -std::atan2(vz, vx * ex);
  const RftAlpha a = rftAlpha(medium.coefficients, beta, gamma);
  const double k = medium.zeta * kNewtonPerCubicCentimetre;
  *sx = -k * a.x * ex;
  *sz = k * a.z;
}

PlanarWrench rftWrench(const RftMedium& medium, const RftFoot& foot, double depth, double angle,
                       const RftTwist& twist) {
  checkFoot(foot);
  requireFinite(depth, "the depth");
  requireFinite(angle, "the angle");
  requireFinite(twist.vx, "the twist");
  requireFinite(twist.vz, "the twist");
  requireFinite(twist.omega, "the twist");
  requireFinite(medium.zeta, "zeta");
  const double ax = std::sin(angle), az = std::cos(angle);  // leg axis
  const double tx = az, tz = -ax;                           // forward axis of the foot
  const double px = 0.0, pz = depth;                         // foot point
  Accumulator acc{medium, foot.width, px + foot.torque_centre * ax, pz + foot.torque_centre * az, twist, {}};
  switch (foot.shape) {
    case RftShape::Plate: {
      const double h = 0.5 * foot.length;
      integrateSegment(acc, px - h * tx, pz - h * tz, px + h * tx, pz + h * tz, ax, az, foot.elements);
      break;
    }
    case RftShape::Blade:
      integrateSegment(acc, px, pz, px + foot.length * ax, pz + foot.length * az, tx, tz, foot.elements);
      break;
    case RftShape::Disc:
      integrateDisc(acc, px, pz + foot.radius, foot.radius, foot.elements);
      break;
  }
  return acc.w;
}

std::vector<RftTwist> rftCircleDirections(int count) {
  if (count < 1) throw std::invalid_argument("rftCircleDirections: count must be at least 1");
  std::vector<RftTwist> out(count);
  for (int j = 0; j < count; ++j) {
    const double psi = 2 * kPi * j / count;
    out[j] = {std::sin(psi), -std::cos(psi), 0.0};
  }
  return out;
}

std::vector<RftTwist> rftCubeDirections(double rotation_radius) {
  if (!(rotation_radius > 0) || !std::isfinite(rotation_radius))
    throw std::invalid_argument("rftCubeDirections: rotation_radius must be positive");
  std::vector<RftTwist> out;
  for (int i = -1; i <= 1; ++i)
    for (int k = -1; k <= 1; ++k)
      for (int l = -1; l <= 1; ++l)
        if (i || k || l) out.push_back({double(i), double(k), l / rotation_radius});
  return out;
}

ForceDataset rftSamples(const RftMedium& medium, const RftFoot& foot, const RftGrid& grid) {
  if (grid.depths.empty() || grid.angles.empty() || grid.directions.empty())
    throw std::invalid_argument("rftSamples: the grid needs depths, angles and directions");
  const Eigen::Index K = static_cast<Eigen::Index>(grid.directions.size());
  const Eigen::Index N = static_cast<Eigen::Index>(grid.depths.size() * grid.angles.size()) * K;
  ForceDataset d;
  d.features.resize(N, 2);
  d.vertex.resize(N);
  d.wrench.resize(N, 3);
  Eigen::Index row = 0;
  for (double depth : grid.depths)
    for (double angle : grid.angles)
      for (Eigen::Index j = 0; j < K; ++j, ++row) {
        const PlanarWrench w = rftWrench(medium, foot, depth, angle, grid.directions[j]);
        d.features.row(row) << depth, angle;
        d.vertex[row] = static_cast<int>(j);
        d.wrench.row(row) << w.fx, w.fz, w.wy;
      }
  applySampleLayout(d, planarSampleLayout());
  d.torque_centre = foot.torque_centre;
  const RftCoefficients& c = medium.coefficients;
  std::ostringstream s;
  s << "resistive force theory (Li, Zhang, Goldman, Science 2013), generic form: A00 " << c.A00 << ", A10 " << c.A10
    << ", B11 " << c.B11 << ", B01 " << c.B01 << ", Bm11 " << c.Bm11 << ", C11 " << c.C11 << ", C01 " << c.C01
    << ", Cm11 " << c.Cm11 << ", D10 " << c.D10 << ", zeta " << number(medium.zeta) << " N/cm^3; foot "
    << rftShapeName(foot.shape) << " "
    << (foot.shape == RftShape::Disc ? "radius " + number(foot.radius) : "length " + number(foot.length))
    << " m, width " << number(foot.width) << " m, torque centre " << number(foot.torque_centre) << " m, "
    << foot.elements << " elements; " << grid.depths.size() << " depths x " << grid.angles.size() << " angles x "
    << K << " directions";
  d.source = s.str();
  return d;
}

}  // namespace nmdp
