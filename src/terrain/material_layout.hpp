// Which ground material lies under a point (x, y): the weights w_m(x, y) ∈ [0, 1] of the materials
// m = 0..M−1, C¹ in (x, y), summing to 1, with their gradients. Material 0 is the ground's default
// (the scene's contacts.model). Two layouts:
//  * patches: material m ≥ 1 is patch m − 1 with the smoothed indicator of its region
//    (material_regions.hpp) and w_0 = 1 − Σ w_m. Patches lie at least their reaches apart (the
//    configuration reader checks it), so at most one patch weight is non-zero anywhere and every
//    weight stays in [0, 1]; inside a patch away from its band w = 1 exactly, outside every band
//    w_0 = 1 exactly.
//  * a material map on a grid (a heightfield's nodes): node (i, j) carries an integer material;
//    w_m = Σ_ij B((x − x_i)/dx) B((y − y_j)/dy) [material_ij = m] with B the quadratic B-spline
//    (a partition of unity, C¹), node indices clamped to the grid outside it. Where the 3 × 3
//    nodes around a point agree, w is exactly 1 for their material.
// weights() never allocates.
#pragma once
#include <string>
#include <vector>

#include "terrain/material_regions.hpp"

namespace nmdp {

struct MaterialPatch {
  std::string name;
  MaterialRegion region;
};

// Integer materials on the nodes (x0 + i dx, y0 + j dy), index j·nx + i (HeightGrid's layout).
struct MaterialGrid {
  double x0 = 0.0, y0 = 0.0, dx = 1.0, dy = 1.0;
  int nx = 0, ny = 0;
  std::vector<int> material;  // each in [0, materials)
  int materials = 1;
};

class MaterialLayout {
 public:
  // Patches given in order (material m = patch m − 1); blend_width > 0 (m). Overlap is the
  // caller's to check (regionSeparation against the reaches).
  MaterialLayout(std::vector<MaterialPatch> patches, double blend_width);
  explicit MaterialLayout(MaterialGrid grid);

  int materialCount() const { return materials_; }
  // Fills w, wx, wy (materialCount() entries each) at (x, y).
  void weights(double x, double y, double* w, double* wx, double* wy) const;
  std::string describe() const;

  const std::vector<MaterialPatch>& patches() const { return patches_; }
  const BlendKernel& kernel() const { return kernel_; }

 private:
  void patchWeights(double x, double y, double* w, double* wx, double* wy) const;
  void gridWeights(double x, double y, double* w, double* wx, double* wy) const;

  int materials_ = 1;
  std::vector<MaterialPatch> patches_;
  std::vector<Eigen::Vector2d> lower_, upper_;  // each patch's bounds widened by its reach
  BlendKernel kernel_;
  bool grid_mode_ = false;
  MaterialGrid grid_;
};

}  // namespace nmdp
