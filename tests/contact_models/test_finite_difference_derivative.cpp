// The zeroth-order methods' dV/dξ, central differences of V (contact_models/
// finite_difference_derivative.hpp), against the models' analytic derivatives: the Coulomb cone on
// flat and tilted ground (feet 1-12 mm deep, tilted legs) and the project's hand-made RBF sand
// model. Also: V is left as it was, the model is never asked for a derivative, and contacts in the
// air give zero.
#include <gtest/gtest-spi.h>

#include <random>

#include "contact_models/coulomb_model.hpp"
#include "contact_models/finite_difference_derivative.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_derivative_check.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

// The inner model seen through a test's lens: values only (the test fails if a derivative is ever
// requested, which the zeroth-order path must never do), or its derivative scaled by a factor.
class Lens : public ContactModel {
 public:
  static Lens valuesOnly(const ContactModel& inner) { return Lens(inner, true, 1.0); }
  static Lens derivativeTimes(const ContactModel& inner, double factor) { return Lens(inner, false, factor); }
  int vertexCount() const override { return inner_.vertexCount(); }
  DerivativeSupport derivative() const override {
    return values_only_ ? DerivativeSupport::None : DerivativeSupport::Analytic;
  }
  std::string describe() const override { return values_only_ ? "values only" : "scaled derivative"; }
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override {
    if (values_only_) EXPECT_FALSE(with_derivatives) << "the finite-difference derivative asked the model for a derivative";
    inner_.evaluate(frames, terrain, out, with_derivatives && !values_only_);
    if (with_derivatives && !values_only_)
      for (ContactWrenches& w : out)
        for (Mat6X& d : w.dV) d *= factor_;
  }

 private:
  Lens(const ContactModel& inner, bool values_only, double factor)
      : inner_(inner), values_only_(values_only), factor_(factor) {}
  const ContactModel& inner_;
  bool values_only_;
  double factor_;
};

// Feet whose lowest point is 1-12 mm below the plane, legs tilted up to 0.4 rad, plus one in the air.
std::vector<ContactFrame> feet(const PlaneTerrain& terrain, double radius, std::mt19937& rng) {
  std::uniform_real_distribution<double> depth(1e-3, 12e-3), tilt(-0.4, 0.4), along(-0.5, 0.5);
  std::vector<ContactFrame> frames;
  for (int c = 0; c < 5; ++c) {
    ContactFrame f;
    f.radius = radius;
    // A point on the plane n̂·p = offset, then the sphere placed along n̂ so its lowest point is d deep.
    const Vec3 n = terrain.normal();
    Vec3 surface(along(rng), along(rng), 0.0);
    surface -= (n.dot(surface) - terrain.offset()) * n;
    const double d = c == 4 ? -0.05 : depth(rng);  // the last one 5 cm above the ground
    f.position = surface + (radius - d) * n;
    const Vec3 normal = n;
    f.leg_axis = (Eigen::AngleAxisd(tilt(rng), Vec3::UnitY()) * Eigen::AngleAxisd(tilt(rng), Vec3::UnitX()) * normal)
                     .normalized();
    f.lateral = Vec3::UnitY();
    frames.push_back(f);
  }
  return frames;
}

// Worst error of the finite-difference dV/dξ against the analytic one (contact_derivative_check.hpp),
// relative to each contact's largest entry (no floor: a derivative that vanishes in the ground fails).
double worstError(const ContactModel& model, const PlaneTerrain& terrain, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<ContactFrame> frames = feet(terrain, radius, rng);
  const int K = model.vertexCount();
  std::vector<ContactWrenches> exact(frames.size()), estimate(frames.size());
  for (ContactWrenches& w : exact) w.resize(K);
  for (ContactWrenches& w : estimate) w.resize(K);
  model.evaluate(frames, terrain, exact, true);
  model.evaluate(frames, terrain, estimate, false);
  std::vector<Mat6X> V_before;
  for (const ContactWrenches& w : estimate) V_before.push_back(w.V);
  FiniteDifferenceDerivative fd(static_cast<int>(frames.size()), K);
  fd.evaluate(Lens::valuesOnly(model), frames, terrain, estimate);
  for (size_t c = 0; c < frames.size(); ++c)
    EXPECT_EQ((estimate[c].V - V_before[c]).cwiseAbs().maxCoeff(), 0.0) << "V must be left as it was";
  // In the air (the last contact): both zero (Coulomb keeps ζ, a constant: its derivative is zero too).
  const double air_scale = largestDerivative(exact.back(), 0, VertexDerivativeCheck::Scale::PerContact);
  for (int i = 0; i < 6; ++i)
    EXPECT_LE(estimate.back().dV[i].cwiseAbs().maxCoeff(), 1e-9 * std::max(air_scale, 1.0));
  exact.pop_back();
  estimate.pop_back();
  for (size_t c = 0; c < exact.size(); ++c)
    EXPECT_GT(largestDerivative(exact[c], 0, VertexDerivativeCheck::Scale::PerContact), 0.0)
        << "contact " << c << " is in the ground: dV/dξ must not vanish";
  VertexDerivativeCheck check;
  check.tolerance = 1e-6;
  check.scale_floor = 0.0;
  return expectVertexDerivativesMatch(exact, estimate, check, "in the ground");
}

TEST(FiniteDifferenceDerivative, MatchesTheCoulombConeOnFlatAndTiltedGround) {
  const CoulombModel model;
  for (const PlaneTerrain& terrain : {PlaneTerrain(), PlaneTerrain(Vec3(0.2, -0.1, 1.0), 0.03)})
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const double e = worstError(model, terrain, 0.02, seed);
      std::printf("  Coulomb, seed %u: worst relative error %.2e\n", seed, e);
    }
}

TEST(FiniteDifferenceDerivative, MatchesTheHandmadeSandModel) {
  const ConfigContext ctx{"test: contacts.model", sourcePath("data/granular")};
  const std::unique_ptr<ContactModel> model = makeRbfModel({{"type", "rbf"}, {"file", "handmade_sand_rbf.h5"}}, ctx);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const double e = worstError(*model, PlaneTerrain(), 0.02, seed);
    std::printf("  hand-made sand RBF, seed %u: worst relative error %.2e\n", seed, e);
  }
}

TEST(VertexDerivativeCheck, PassesTheExactDerivativeAndCatchesAWrongOne) {
  const CoulombModel model;
  const PlaneTerrain terrain(Vec3(0.2, -0.1, 1.0), 0.03);
  std::mt19937 rng(3);
  const std::vector<ContactFrame> frames = feet(terrain, 0.02, rng);
  const VertexDerivativeCheck check;  // 1e-6 m and rad, 1e-6 relative to the contact's largest entry
  EXPECT_LT(checkVertexDerivative(model, frames, terrain, check).worst, 1e-6);
  // A derivative 1e-5 too large (relative) must fail the check.
  ::testing::TestPartResultArray failures;
  {
    const ::testing::ScopedFakeTestPartResultReporter intercept(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    checkVertexDerivative(Lens::derivativeTimes(model, 1.0 + 1e-5), frames, terrain, check);
  }
  EXPECT_GT(failures.size(), 0) << "the checker passed a derivative 1e-5 off";
}

TEST(FiniteDifferenceDerivative, PerturbedFrameRotatesAboutTheCentreAndTranslates) {
  ContactFrame f;
  f.position = Vec3(1, 2, 3);
  f.leg_axis = Vec3::UnitZ();
  f.lateral = Vec3::UnitY();
  const ContactFrame r = perturbedFrame(f, 0, 0.5 * M_PI);  // about world x: z → −y, y → z
  EXPECT_LT((r.position - f.position).norm(), 1e-15);
  EXPECT_LT((r.leg_axis - Vec3(0, -1, 0)).norm(), 1e-15);
  EXPECT_LT((r.lateral - Vec3(0, 0, 1)).norm(), 1e-15);
  f.lateral_rotates = false;  // planar base: the sagittal plane stays
  EXPECT_LT((perturbedFrame(f, 0, 0.5 * M_PI).lateral - Vec3::UnitY()).norm(), 1e-15);
  const ContactFrame t = perturbedFrame(f, 4, 0.25);
  EXPECT_LT((t.position - Vec3(1, 2.25, 3)).norm(), 1e-15);
  EXPECT_EQ(t.leg_axis, f.leg_axis);
}

}  // namespace
}  // namespace nmdp::test
