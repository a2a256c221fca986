// What the contact models report they read at a contact (ContactModel::featureInfo/features):
//  * known geometry gives known features: a foot d deep gives depth −d, a leg tilted by ±0.2 rad in
//    the sagittal plane gives β = ±0.2 (positive leaning forward), a lateral lean gives γ;
//  * the features are the ones evaluate() used: a feature function that records its input sees
//    exactly the reported rows, and the RBF evaluated at the reported features gives the forces the
//    model returned (the Coulomb cone's normal force is k (max(0, −depth)^p + ζ));
//  * the patched model reports the columns of the material with the largest weight across a
//    patch border, NaN in the columns that material lacks, and its index and weight;
//  * a wrong shape of `out` is a std::logic_error; features() allocates nothing.
#define NMDP_COUNT_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/foot_frame.hpp"
#include "contact_models/patched_model.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/spatial_wrench_model.hpp"
#include "terrain/plane.hpp"
#include "test_allocation_counter.hpp"
#include "test_support.hpp"
#include "test_terrains.hpp"

namespace nmdp::test {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kRadius = 0.02;  // m, the project quadruped's foot sphere

std::unique_ptr<ContactModel> planarSand() {
  return makeRbfModel({{"file", sourcePath("data/granular/rft_quadruped_rbf.h5")}}, ConfigContext{"test", ""});
}

std::unique_ptr<ContactModel> spatialSand() {
  return makeRbfModel({{"file", sourcePath("data/granular/rft3d_quadruped_rbf.h5")}}, ConfigContext{"test", ""});
}

std::vector<std::string> namesOf(const ContactModel& model) {
  std::vector<std::string> names;
  for (const ContactFeatureInfo& c : model.featureInfo()) names.push_back(c.name);
  return names;
}

Eigen::MatrixXd featuresOf(const ContactModel& model, const std::vector<ContactFrame>& frames, const Terrain& terrain) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(frames.size()), static_cast<Eigen::Index>(model.featureInfo().size()));
  model.features(frames, terrain, out);
  return out;
}

// A foot whose sphere's lowest point is `depth` from a horizontal plane at z = 0, the leg axis
// a = (cos γ sin β, sin γ, cos γ cos β) in the world, lateral axis y.
ContactFrame footOnFlat(double x, double depth, double beta, double gamma) {
  ContactFrame f;
  f.radius = kRadius;
  f.position = Vec3(x, 0.1, kRadius + depth);
  f.leg_axis = Vec3(std::cos(gamma) * std::sin(beta), std::sin(gamma), std::cos(gamma) * std::cos(beta));
  f.lateral = Vec3::UnitY();
  return f;
}

// Contacts on curved or tilted ground with legs and lateral axes in general directions, some deep,
// some in the cut-off band and one in the air.
std::vector<ContactFrame> generalFrames(const Terrain& terrain) {
  const double depths[5] = {-0.03, -0.012, -0.004, 0.002, 0.2};
  std::vector<ContactFrame> frames;
  for (int c = 0; c < 5; ++c) {
    ContactFrame f = footFrameAt(terrain, 0.1 * c - 0.2, 0.05 * c, depths[c], 0.35 - 0.2 * c, 0.1 * c - 0.25, kRadius);
    f.lateral = Vec3(0.1 * c - 0.15, 1.0, 0.05 * c).normalized();
    f.lateral_rotates = c % 2 == 0;
    frames.push_back(f);
  }
  return frames;
}

// Feature functions that remember the features they were given (the models call their generic
// evaluate() in contact order when the function has no evaluateRows()).
class RecordingPlanarFunction : public FeatureWrenchFunction {
 public:
  explicit RecordingPlanarFunction(const FeatureWrenchFunction& f) : f_(f) {}
  int vertexCount() const override { return f_.vertexCount(); }
  DerivativeSupport derivative() const override { return f_.derivative(); }
  std::string describe() const override { return "recording " + f_.describe(); }
  void evaluate(const Eigen::MatrixX2d& features, Eigen::MatrixXd& W, Eigen::MatrixXd* dW_dphi,
                Eigen::MatrixXd* dW_dbeta) const override {
    seen = features;
    f_.evaluate(features, W, dW_dphi, dW_dbeta);
  }
  mutable Eigen::MatrixXd seen;

 private:
  const FeatureWrenchFunction& f_;
};

class RecordingSpatialFunction : public SpatialFeatureFunction {
 public:
  explicit RecordingSpatialFunction(const SpatialFeatureFunction& f) : f_(f) {}
  int vertexCount() const override { return f_.vertexCount(); }
  DerivativeSupport derivative() const override { return f_.derivative(); }
  std::string describe() const override { return "recording " + f_.describe(); }
  void evaluate(const Eigen::MatrixX3d& features, Eigen::MatrixXd& W, std::array<Eigen::MatrixXd, 3>* dW) const override {
    seen = features;
    f_.evaluate(features, W, dW);
  }
  mutable Eigen::MatrixXd seen;

 private:
  const SpatialFeatureFunction& f_;
};

// Bit for bit, a NaN matching a NaN (the patched model's missing columns).
bool identical(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.array() == b.array() || (a.array().isNaN() && b.array().isNaN())).all();
}

// Features of feet placed on tilted planes carry the round-off of positions of order 1 m.
constexpr double kPlacement = 1e-14;

void expectShapeIsChecked(const ContactModel& model, const std::vector<ContactFrame>& frames, const Terrain& terrain) {
  const Eigen::Index B = static_cast<Eigen::Index>(frames.size());
  const Eigen::Index F = static_cast<Eigen::Index>(model.featureInfo().size());
  for (const auto& [rows, cols] : {std::pair{B + 1, F}, std::pair{B - 1, F}, std::pair{B, F + 1}, std::pair{B, F - 1},
                                   std::pair{Eigen::Index{0}, Eigen::Index{0}}}) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(rows, cols);
    EXPECT_THROW(model.features(frames, terrain, out), std::logic_error) << model.describe() << ": " << rows << " x " << cols;
  }
  Eigen::MatrixXd none(0, F);
  EXPECT_NO_THROW(model.features({}, terrain, none)) << model.describe();
}

// --- Coulomb ---------------------------------------------------------------------------------

TEST(ContactFeatures, CoulombReportsTheDepthItsConeReads) {
  const CoulombModel model;
  ASSERT_EQ(namesOf(model), std::vector<std::string>{"depth"});
  EXPECT_EQ(model.featureInfo()[0].unit, "m");
  // On a tilted plane, feet 0, 3.5 and 10 mm deep and one 5 mm in the air.
  const PlaneTerrain tilted(Vec3(0.1, -0.2, 1.0), 0.03);
  const Vec3 n = tilted.normal().normalized();
  const double depths[4] = {0.0, -0.0035, -0.01, 0.005};
  std::vector<ContactFrame> frames;
  for (int c = 0; c < 4; ++c) {
    ContactFrame f;
    f.radius = kRadius;
    const Vec3 on_plane = Vec3(0.3 * c, -0.1 * c, 0.0) + (0.03 - n.dot(Vec3(0.3 * c, -0.1 * c, 0.0))) * n;
    f.position = on_plane + (kRadius + depths[c]) * n;
    frames.push_back(f);
  }
  const Eigen::MatrixXd features = featuresOf(model, frames, tilted);
  std::vector<ContactWrenches> V(frames.size());
  model.evaluate(frames, tilted, V, false);
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(features(c, 0), depths[c], kPlacement) << c;
    // Every vertex's normal component is k (d^p + ζ) with d = max(0, −depth).
    const double normal = n.dot(V[c].V.col(0).tail<3>());
    EXPECT_NEAR(normal, model.normalForce(-features(c, 0)), 1e-13 * model.normalForce(0.01)) << c;
  }
}

// --- planar granular models --------------------------------------------------------------------

TEST(ContactFeatures, PlanarModelReportsDepthAndSagittalAngle) {
  const auto model = planarSand();
  ASSERT_EQ(namesOf(*model), (std::vector<std::string>{"depth", "beta"}));
  EXPECT_EQ(model->featureInfo()[0].unit, "m");
  EXPECT_EQ(model->featureInfo()[1].unit, "rad");
  const PlaneTerrain flat;
  // A leg leaning toward +x (forward, x_s = y × n = x) has β = +0.2; toward −x, β = −0.2. A lateral
  // lean does not change β (the planar models do not read it).
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.015, 0.2, 0.0), footOnFlat(0.1, -0.015, -0.2, 0.0),
                                            footOnFlat(0.2, -0.03, 0.0, 0.0), footOnFlat(0.3, 0.01, 0.2, 0.3)};
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  const double expected[4][2] = {{-0.015, 0.2}, {-0.015, -0.2}, {-0.03, 0.0}, {0.01, 0.2}};
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(f(c, 0), expected[c][0], 1e-15) << c;
    EXPECT_NEAR(f(c, 1), expected[c][1], 1e-15) << c;
  }
  // On a tilted plane, the foot placed by footFrameAt at depth −0.01 with angle 0.2.
  const PlaneTerrain tilted(Vec3(0.2, 0.1, 1.0), 0.02);
  const Eigen::MatrixXd g = featuresOf(*model, {footFrameAt(tilted, 0.3, -0.2, -0.01, 0.2, kRadius)}, tilted);
  EXPECT_NEAR(g(0, 0), -0.01, kPlacement);
  EXPECT_NEAR(g(0, 1), 0.2, kPlacement);
}

TEST(ContactFeatures, PlanarFeaturesAreTheFeatureFunctionsInput) {
  const auto sand = planarSand();
  const auto& planar = dynamic_cast<const PlanarWrenchModel&>(*sand);
  auto recording = std::make_shared<RecordingPlanarFunction>(planar.function());
  const PlanarWrenchModel model(recording, planar.geometry(), "rbf");
  const ParaboloidTerrain bowl(0.3, -0.2);
  const PlaneTerrain tilted(Vec3(0.2, -0.1, 1.0), 0.01);
  for (const Terrain* terrain : {static_cast<const Terrain*>(&bowl), static_cast<const Terrain*>(&tilted)}) {
    const std::vector<ContactFrame> frames = generalFrames(*terrain);
    const Eigen::MatrixXd reported = featuresOf(model, frames, *terrain);
    // The model built on the file's function reports the same (one geometry, one computation).
    EXPECT_TRUE(identical(featuresOf(*sand, frames, *terrain), reported)) << terrain->describe();
    for (bool derivatives : {false, true}) {
      std::vector<ContactWrenches> out(frames.size());
      for (ContactWrenches& w : out) w.resize(model.vertexCount());
      recording->seen.resize(0, 0);
      model.evaluate(frames, *terrain, out, derivatives);
      EXPECT_TRUE(identical(recording->seen, reported))
          << terrain->describe() << (derivatives ? " with" : " without") << " derivatives:\nreported\n"
          << reported << "\nused\n" << recording->seen;
    }
  }
}

TEST(ContactFeatures, RbfAtThePlanarFeaturesGivesTheModelsForces) {
  const auto model = planarSand();
  const auto& planar = dynamic_cast<const PlanarWrenchModel&>(*model);
  const PlaneTerrain flat;
  // On flat ground with lateral axis y the sagittal frame is the world's: F = (σ F_x, 0, σ F_z).
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.01, 0.2, 0.0), footOnFlat(0.1, -0.02, -0.3, 0.0),
                                            footOnFlat(0.2, -0.005, 0.0, 0.0)};
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& w : out) w.resize(model->vertexCount());
  model->evaluate(frames, flat, out, false);
  Eigen::MatrixXd W;
  planar.function().evaluate(Eigen::MatrixX2d(f), W, nullptr, nullptr);
  const int K = model->vertexCount();
  for (int c = 0; c < 3; ++c) {
    const double sigma = cutoffStep(planar.geometry(), f(c, 0), nullptr);
    ASSERT_GT(sigma, 0.0) << c;
    Eigen::MatrixXd expected(3, K), forces(3, K);
    for (int k = 0; k < K; ++k) expected.col(k) = Vec3(sigma * W(c, 3 * k), 0.0, sigma * W(c, 3 * k + 1));
    forces = out[c].V.bottomRows<3>();
    EXPECT_GT(forces.row(2).cwiseAbs().maxCoeff(), 1.0) << c;  // N: the sand pushes back
    // The RBF's evaluate() and the model's evaluateRows() sum the kernels in another order.
    const double ulps = ulpsOfLargest(forces, expected);
    std::cout << "[ info ] contact " << c << ": forces vs the function at the reported features, " << ulps << " ulps\n";
    EXPECT_LE(ulps, 64.0) << c << "\n" << forces << "\n" << expected;
  }
}

// --- spatial granular models ------------------------------------------------------------------

TEST(ContactFeatures, SpatialModelReportsDepthAndBothLeans) {
  const auto model = spatialSand();
  ASSERT_EQ(namesOf(*model), (std::vector<std::string>{"depth", "beta", "gamma"}));
  for (int j = 1; j < 3; ++j) EXPECT_EQ(model->featureInfo()[j].unit, "rad");
  const PlaneTerrain flat;
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.015, 0.2, 0.0), footOnFlat(0.1, -0.015, 0.0, 0.2),
                                            footOnFlat(0.2, -0.01, -0.2, -0.3), footOnFlat(0.3, 0.02, 0.1, 0.1)};
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  const double expected[4][3] = {{-0.015, 0.2, 0.0}, {-0.015, 0.0, 0.2}, {-0.01, -0.2, -0.3}, {0.02, 0.1, 0.1}};
  for (int c = 0; c < 4; ++c)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(f(c, j), expected[c][j], 1e-15) << c << ", " << j;
  // A tilted plane, the foot placed by footFrameAt with β = −0.25 and γ = 0.15.
  const PlaneTerrain tilted(Vec3(-0.2, 0.15, 1.0), 0.02);
  const Eigen::MatrixXd g =
      featuresOf(*model, {footFrameAt(tilted, 0.3, -0.2, -0.01, -0.25, 0.15, kRadius)}, tilted);
  EXPECT_NEAR(g(0, 0), -0.01, kPlacement);
  EXPECT_NEAR(g(0, 1), -0.25, kPlacement);
  EXPECT_NEAR(g(0, 2), 0.15, kPlacement);
}

TEST(ContactFeatures, SpatialFeaturesAreTheFeatureFunctionsInput) {
  const auto sand = spatialSand();
  const auto& spatial = dynamic_cast<const SpatialWrenchModel&>(*sand);
  auto recording = std::make_shared<RecordingSpatialFunction>(spatial.function());
  const SpatialWrenchModel model(recording, spatial.geometry(), "rbf");
  const ParaboloidTerrain bowl(-0.25, 0.3);
  const PlaneTerrain tilted(Vec3(-0.1, 0.2, 1.0), -0.01);
  for (const Terrain* terrain : {static_cast<const Terrain*>(&bowl), static_cast<const Terrain*>(&tilted)}) {
    const std::vector<ContactFrame> frames = generalFrames(*terrain);
    const Eigen::MatrixXd reported = featuresOf(model, frames, *terrain);
    EXPECT_TRUE(identical(featuresOf(*sand, frames, *terrain), reported)) << terrain->describe();
    EXPECT_GT(reported.col(2).cwiseAbs().maxCoeff(), 0.1);  // the legs lean sideways too
    for (bool derivatives : {false, true}) {
      std::vector<ContactWrenches> out(frames.size());
      for (ContactWrenches& w : out) w.resize(model.vertexCount());
      recording->seen.resize(0, 0);
      model.evaluate(frames, *terrain, out, derivatives);
      EXPECT_TRUE(identical(recording->seen, reported))
          << terrain->describe() << (derivatives ? " with" : " without") << " derivatives:\nreported\n"
          << reported << "\nused\n" << recording->seen;
    }
  }
}

TEST(ContactFeatures, RbfAtTheSpatialFeaturesGivesTheModelsForces) {
  const auto model = spatialSand();
  const auto& spatial = dynamic_cast<const SpatialWrenchModel&>(*model);
  const PlaneTerrain flat;
  // On flat ground with lateral axis y, R = I: the force rows of V are σ (F_x, F_y, F_z).
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.01, 0.2, 0.1), footOnFlat(0.1, -0.02, -0.3, -0.2),
                                            footOnFlat(0.2, -0.006, 0.0, 0.25)};
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& w : out) w.resize(model->vertexCount());
  model->evaluate(frames, flat, out, false);
  Eigen::MatrixXd W;
  spatial.function().evaluate(Eigen::MatrixX3d(f), W, nullptr);
  const int K = model->vertexCount();
  for (int c = 0; c < 3; ++c) {
    const double sigma = cutoffStep(planarGeometryOf(spatial.geometry()), f(c, 0), nullptr);
    ASSERT_GT(sigma, 0.0) << c;
    Eigen::MatrixXd expected(3, K), forces(3, K);
    for (int k = 0; k < K; ++k) expected.col(k) = sigma * W.row(c).segment<3>(6 * k + 3).transpose();
    forces = out[c].V.bottomRows<3>();
    EXPECT_GT(forces.cwiseAbs().maxCoeff(), 1.0) << c;
    const double ulps = ulpsOfLargest(forces, expected);
    std::cout << "[ info ] contact " << c << ": forces vs the function at the reported features, " << ulps << " ulps\n";
    EXPECT_LE(ulps, 64.0) << c << "\n" << forces << "\n" << expected;
  }
}

// --- patched ground ---------------------------------------------------------------------------

constexpr double kBlend = 0.05;  // m

// Rigid ground (Coulomb) with a planar sand pit at x ∈ [1, 3], |y| ≤ 1 and, with `spatial_pit`, a
// 3-D sand pit at x ∈ [−3, −1].
std::unique_ptr<PatchedModel> patchedGround(bool spatial_pit) {
  std::vector<MaterialPatch> patches{{"pit", MaterialRegion::rectangle(Vec2(1.0, -1.0), Vec2(3.0, 1.0))}};
  std::vector<std::unique_ptr<ContactModel>> parts;
  parts.push_back(std::make_unique<CoulombModel>());
  parts.push_back(planarSand());
  if (spatial_pit) {
    patches.push_back({"pit3d", MaterialRegion::rectangle(Vec2(-3.0, -1.0), Vec2(-1.0, 1.0))});
    parts.push_back(spatialSand());
  }
  return std::make_unique<PatchedModel>(std::make_shared<MaterialLayout>(patches, kBlend), std::move(parts));
}

TEST(ContactFeatures, PatchedModelReportsTheHeaviestMaterialAcrossTheBorder) {
  const auto model = patchedGround(false);
  ASSERT_EQ(namesOf(*model), (std::vector<std::string>{"depth", "beta", "material", "weight"}));
  const auto sand = planarSand();
  const CoulombModel rigid;
  const PlaneTerrain flat;
  // A row of feet across the pit's edge x = 1 and its blending band.
  std::vector<ContactFrame> frames;
  for (int i = 0; i <= 40; ++i) frames.push_back(footOnFlat(0.9 + 0.005 * i, -0.01 - 0.0002 * i, 0.25, 0.0));
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  const Eigen::MatrixXd sand_f = featuresOf(*sand, frames, flat), rigid_f = featuresOf(rigid, frames, flat);
  int switches = 0, in_band = 0;
  for (int c = 0; c < static_cast<int>(frames.size()); ++c) {
    double w[2], wx[2], wy[2];
    model->layout().weights(frames[c].position.x(), frames[c].position.y(), w, wx, wy);
    const int heaviest = w[1] > w[0] ? 1 : 0;
    EXPECT_EQ(f(c, 2), static_cast<double>(heaviest)) << c;
    EXPECT_EQ(f(c, 3), w[heaviest]) << c;
    EXPECT_EQ(f(c, 0), heaviest == 1 ? sand_f(c, 0) : rigid_f(c, 0)) << c;
    if (heaviest == 1) EXPECT_EQ(f(c, 1), sand_f(c, 1)) << c;
    else EXPECT_TRUE(std::isnan(f(c, 1))) << c << ": the rigid ground has no leg angle";
    if (c > 0 && f(c, 2) != f(c - 1, 2)) ++switches;
    if (w[0] > 0.0 && w[1] > 0.0) ++in_band;
  }
  EXPECT_EQ(f(0, 2), 0.0);
  EXPECT_EQ(f(40, 2), 1.0);
  EXPECT_EQ(switches, 1);
  EXPECT_GT(in_band, 4);  // the row crosses the band, not only its two sides
}

TEST(ContactFeatures, PatchedModelColumnsAreTheUnionOfItsMaterials) {
  const auto model = patchedGround(true);
  ASSERT_EQ(namesOf(*model), (std::vector<std::string>{"depth", "beta", "gamma", "material", "weight"}));
  const PlaneTerrain flat;
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.004, 0.2, 0.1), footOnFlat(2.0, -0.01, 0.2, 0.1),
                                            footOnFlat(-2.0, -0.01, 0.2, 0.1)};
  const Eigen::MatrixXd f = featuresOf(*model, frames, flat);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double expected[3][5] = {{-0.004, nan, nan, 0, 1}, {-0.01, 0.2, nan, 1, 1}, {-0.01, 0.2, 0.1, 2, 1}};
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < 5; ++j) {
      if (std::isnan(expected[c][j])) EXPECT_TRUE(std::isnan(f(c, j))) << c << ", " << j;
      else EXPECT_NEAR(f(c, j), expected[c][j], 1e-15) << c << ", " << j;
    }
}

// A Coulomb cone that claims a second column "beta" in degrees.
class DegreesModel : public CoulombModel {
 public:
  std::vector<ContactFeatureInfo> featureInfo() const override {
    return {{"depth", "m", "depth"}, {"beta", "deg", "an angle in degrees"}};
  }
};

TEST(ContactFeatures, PatchedModelRefusesOneColumnInTwoUnits) {
  std::vector<std::unique_ptr<ContactModel>> parts;
  parts.push_back(std::make_unique<DegreesModel>());
  parts.push_back(planarSand());
  const auto layout = std::make_shared<MaterialLayout>(
      std::vector<MaterialPatch>{{"pit", MaterialRegion::rectangle(Vec2(1.0, -1.0), Vec2(3.0, 1.0))}}, kBlend);
  EXPECT_THROW(PatchedModel(layout, std::move(parts)), std::invalid_argument);
}

// --- every model: shapes and allocations -----------------------------------------------------

std::vector<std::unique_ptr<ContactModel>> everyModel() {
  std::vector<std::unique_ptr<ContactModel>> models;
  models.push_back(std::make_unique<CoulombModel>());
  models.push_back(planarSand());
  models.push_back(spatialSand());
  models.push_back(patchedGround(true));
  return models;
}

TEST(ContactFeatures, WrongOutputShapeIsALogicError) {
  const PlaneTerrain flat;
  const std::vector<ContactFrame> frames = {footOnFlat(0.0, -0.01, 0.1, 0.0), footOnFlat(2.0, -0.01, 0.1, 0.0)};
  for (const auto& model : everyModel()) expectShapeIsChecked(*model, frames, flat);
}

TEST(ContactFeatures, FeaturesAllocateNothing) {
  if (!NMDP_COUNTS_MALLOC) GTEST_SKIP() << "allocations are not counted on this platform";
  const ParaboloidTerrain bowl(0.1, 0.05);
  std::vector<ContactFrame> frames = generalFrames(bowl);
  for (double x : {2.0, -2.0, 1.0}) frames.push_back(footFrameAt(bowl, x, 0.0, -0.01, 0.1, 0.05, kRadius));
  for (const auto& model : everyModel()) {
    Eigen::MatrixXd out(static_cast<Eigen::Index>(frames.size()), static_cast<Eigen::Index>(model->featureInfo().size()));
    // Not even the first call (the patched model's scratch is sized when it is built).
    const AllocationCount first = countAllocations([&] { model->features(frames, bowl, out); });
    EXPECT_EQ(first.total(), 0) << model->describe();
    // Into a block of a larger array, as a writer filling a (steps × contacts × features) buffer does.
    Eigen::MatrixXd big = Eigen::MatrixXd::Zero(3 * out.rows(), out.cols() + 2);
    const AllocationCount block =
        countAllocations([&] { model->features(frames, bowl, big.block(out.rows(), 1, out.rows(), out.cols())); });
    EXPECT_EQ(block.total(), 0) << model->describe();
    EXPECT_TRUE(identical(big.block(out.rows(), 1, out.rows(), out.cols()), out)) << model->describe();
  }
}

}  // namespace
}  // namespace nmdp::test
