// The 3-D contact model (spatial_wrench_model.hpp): dV/dξ against central differences on a plane, a
// tilted plane and curved terrains with the leg leaning in β and γ, near and away from the cut-off
// band; heading invariance; the planar placement at γ = 0; zero above the cut-off; no allocation.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "contact_derivative_check.hpp"
#include "contact_models/foot_frame.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/spatial_rbf_function.hpp"
#include "spatial_sand.hpp"
#include "terrain/plane.hpp"
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"
#include "test_support.hpp"
#include "test_terrains.hpp"

namespace nmdp::test {
namespace {

// Cut-off 0.01 m above the surface, band 0.008 m: the sand fixture's depths reach 0.01 m.
const SpatialGeometry kGeometry{0.01, 0.008};

std::shared_ptr<const SpatialRbfFunction> sandFunction() {
  static const auto f = std::make_shared<const SpatialRbfFunction>(sandSpatialRbf());
  return f;
}

// A contact on `terrain` at `depth` below/above the surface (φ = depth), leg leaning by β toward the
// heading and γ toward the lateral axis, above the point (x, y) of `where` (exact on planes; on
// curved terrain the sphere is moved along the normal once, so the features are close to the asked
// ones).
ContactFrame contactAt(const Terrain& terrain, const Vec3& where, double depth, double beta, double gamma,
                       double radius, const Vec3& lateral, bool lateral_rotates) {
  TerrainQuery q;
  terrain.query(where, q, false);
  Vec3 p = where - q.distance * Vec3::UnitZ();  // near the surface
  terrain.query(p, q, false);
  p -= q.distance * q.normal;
  terrain.query(p, q, false);
  const Vec3 n = q.normal;
  ContactFrame f;
  f.radius = radius;
  f.position = p + (depth + radius - q.distance) * n;
  f.lateral = lateral.normalized();
  f.lateral_rotates = lateral_rotates;
  const Vec3 y = (f.lateral - f.lateral.dot(n) * n).normalized(), x = y.cross(n);
  f.leg_axis = std::cos(gamma) * std::sin(beta) * x + std::sin(gamma) * y + std::cos(gamma) * std::cos(beta) * n;
  return f;
}

// Four contacts: deep, shallow, inside the cut-off band and just below it, leaning in β and γ.
std::vector<ContactFrame> fourContacts(const Terrain& terrain, double radius, bool lateral_rotates) {
  const double depths[4] = {-0.04, -0.012, 0.006, 0.0025};
  const double betas[4] = {0.3, -0.5, 0.2, -0.1};
  const double gammas[4] = {-0.25, 0.35, 0.45, -0.6};
  const Vec3 laterals[4] = {Vec3(0.1, 1.0, 0.05), Vec3(-0.2, 1.0, 0.3), Vec3(1.0, 0.2, 0.0), Vec3(0.3, 0.9, -0.2)};
  std::vector<ContactFrame> out;
  for (int c = 0; c < 4; ++c)
    out.push_back(contactAt(terrain, Vec3(0.1 * c, -0.05 * c, 0.0), depths[c], betas[c], gammas[c], radius,
                            laterals[c], lateral_rotates));
  return out;
}

TEST(SpatialWrenchModel, FeaturesAreTheLeansOfTheLeg) {
  const PlaneTerrain tilted(Vec3(0.2, -0.15, 1.0), 0.05);
  const ContactFrame f = contactAt(tilted, Vec3(0.1, 0.2, 0.0), -0.02, 0.3, -0.4, 0.02, Vec3(0.2, 1.0, 0.1), true);
  SpatialFrame s;
  computeSpatialFrame(f, tilted, kGeometry, false, s);
  EXPECT_NEAR(s.planar.phi, -0.02, 1e-14);
  EXPECT_NEAR(s.planar.beta, 0.3, 1e-14);
  EXPECT_NEAR(s.gamma, -0.4, 1e-14);
  // The foot point: arm = P − c = −r n.
  EXPECT_LT((s.planar.arm + 0.02 * s.planar.n).norm(), 1e-15);
}

// dV/dξ against central differences of the model, step 2e-7 (m, rad): the cut-off band (8 mm) has
// the largest third derivative, truncation there is ~3e-8 of the scale (1e-6 gives ~7e-7, falling
// as h²), rounding ~1e-9.
void checkDerivatives(const ContactModel& model, const Terrain& terrain, const std::string& what) {
  VertexDerivativeCheck check;
  check.rotation_step = check.translation_step = 2e-7;
  check.tolerance = 1e-6;
  for (bool lateral_rotates : {true, false})
    for (double radius : {0.0, 0.02}) {
      const std::vector<ContactFrame> frames = fourContacts(terrain, radius, lateral_rotates);
      const std::string label = what + ", radius " + std::to_string(radius) + (lateral_rotates ? "" : ", fixed lateral");
      const VertexDerivativeResult r = checkVertexDerivative(model, frames, terrain, check, label);
      std::cout << "[ info ] dV/dxi vs central differences, " << label << ": " << r.worst << "\n";
      for (const ContactWrenches& w : r.analytic) EXPECT_GT(w.V.cwiseAbs().maxCoeff(), 0.0) << label;
    }
}

TEST(SpatialWrenchModel, FootFrameAtPlacesTheFeaturesAsked) {
  // nmdp wrench's placement: on a plane, φ = depth, β = angle, γ = lateral angle; γ = 0 is the
  // planar placement exactly.
  for (const Vec3& normal : {Vec3(0, 0, 1), Vec3(0.2, -0.15, 1.0)}) {
    const PlaneTerrain plane(normal, 0.03);
    const ContactFrame f = footFrameAt(plane, 0.2, -0.1, -0.015, 0.35, -0.5, 0.02);
    SpatialFrame s;
    computeSpatialFrame(f, plane, kGeometry, false, s);
    EXPECT_NEAR(s.planar.phi, -0.015, 1e-14);
    EXPECT_NEAR(s.planar.beta, 0.35, 1e-14);
    EXPECT_NEAR(s.gamma, -0.5, 1e-14);
    const ContactFrame planar = footFrameAt(plane, 0.2, -0.1, -0.015, 0.35, 0.02);
    const ContactFrame upright = footFrameAt(plane, 0.2, -0.1, -0.015, 0.35, 0.0, 0.02);
    EXPECT_EQ(planar.leg_axis, upright.leg_axis);
    EXPECT_EQ(planar.position, upright.position);
  }
}

TEST(SpatialWrenchModel, DerivativesMatchCentralDifferences) {
  const SpatialWrenchModel model(sandFunction(), kGeometry, "rbf");
  checkDerivatives(model, PlaneTerrain(), "flat");
  checkDerivatives(model, PlaneTerrain(Vec3(0.2, -0.15, 1.0), 0.05), "tilted plane");
  checkDerivatives(model, ParaboloidTerrain(0.8, -0.5), "paraboloid");
  checkDerivatives(model, BallTerrain(Vec3(0.1, -0.2, -0.8), 0.8), "ball");
  // A random function with every feature derivative non-trivial (γ included) and a Gaussian kernel.
  std::mt19937 rng(13);
  const SpatialWrenchModel random(std::make_shared<const SpatialRbfFunction>(randomSpatialRbf(RbfKernel::Gaussian, true, rng, 15, 4)),
                                  kGeometry, "rbf");
  checkDerivatives(random, PlaneTerrain(Vec3(-0.3, 0.25, 1.0), -0.1), "random, tilted plane");
  checkDerivatives(random, BallTerrain(Vec3(0.1, -0.2, -0.8), 0.8), "random, ball");
}

TEST(SpatialWrenchModel, ValuesWithoutDerivativesEqualThoseWithThem) {
  const SpatialWrenchModel model(sandFunction(), kGeometry, "rbf");
  const PlaneTerrain terrain(Vec3(0.2, -0.15, 1.0), 0.05);
  const auto frames = fourContacts(terrain, 0.02, true);
  std::vector<ContactWrenches> a(4), b(4);
  for (int c = 0; c < 4; ++c) a[c].resize(26), b[c].resize(26);
  model.evaluate(frames, terrain, a, true);
  model.evaluate(frames, terrain, b, false);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(a[c].V, b[c].V) << c;
}

TEST(SpatialWrenchModel, TurningTheContactAboutTheNormalTurnsItsWrenches) {
  const SpatialWrenchModel model(sandFunction(), kGeometry, "rbf");
  const PlaneTerrain terrain(Vec3(0.2, -0.15, 1.0), 0.05);
  const std::vector<ContactFrame> frames = fourContacts(terrain, 0.02, true);
  std::vector<ContactWrenches> base(4), turned(4);
  for (int c = 0; c < 4; ++c) base[c].resize(26), turned[c].resize(26);
  model.evaluate(frames, terrain, base, false);
  for (double angle : {0.3, -1.2, 2.5}) {
    const Mat3 Q = Eigen::AngleAxisd(angle, terrain.normal()).toRotationMatrix();
    std::vector<ContactFrame> moved = frames;
    for (ContactFrame& f : moved) {  // about the normal through the sphere centre (and the foot point)
      f.leg_axis = Q * f.leg_axis;
      f.lateral = Q * f.lateral;
    }
    model.evaluate(moved, terrain, turned, false);
    for (int c = 0; c < 4; ++c) {
      Mat6X expected(6, 26);
      expected.topRows<3>() = Q * base[c].V.topRows<3>();
      expected.bottomRows<3>() = Q * base[c].V.bottomRows<3>();
      EXPECT_LT(relativeError(turned[c].V, expected), 1e-12) << "angle " << angle << ", contact " << c;
    }
  }
}

// A planar function seen as a spatial one: (F_x, F_z, τ_y) → (0, τ_y, 0, F_x, 0, F_z), γ ignored.
class SagittalFunction : public SpatialFeatureFunction {
 public:
  explicit SagittalFunction(std::shared_ptr<const RbfFunction> planar) : planar_(std::move(planar)) {}
  int vertexCount() const override { return planar_->vertexCount(); }
  DerivativeSupport derivative() const override { return DerivativeSupport::Analytic; }
  std::string describe() const override { return "sagittal"; }
  void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W, std::array<Eigen::MatrixXd, 3>* dW) const override {
    const Eigen::MatrixX2d f2 = features.leftCols<2>();
    Eigen::MatrixXd w, dphi, dbeta;
    planar_->evaluate(f2, w, &dphi, &dbeta);
    const auto widen = [&](const Eigen::MatrixXd& p, Eigen::MatrixXd& out) {
      out.setZero(p.rows(), 6 * vertexCount());
      for (int j = 0; j < vertexCount(); ++j) {
        out.col(6 * j + 1) = p.col(3 * j + 2);
        out.col(6 * j + 3) = p.col(3 * j);
        out.col(6 * j + 5) = p.col(3 * j + 1);
      }
    };
    widen(w, W);
    if (!dW) return;
    widen(dphi, (*dW)[0]);
    widen(dbeta, (*dW)[1]);
    (*dW)[2].setZero(features.rows(), 6 * vertexCount());
  }

 private:
  std::shared_ptr<const RbfFunction> planar_;
};

TEST(SpatialWrenchModel, InTheSagittalPlaneItPlacesWrenchesAsThePlanarModel) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RbfParameters p;
  p.spec.kernel = RbfKernel::ThinPlate;
  p.centres.resize(10, 2);
  for (int i = 0; i < 10; ++i) p.centres.row(i) << -0.03 + 0.04 * u(rng), 0.8 * u(rng);
  p.weights = Eigen::MatrixXd::NullaryExpr(10, 15, [&]() { return 50.0 * u(rng); });
  const auto planar_function = std::make_shared<const RbfFunction>(p);
  const PlanarWrenchModel planar(planar_function, planarGeometryOf(kGeometry), "rbf");
  const SpatialWrenchModel spatial(std::make_shared<const SagittalFunction>(planar_function), kGeometry, "rbf");
  for (const Vec3& normal : {Vec3(0, 0, 1), Vec3(0.2, -0.15, 1.0)}) {
    const PlaneTerrain terrain(normal, 0.02);
    std::vector<ContactFrame> frames;
    const double depths[3] = {-0.03, -0.01, 0.005};
    for (int c = 0; c < 3; ++c)  // γ = 0: the leg in the sagittal plane
      frames.push_back(contactAt(terrain, Vec3(0.1 * c, 0.05, 0.0), depths[c], 0.4 - 0.3 * c, 0.0, 0.01 * c,
                                 Vec3(0.2 * c, 1.0, 0.1), c != 1));
    std::vector<ContactWrenches> a(3), b(3);
    for (int c = 0; c < 3; ++c) a[c].resize(5), b[c].resize(5);
    planar.evaluate(frames, terrain, a, true);
    spatial.evaluate(frames, terrain, b, true);
    for (int c = 0; c < 3; ++c) {
      // Different groupings of the same products: a few ulps of the largest entry.
      EXPECT_LE(ulpsOfLargest(a[c].V, b[c].V), 8.0) << c;
      for (int i = 0; i < 6; ++i) EXPECT_LE(ulpsOfLargest(a[c].dV[i], b[c].dV[i]), 64.0) << c << ", xi_" << i;
    }
  }
}

TEST(SpatialWrenchModel, ZeroAtAndAboveTheCutoffWithoutEvaluatingTheFunction) {
  // A function that fails the test when evaluated for a point at or above the cut-off.
  class Watch : public SpatialFeatureFunction {
   public:
    int vertexCount() const override { return 26; }
    DerivativeSupport derivative() const override { return DerivativeSupport::Analytic; }
    std::string describe() const override { return "watch"; }
    void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W, std::array<Eigen::MatrixXd, 3>* dW) const override {
      sandFunction()->evaluate(features, W, dW);
    }
    bool evaluateRows(const Eigen::MatrixX3d& features, Eigen::Index count, bool derivatives,
                      SpatialRows& rows) const override {
      for (Eigen::Index b = 0; b < count; ++b) EXPECT_LT(features(b, 0), kGeometry.cutoff);
      counted += count;
      return sandFunction()->evaluateRows(features, count, derivatives, rows);
    }
    mutable Eigen::Index counted = 0;
  };
  const auto watch = std::make_shared<Watch>();
  const SpatialWrenchModel model(watch, kGeometry, "rbf");
  const PlaneTerrain terrain;
  std::vector<ContactFrame> frames = {contactAt(terrain, Vec3::Zero(), kGeometry.cutoff, 0.2, 0.1, 0.0, Vec3::UnitY(), true),
                                      contactAt(terrain, Vec3(1, 0, 0), 0.05, 0.2, 0.1, 0.02, Vec3::UnitY(), true),
                                      contactAt(terrain, Vec3(2, 0, 0), -0.02, 0.2, 0.1, 0.02, Vec3::UnitY(), true)};
  std::vector<ContactWrenches> out(3);
  for (ContactWrenches& w : out) {
    w.resize(26);
    w.V.setConstant(7.0);
    for (Mat6X& d : w.dV) d.setConstant(7.0);
  }
  model.evaluate(frames, terrain, out, true);
  EXPECT_EQ(watch->counted, 1);
  for (int c = 0; c < 2; ++c) {
    EXPECT_TRUE(out[c].V.isZero(0.0)) << c;
    for (const Mat6X& d : out[c].dV) EXPECT_TRUE(d.isZero(0.0)) << c;
  }
  EXPECT_GT(out[2].V.cwiseAbs().maxCoeff(), 100.0);
  // Just inside the band the wrenches are small and continuous toward zero.
  frames[0] = contactAt(terrain, Vec3::Zero(), kGeometry.cutoff - 1e-5, 0.2, 0.1, 0.02, Vec3::UnitY(), true);
  model.evaluate(frames, terrain, out, false);
  EXPECT_GT(out[0].V.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(out[0].V.cwiseAbs().maxCoeff(), 1e-6 * out[2].V.cwiseAbs().maxCoeff());
}

TEST(SpatialWrenchModel, NoAllocationOnceWarmedUp) {
  const SpatialWrenchModel model(sandFunction(), kGeometry, "rbf");
  const PlaneTerrain terrain(Vec3(0.1, -0.05, 1.0), 0.0);
  const auto frames = fourContacts(terrain, 0.02, true);
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& w : out) w.resize(model.vertexCount());
  model.evaluate(frames, terrain, out, true);  // warm up
  model.evaluate(frames, terrain, out, false);
  std::vector<ContactFrame> fewer(frames.begin(), frames.begin() + 2);
  const AllocationCount count = countAllocations([&] {
    model.evaluate(frames, terrain, out, true);
    model.evaluate(frames, terrain, out, false);
    model.evaluate(fewer, terrain, out, true);
  });
  if (NMDP_COUNTS_MALLOC) {
    EXPECT_EQ(count.mallocs, 0) << "SpatialWrenchModel(RBF)::evaluate allocated once warmed up";
  } else {
    std::cout << "[ info ] allocation counting unavailable in this build (sanitizer or non-glibc)\n";
  }
}

TEST(SpatialWrenchModel, DescribesItselfAndItsConfiguration) {
  const SpatialWrenchModel built(sandFunction(), kGeometry, "rbf");
  EXPECT_TRUE(built.configuration().is_null());
  EXPECT_NE(built.describe().find("45 centres, 26 vertices"), std::string::npos) << built.describe();
}

}  // namespace
}  // namespace nmdp::test
