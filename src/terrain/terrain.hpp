// Terrain: a signed distance φ(p) (negative below the surface), the surface normal n(p), and their
// derivatives with respect to the query point (DESIGN.md §8). Implementations: plane, heightfield
// (bicubic on a grid, from a file), procedural hills and slopes. Heightfields use the vertical
// distance φ = z − h(x, y) and n = ∇φ/‖∇φ‖.
#pragma once
#include <memory>
#include <string>

#include "multibody/spatial.hpp"

namespace nmdp {

struct TerrainQuery {
  double distance = 0.0;             // φ(p)
  Vec3 normal = Vec3::UnitZ();       // n(p), unit
  Vec3 gradient = Vec3::UnitZ();     // ∇φ(p)            (filled when derivatives are requested)
  Mat3 normal_jacobian = Mat3::Zero();  // ∂n/∂p       (filled when derivatives are requested)
};

class Terrain {
 public:
  virtual ~Terrain() = default;
  // Never allocates; thread-compatible (const).
  virtual void query(const Vec3& p, TerrainQuery& out, bool derivatives) const = 0;
  virtual std::string describe() const = 0;  // one line for logs and output files
};

}  // namespace nmdp
