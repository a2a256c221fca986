// Height-function terrains (DESIGN.md §8): the surface z = h(x, y) with the vertical signed distance
//
//     φ(p) = z − h(x, y),   ∇φ = (−h_x, −h_y, 1),   n = ∇φ / ‖∇φ‖,
//     ∂n/∂p = (I − n nᵀ) / ‖∇φ‖ · ∂(∇φ)/∂p,   ∂(∇φ)/∂p = −[[h_xx, h_xy, 0], [h_xy, h_yy, 0], [0, 0, 0]].
//
// φ is the vertical, not the Euclidean, distance to the surface: it has the right sign and zero set,
// and agrees with the true distance to first order where the surface is flat (it is larger by
// 1/cos(slope) on a slope). HeightfieldTerrain interpolates heights on a regular grid;
// ProceduralTerrain (procedural.hpp) is analytic. Both fill a HeightSample and share heightToQuery.
#pragma once
#include <string>
#include <vector>

#include "terrain/terrain.hpp"

namespace nmdp {

// h and its first and second derivatives at one (x, y).
struct HeightSample {
  double h = 0.0;
  double hx = 0.0, hy = 0.0;              // first derivatives
  double hxx = 0.0, hxy = 0.0, hyy = 0.0; // second derivatives (only when asked for)
};

// Fills `out` from the height sample at (p.x, p.y) by the formulas above. Never allocates.
void heightToQuery(const Vec3& p, const HeightSample& s, TerrainQuery& out, bool derivatives);

// Heights on a regular grid: node (i, j) at (x0 + i dx, y0 + j dy) has height z[j * nx + i],
// i = 0..nx−1 along x, j = 0..ny−1 along y.
struct HeightGrid {
  double x0 = 0.0, y0 = 0.0;  // position of node (0, 0), m
  double dx = 1.0, dy = 1.0;  // spacing, m (> 0)
  int nx = 0, ny = 0;         // nodes along x and y (≥ 2 each)
  std::vector<double> z;      // nx·ny heights, m, row j (constant y) after row j − 1
};

// Reads the heights of a CSV file: one line per grid row j (y = y0 + j dy, the first data line is
// j = 0, i.e. the smallest y), comma-separated values along x (column i), surrounding blanks
// ignored; lines whose first non-blank character is '#' and blank lines are skipped. Origin and
// spacing are not in the file (they are left at their defaults). Throws InputError naming the file
// and the line and column for: a file that cannot be read, a non-numeric value, an empty cell or
// 'nan' (holes are not supported), an infinite value, rows of different lengths, fewer than 2×2
// values.
HeightGrid readHeightGridCsv(const std::string& path);

// A heightfield interpolated by a bicubic (tensor-product cubic) spline with not-a-knot end
// conditions, so h is C² inside the grid, interpolates every node, and reproduces exactly any
// polynomial of degree ≤ 3 in x and ≤ 3 in y (grids of ≥ 4 nodes along an axis; with 3 nodes
// the spline along that axis is the parabola through them, with 2 the straight line).
// Outside the grid the heights are clamped to the border: h(x, y) = h(clamp(x), clamp(y)), i.e.
// the border heights continue horizontally, so h is continuous there but its slope across the
// border drops to zero (a kink unless the border is flat; give a grid a flat margin if the robot
// may walk off it).
// The spline's node slopes (h_x, h_y, h_xy) are computed once at construction; query() evaluates
// one bicubic Hermite patch and never allocates. A NaN coordinate gives a NaN result.
class HeightfieldTerrain : public Terrain {
 public:
  // Throws std::invalid_argument for an invalid grid (sizes, spacing, non-finite values); input
  // from files is validated by readHeightGridCsv and the factory, which throw InputError.
  explicit HeightfieldTerrain(HeightGrid grid, std::string source = "");
  void query(const Vec3& p, TerrainQuery& out, bool derivatives) const override;
  std::string describe() const override;

  // h and its first derivatives; second derivatives too when `second` is set.
  HeightSample sample(double x, double y, bool second) const;
  const HeightGrid& grid() const { return grid_; }

 private:
  HeightGrid grid_;
  std::string source_;  // file name, for describe()
  // Node derivatives of the spline, same layout as grid_.z.
  std::vector<double> zx_, zy_, zxy_;
};

}  // namespace nmdp
