// A plane n̂·p = offset, n̂ the normalized normal (offset in m along it): φ(p) = n̂·p − offset.
#pragma once
#include "terrain/terrain.hpp"

namespace nmdp {

class PlaneTerrain : public Terrain {
 public:
  explicit PlaneTerrain(const Vec3& normal = Vec3::UnitZ(), double offset = 0.0);  // normal need not be unit
  void query(const Vec3& p, TerrainQuery& out, bool derivatives) const override;
  std::string describe() const override;
  const Vec3& normal() const { return normal_; }
  double offset() const { return offset_; }

 private:
  Vec3 normal_;
  double offset_;
};

}  // namespace nmdp
