#include "training/rft3d_samples.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace nmdp {

namespace {
constexpr double kPi = 3.14159265358979323846;

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

void checkGrid(const Rft3dGrid& grid, const char* who) {
  if (grid.depths.empty() || grid.betas.empty() || grid.directions.empty())
    throw std::invalid_argument(std::string(who) + ": the grid needs depths, betas and directions");
}

std::string describe(const RftMedium& medium, const Rft3dFoot& foot, const Rft3dGrid& grid, bool planar) {
  const RftCoefficients& c = medium.coefficients;
  std::ostringstream s;
  s << "3-D resistive force theory (the planar generic form of Li, Zhang, Goldman, Science 2013, applied in each "
       "element's vertical plane of motion, training/rft3d_law.hpp): A00 "
    << c.A00 << ", A10 " << c.A10 << ", B11 " << c.B11 << ", B01 " << c.B01 << ", Bm11 " << c.Bm11 << ", C11 "
    << c.C11 << ", C01 " << c.C01 << ", Cm11 " << c.Cm11 << ", D10 " << c.D10 << ", zeta " << number(medium.zeta)
    << " N/cm^3; foot " << rft3dShapeName(foot.shape) << " "
    << (foot.shape == Rft3dShape::Sphere ? "radius " + number(foot.radius)
                                         : "length " + number(foot.length) + " m, width " + number(foot.width))
    << " m, " << foot.elements << " elements per direction; " << grid.depths.size() << " depths x "
    << grid.betas.size() << " betas x " << (planar ? std::string("gamma 0") : std::to_string(grid.gammas.size()) + " gammas")
    << " x " << grid.directions.size() << " directions";
  return s.str();
}
}  // namespace

std::vector<Eigen::Vector3d> rft3dCubeDirections() {
  std::vector<Eigen::Vector3d> out;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (i || j || k) out.push_back(Eigen::Vector3d(i, j, k).normalized());
  return out;
}

std::vector<Eigen::Vector3d> rft3dFibonacciDirections(int count) {
  if (count < 1) throw std::invalid_argument("rft3dFibonacciDirections: count must be at least 1");
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<Eigen::Vector3d> out(count);
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / count, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    out[k] = Eigen::Vector3d(r * std::cos(k * golden), r * std::sin(k * golden), z);
  }
  return out;
}

std::vector<Eigen::Vector3d> rft3dCircleDirections(int count) {
  std::vector<Eigen::Vector3d> out;
  for (const RftTwist& t : rftCircleDirections(count)) out.push_back(Eigen::Vector3d(t.vx, 0.0, t.vz));
  return out;
}

ForceDataset rft3dSamples(const RftMedium& medium, const Rft3dFoot& foot, const Rft3dGrid& grid) {
  checkGrid(grid, "rft3dSamples");
  if (grid.gammas.empty()) throw std::invalid_argument("rft3dSamples: the grid needs gammas");
  const Eigen::Index K = static_cast<Eigen::Index>(grid.directions.size());
  const Eigen::Index N = static_cast<Eigen::Index>(grid.depths.size() * grid.betas.size() * grid.gammas.size()) * K;
  ForceDataset d;
  d.features.resize(N, 3);
  d.vertex.resize(N);
  d.wrench.resize(N, 6);
  Eigen::Index row = 0;
  for (double depth : grid.depths)
    for (double beta : grid.betas)
      for (double gamma : grid.gammas)
        for (Eigen::Index j = 0; j < K; ++j, ++row) {
          const Wrench6 w = rft3dWrench(medium, foot, depth, beta, gamma, grid.directions[j]);
          d.features.row(row) << depth, beta, gamma;
          d.vertex[row] = static_cast<int>(j);
          d.wrench.row(row) << w.torque.transpose(), w.force.transpose();
        }
  applySampleLayout(d, spatialSampleLayout());
  d.source = describe(medium, foot, grid, false);
  return d;
}

ForceDataset rft3dPlanarSamples(const RftMedium& medium, const Rft3dFoot& foot, const Rft3dGrid& grid,
                                double torque_centre) {
  checkGrid(grid, "rft3dPlanarSamples");
  if (!std::isfinite(torque_centre)) throw std::invalid_argument("rft3dPlanarSamples: the torque centre is not finite");
  for (const Eigen::Vector3d& v : grid.directions)
    if (v.y() != 0.0) throw std::invalid_argument("rft3dPlanarSamples: a planar direction must have y = 0");
  const Eigen::Index K = static_cast<Eigen::Index>(grid.directions.size());
  const Eigen::Index N = static_cast<Eigen::Index>(grid.depths.size() * grid.betas.size()) * K;
  ForceDataset d;
  d.features.resize(N, 2);
  d.vertex.resize(N);
  d.wrench.resize(N, 3);
  Eigen::Index row = 0;
  for (double depth : grid.depths)
    for (double beta : grid.betas) {
      // Q − P = L a, a = (sin β, 0, cos β) at γ = 0.
      const Eigen::Vector3d q_minus_p(torque_centre * std::sin(beta), 0.0, torque_centre * std::cos(beta));
      for (Eigen::Index j = 0; j < K; ++j, ++row) {
        const Wrench6 w = rft3dWrench(medium, foot, depth, beta, 0.0, grid.directions[j]);
        const double tau_q = w.torque.y() - q_minus_p.cross(w.force).y();
        d.features.row(row) << depth, beta;
        d.vertex[row] = static_cast<int>(j);
        d.wrench.row(row) << w.force.x(), w.force.z(), tau_q;
      }
    }
  applySampleLayout(d, planarSampleLayout());
  d.torque_centre = torque_centre;
  d.source = describe(medium, foot, grid, true) + ", torque centre " + number(torque_centre) + " m";
  return d;
}

}  // namespace nmdp
