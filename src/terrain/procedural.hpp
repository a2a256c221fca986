// Procedural terrain (DESIGN.md §8): an inclined plane plus a sum of Gaussian hills,
//
//     h(x, y) = offset + x tan(slope_x) + y tan(slope_y) + Σ_k height_k exp(−r_k² / (2 width_k²)),
//     r_k² = (x − cx_k)² + (y − cy_k)²,
//
// with analytic first and second derivatives, and the vertical distance φ = z − h(x, y) and normal
// of heightfield.hpp. slope_x is the angle the surface rises along +x (a rotation about −y), and
// slope_y along +y; the plane's normal is (−tan slope_x, −tan slope_y, 1)/‖·‖. `width` is the
// standard deviation of a hill (m) and `height` its peak (m; negative for a dip). On a pure slope φ
// is the vertical distance, larger than the Euclidean one by 1/cos(slope); use PlaneTerrain for an
// exact signed distance. query() never allocates.
#pragma once
#include <vector>

#include "terrain/heightfield.hpp"

namespace nmdp {

struct GaussianHill {
  double cx = 0.0, cy = 0.0;  // centre, m
  double height = 0.0;        // peak height above the slope, m (negative: a dip)
  double width = 1.0;         // standard deviation, m (> 0)
};

class ProceduralTerrain : public Terrain {
 public:
  // Throws std::invalid_argument for |slope| ≥ π/2, width ≤ 0 or non-finite numbers (the factory
  // checks configuration input first and throws InputError).
  ProceduralTerrain(double slope_x, double slope_y, double offset, std::vector<GaussianHill> hills);
  void query(const Vec3& p, TerrainQuery& out, bool derivatives) const override;
  std::string describe() const override;
  HeightSample sample(double x, double y, bool second) const;

 private:
  double slope_x_, slope_y_, offset_;
  double tan_x_, tan_y_;
  std::vector<GaussianHill> hills_;
};

}  // namespace nmdp
