// Curved test terrains with exact derivatives, so that checks of the contact models exercise the
// ∂n/∂p terms a plane leaves out (CoulombTestTerrains checks their derivatives).
#pragma once
#include <string>

#include "terrain/terrain.hpp"

namespace nmdp::test {

// z = a x² + b y² with the vertical distance φ = z − h(x, y), as heightfields do (DESIGN.md §8):
// ∇φ = (−2a x, −2b y, 1), n = ∇φ/‖∇φ‖, ∂n/∂p = (I − n nᵀ) ∇²φ / ‖∇φ‖.
class ParaboloidTerrain : public Terrain {
 public:
  ParaboloidTerrain(double a, double b) : a_(a), b_(b) {}
  void query(const Vec3& p, TerrainQuery& out, bool derivatives) const override {
    const Vec3 g(-2 * a_ * p.x(), -2 * b_ * p.y(), 1.0);
    const double norm = g.norm();
    out.distance = p.z() - a_ * p.x() * p.x() - b_ * p.y() * p.y();
    out.normal = g / norm;
    if (derivatives) {
      out.gradient = g;
      const Mat3 hessian = Vec3(-2 * a_, -2 * b_, 0.0).asDiagonal();
      out.normal_jacobian = (Mat3::Identity() - out.normal * out.normal.transpose()) * hessian / norm;
    }
  }
  std::string describe() const override { return "test paraboloid"; }

 private:
  double a_, b_;
};

// A ball of radius R centred at o, the ground outside it: φ = ‖p − o‖ − R, n = (p − o)/‖p − o‖.
class BallTerrain : public Terrain {
 public:
  BallTerrain(const Vec3& centre, double R) : o_(centre), R_(R) {}
  void query(const Vec3& p, TerrainQuery& out, bool derivatives) const override {
    const Vec3 v = p - o_;
    const double norm = v.norm();
    out.distance = norm - R_;
    out.normal = v / norm;
    if (derivatives) {
      out.gradient = out.normal;
      out.normal_jacobian = (Mat3::Identity() - out.normal * out.normal.transpose()) / norm;
    }
  }
  std::string describe() const override { return "test ball"; }
  const Vec3& centre() const { return o_; }
  double radius() const { return R_; }

 private:
  Vec3 o_;
  double R_;
};

}  // namespace nmdp::test
