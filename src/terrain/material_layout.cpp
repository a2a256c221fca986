#include "terrain/material_layout.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nmdp {

MaterialLayout::MaterialLayout(std::vector<MaterialPatch> patches, double blend_width)
    : materials_(static_cast<int>(patches.size()) + 1), patches_(std::move(patches)) {
  if (!(blend_width > 0.0) || !std::isfinite(blend_width))
    throw std::invalid_argument("MaterialLayout: blend_width must be positive and finite");
  kernel_.h = 0.5 * blend_width;
  for (const MaterialPatch& p : patches_) {
    const double reach = p.region.reach(kernel_);
    lower_.push_back(p.region.lower().array() - reach);
    upper_.push_back(p.region.upper().array() + reach);
  }
}

MaterialLayout::MaterialLayout(MaterialGrid grid) : materials_(grid.materials), grid_mode_(true), grid_(std::move(grid)) {
  if (grid_.nx < 1 || grid_.ny < 1 || grid_.material.size() != static_cast<size_t>(grid_.nx) * grid_.ny ||
      !(grid_.dx > 0) || !(grid_.dy > 0) || grid_.materials < 1)
    throw std::invalid_argument("MaterialLayout: an invalid material grid");
  for (int m : grid_.material)
    if (m < 0 || m >= grid_.materials) throw std::invalid_argument("MaterialLayout: a grid material out of range");
}

void MaterialLayout::weights(double x, double y, double* w, double* wx, double* wy) const {
  std::fill(w, w + materials_, 0.0);
  std::fill(wx, wx + materials_, 0.0);
  std::fill(wy, wy + materials_, 0.0);
  if (grid_mode_) gridWeights(x, y, w, wx, wy);
  else patchWeights(x, y, w, wx, wy);
}

void MaterialLayout::patchWeights(double x, double y, double* w, double* wx, double* wy) const {
  w[0] = 1.0;
  for (size_t p = 0; p < patches_.size(); ++p) {
    if (x < lower_[p].x() || x > upper_[p].x() || y < lower_[p].y() || y > upper_[p].y()) continue;
    double gx = 0.0, gy = 0.0;
    const double wp = patches_[p].region.weight(kernel_, x, y, gx, gy);
    if (wp == 0.0 && gx == 0.0 && gy == 0.0) continue;
    // Patch bands do not overlap: this is the only patch with weight here.
    w[p + 1] = wp;
    wx[p + 1] = gx;
    wy[p + 1] = gy;
    w[0] = 1.0 - wp;
    wx[0] = -gx;
    wy[0] = -gy;
    return;
  }
}

namespace {

// The three quadratic B-spline values (and derivatives per unit t) at the nodes nearest − 1,
// nearest, nearest + 1 of the coordinate t (in node spacings).
void splineRow(double t, int n, int nodes[3], double b[3], double db[3]) {
  t = std::clamp(t, -1.0, static_cast<double>(n));  // beyond: every node clamps to the border
  const double nearest = std::round(t);
  const double d = t - nearest;
  b[0] = 0.5 * (0.5 - d) * (0.5 - d);
  b[1] = 0.75 - d * d;
  b[2] = 0.5 * (0.5 + d) * (0.5 + d);
  db[0] = -(0.5 - d);
  db[1] = -2.0 * d;
  db[2] = 0.5 + d;
  for (int k = 0; k < 3; ++k) nodes[k] = std::clamp(static_cast<int>(nearest) - 1 + k, 0, n - 1);
}

}  // namespace

void MaterialLayout::gridWeights(double x, double y, double* w, double* wx, double* wy) const {
  int ix[3], iy[3];
  double bx[3], dbx[3], by[3], dby[3];
  const double tx = (x - grid_.x0) / grid_.dx, ty = (y - grid_.y0) / grid_.dy;
  if (!std::isfinite(tx) || !std::isfinite(ty)) {
    w[0] = NAN;
    return;
  }
  splineRow(tx, grid_.nx, ix, bx, dbx);
  splineRow(ty, grid_.ny, iy, by, dby);
  const int first = grid_.material[static_cast<size_t>(iy[0]) * grid_.nx + ix[0]];
  bool uniform = true;
  for (int j = 0; j < 3 && uniform; ++j)
    for (int i = 0; i < 3 && uniform; ++i) uniform = grid_.material[static_cast<size_t>(iy[j]) * grid_.nx + ix[i]] == first;
  if (uniform) {
    w[first] = 1.0;
    return;
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int m = grid_.material[static_cast<size_t>(iy[j]) * grid_.nx + ix[i]];
      w[m] += bx[i] * by[j];
      wx[m] += dbx[i] / grid_.dx * by[j];
      wy[m] += bx[i] * dby[j] / grid_.dy;
    }
}

std::string MaterialLayout::describe() const {
  std::ostringstream s;
  if (grid_mode_) {
    s << "material map " << grid_.nx << "x" << grid_.ny << " with " << materials_ << " materials";
    return s.str();
  }
  s << patches_.size() << " patch" << (patches_.size() == 1 ? "" : "es") << " (";
  for (size_t p = 0; p < patches_.size(); ++p) s << (p ? ", " : "") << "'" << patches_[p].name << "'";
  s << "), blend width " << 2.0 * kernel_.h << " m";
  return s.str();
}

}  // namespace nmdp
