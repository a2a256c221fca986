// The regions of material patches on the ground and their C¹ weights (the scene's terrain.patches).
//
// A patch's weight is the indicator of its region smoothed by a separable kernel κ(u)κ(v), κ the
// quadratic B-spline stretched over [−h, h], h = blend_width / 2:
//
//     w(x, y) = ∫∫_region κ(x − u) κ(y − v) du dv  ∈ [0, 1].
//
// κ is C¹, so w is C² everywhere, corners included (a signed-distance step would kink on the
// region's medial axis, which meets the boundary at every corner). Across a straight edge w rises
// from 0 to 1 over the band of width blend_width centred on the edge; it is exactly 1 where the
// square [x ± h] × [y ± h] lies inside the region and exactly 0 where it lies outside (no kernel
// sum is evaluated there). Beyond a corner the band reaches h√2, beyond a circle h.
//
//  * rectangle  [x0, x1] × [y0, y1]: w is the product of two 1-D steps (closed form);
//  * circle     centre c, radius r > h: w = S(r − |p − c|), S the step of a straight edge
//               (the 2-D kernel's profile is not radial; a circle uses the edge's profile along
//               its radius, C¹ because r > h keeps the centre out of the band);
//  * polygon    simple, either orientation: by Green's theorem w = ∮ S(u − x) κ(y − v) dv, each edge
//               integrated exactly (the integrand is a polynomial of degree ≤ 5 between the
//               kernel's knots: three-point Gauss–Legendre per piece).
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

namespace nmdp {

// The blending kernel of half-width h (m): κ(s), its derivative, and the step S(s) = ∫_{−∞}^s κ.
struct BlendKernel {
  double h = 0.025;
  double density(double s) const;     // κ(s), 1/m; zero for |s| ≥ h
  double slope(double s) const;       // κ'(s), 1/m²
  double step(double s) const;        // S(s): exactly 0 for s ≤ −h, exactly 1 for s ≥ h
};

struct MaterialRegion {
  enum class Kind { Rectangle, Circle, Polygon };
  Kind kind = Kind::Rectangle;
  // Rectangle: the corners (x0, y0), (x1, y0), (x1, y1), (x0, y1); polygon: its points as given
  // (either orientation); circle: empty.
  std::vector<Eigen::Vector2d> points;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // circle
  double radius = 0.0;                               // circle, m
  double orientation = 1.0;                          // polygon: +1 counter-clockwise, −1 clockwise

  static MaterialRegion rectangle(const Eigen::Vector2d& min, const Eigen::Vector2d& max);
  static MaterialRegion circle(const Eigen::Vector2d& centre, double radius);
  static MaterialRegion polygon(std::vector<Eigen::Vector2d> points);  // call polygonProblem first

  // Weight w of the point (x, y) and its gradient (wx, wy). Never allocates.
  double weight(const BlendKernel& kernel, double x, double y, double& wx, double& wy) const;
  // How far beyond the region its weight is non-zero (m): h for a circle, h√2 beyond a corner.
  double reach(const BlendKernel& kernel) const;
  // Axis-aligned bounds of the region (before the reach).
  Eigen::Vector2d lower() const;
  Eigen::Vector2d upper() const;
  bool contains(const Eigen::Vector2d& p) const;
};

// Why `points` is not a usable polygon ("" when it is): fewer than 3 points, a repeated point, a
// zero area, an edge folding back on the previous one, or two edges that cross or touch.
std::string polygonProblem(const std::vector<Eigen::Vector2d>& points);

// The distance between two regions (m), 0 when they intersect or one contains the other.
double regionSeparation(const MaterialRegion& a, const MaterialRegion& b);

}  // namespace nmdp
