#include "terrain/procedural.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nmdp {

ProceduralTerrain::ProceduralTerrain(double slope_x, double slope_y, double offset, std::vector<GaussianHill> hills)
    : slope_x_(slope_x), slope_y_(slope_y), offset_(offset), hills_(std::move(hills)) {
  const double right = 0.5 * M_PI;
  if (!(std::abs(slope_x) < right) || !(std::abs(slope_y) < right))
    throw std::invalid_argument("procedural terrain: slopes must be finite angles in (-pi/2, pi/2) rad");
  if (!std::isfinite(offset)) throw std::invalid_argument("procedural terrain: the offset must be finite");
  for (const GaussianHill& k : hills_) {
    if (!std::isfinite(k.cx) || !std::isfinite(k.cy) || !std::isfinite(k.height))
      throw std::invalid_argument("procedural terrain: hill centre and height must be finite");
    if (!(k.width > 0.0) || !std::isfinite(k.width))
      throw std::invalid_argument("procedural terrain: hill width must be positive and finite");
  }
  tan_x_ = std::tan(slope_x);
  tan_y_ = std::tan(slope_y);
}

HeightSample ProceduralTerrain::sample(double x, double y, bool second) const {
  HeightSample s;
  s.h = offset_ + tan_x_ * x + tan_y_ * y;
  s.hx = tan_x_;
  s.hy = tan_y_;
  for (const GaussianHill& k : hills_) {
    const double ex = x - k.cx, ey = y - k.cy;
    const double inv_w2 = 1.0 / (k.width * k.width);
    const double g = k.height * std::exp(-0.5 * (ex * ex + ey * ey) * inv_w2);
    s.h += g;
    s.hx -= g * ex * inv_w2;
    s.hy -= g * ey * inv_w2;
    if (second) {
      s.hxx += g * (ex * ex * inv_w2 - 1.0) * inv_w2;
      s.hxy += g * ex * ey * inv_w2 * inv_w2;
      s.hyy += g * (ey * ey * inv_w2 - 1.0) * inv_w2;
    }
  }
  return s;
}

void ProceduralTerrain::query(const Vec3& p, TerrainQuery& out, bool derivatives) const {
  heightToQuery(p, sample(p.x(), p.y(), derivatives), out, derivatives);
}

std::string ProceduralTerrain::describe() const {
  std::ostringstream s;
  s << "procedural: slope (" << slope_x_ << ", " << slope_y_ << ") rad, offset " << offset_ << " m, "
    << hills_.size() << " Gaussian hill" << (hills_.size() == 1 ? "" : "s");
  return s.str();
}

}  // namespace nmdp
