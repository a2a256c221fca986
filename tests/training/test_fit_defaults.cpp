// A first fit is physical (training/fit_config.hpp resolveFitConfig, training/fit_warnings.hpp):
//  * what FIT.json leaves out is decided from the data: mirror when the data covers one side of
//    β = 0, zero-wrench heights scaled to the data's depth span, a cut-off at the lowest zero-wrench
//    point above the data's wrenches (the surface when nothing lower), blended from the highest
//    wrench, so the model is zero above the ground and every data point keeps its value; explicit
//    values (and "data") are respected; the settings recorded are those used;
//  * the report warns, with a suggestion, when the leave-one-point-out error is large and when the
//    model pushes above the surface, and not otherwise.
// The MLP's warnings and the sand-data acceptance run through the CLI (test_first_fit_cli.cpp).
#include <cmath>
#include <random>

#include "contact_models/rbf_function.hpp"
#include "fit_fixtures.hpp"
#include "io/hdf5_file.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "training/fit_config.hpp"
#include "training/fit_warnings.hpp"
#include "training/force_dataset.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp::test {
namespace {
using json = nlohmann::json;

const std::vector<double> kPublishedHeights = {0.01, 0.03, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0};

ResolvedFitConfig resolve(const ForceDataset& d, const FitConfig& c = FitConfig{}) {
  return resolveFitConfig(c, d, groupPlanarSamples(d, "synthetic"), "synthetic");
}

bool mentions(const std::vector<std::string>& lines, const std::string& part) {
  for (const std::string& l : lines)
    if (l.find(part) != std::string::npos) return true;
  return false;
}

// The fitted model as the contact model evaluates it: the RBF times the cut-off step.
Eigen::MatrixXd modelAt(const RbfFitOutcome& fit, const Eigen::MatrixX2d& f) {
  Eigen::MatrixXd W;
  RbfFunction(fit.record.fit.parameters).evaluate(f, W, nullptr, nullptr);
  for (Eigen::Index i = 0; i < f.rows(); ++i) W.row(i) *= cutoffStep(fit.geometry, f(i, 0), nullptr);
  return W;
}

// ==== defaults decided from the data ============================================================

TEST(FitDefaults, MirrorWhenTheDataCoversOneSideOfBetaZero) {
  const std::vector<double> phis = {-0.03, -0.02, -0.01, 0.0};
  const ResolvedFitConfig one_side = resolve(syntheticDataset(2, phis, {0.0, 0.3, 0.6}));
  EXPECT_EQ(one_side.config.augmentation.mirror, std::optional<bool>(true));
  EXPECT_TRUE(mentions(one_side.from_data, "augmentation.mirror = true"));
  EXPECT_EQ(resolve(syntheticDataset(2, phis, {-0.6, -0.3})).config.augmentation.mirror, std::optional<bool>(true));
  EXPECT_EQ(resolve(syntheticDataset(2, phis, {-0.3, 0.0, 0.3})).config.augmentation.mirror,
            std::optional<bool>(false));
  EXPECT_EQ(resolve(syntheticDataset(2, phis, {0.0})).config.augmentation.mirror, std::optional<bool>(false))
      << "nothing to mirror";

  FitConfig explicit_off;
  explicit_off.augmentation.mirror = false;
  const ResolvedFitConfig off = resolve(syntheticDataset(2, phis, {0.0, 0.3, 0.6}), explicit_off);
  EXPECT_EQ(off.config.augmentation.mirror, std::optional<bool>(false));
  EXPECT_FALSE(mentions(off.from_data, "augmentation.mirror"));

  // The fit does mirror: (φ, 0.3) gets a copy at (φ, −0.3).
  const RbfFitOutcome fit = fitRbfToDataset(syntheticDataset(2, phis, {0.0, 0.3}), FitConfig{}, "synthetic");
  int mirrored = 0;
  for (PointOrigin o : fit.record.points.origin) mirrored += o == PointOrigin::Mirrored;
  EXPECT_EQ(mirrored, 4);
}

TEST(FitDefaults, ZeroWrenchHeightsFollowTheDataDepthSpan) {
  // 7 cm of data: exactly the published model's heights.
  const ResolvedFitConfig sand_like = resolve(syntheticDataset(2, {-0.07, -0.05, -0.03, -0.01, 0.0}, {0.0, 0.3}));
  EXPECT_EQ(sand_like.config.augmentation.above_heights, std::optional<std::vector<double>>(kPublishedHeights));
  EXPECT_TRUE(mentions(sand_like.from_data, "augmentation.above_surface.heights = [0.01, 0.03"));
  // 14 cm: twice as high.
  const std::vector<double> deep =
      *resolve(syntheticDataset(2, {-0.14, -0.07, 0.0}, {0.0, 0.3})).config.augmentation.above_heights;
  ASSERT_EQ(deep.size(), kPublishedHeights.size());
  for (size_t i = 0; i < deep.size(); ++i) EXPECT_NEAR(deep[i], 2 * kPublishedHeights[i], 1e-15) << i;
  // Data with points above the surface brings its own: none added.
  EXPECT_EQ(resolve(syntheticDataset(2, {-0.02, 0.0, 0.01}, {0.0, 0.3})).config.augmentation.above_heights,
            std::optional<std::vector<double>>(std::vector<double>{}));
  // Explicit heights, and explicit none, are kept.
  FitConfig none;
  none.augmentation.above_heights = std::vector<double>{};
  const ResolvedFitConfig kept = resolve(syntheticDataset(2, {-0.02, 0.0}, {0.0, 0.3}), none);
  EXPECT_TRUE(kept.config.augmentation.above_heights->empty());
  EXPECT_FALSE(mentions(kept.from_data, "heights"));

  // Many distinct angles (scattered data): the default rows get kMaxDefaultAboveAngles angles evenly
  // over the data's range, not one per angle.
  std::vector<double> betas;
  for (int k = 0; k < 40; ++k) betas.push_back(-0.8 + 0.04 * k);
  const ForceDataset scattered = syntheticDataset(2, {-0.02, -0.01}, betas);
  const ResolvedFitConfig few = resolve(scattered);
  const std::vector<double>& angles = few.config.augmentation.above_angles;
  ASSERT_EQ(angles.size(), static_cast<size_t>(kMaxDefaultAboveAngles));
  EXPECT_EQ(angles.front(), betas.front());
  EXPECT_EQ(angles.back(), betas.back());
  EXPECT_TRUE(mentions(few.from_data, "augmentation.above_surface.angles = 25"));
  const RbfFitOutcome fit = fitRbfToDataset(scattered, FitConfig{}, "scattered");
  EXPECT_EQ(fit.record.points.pointCount(), 80 + 10 * kMaxDefaultAboveAngles);
  // Explicit heights keep the documented "every angle of the data".
  FitConfig given;
  given.augmentation.above_heights = std::vector<double>{0.01};
  EXPECT_TRUE(resolve(scattered, given).config.augmentation.above_angles.empty());
}

TEST(FitDefaults, CutoffMakesTheModelZeroAboveTheDataAndKeepsEveryDataPoint) {
  // Zero at the surface (as the sand samples): the cut-off is the surface, blended from the highest
  // wrench, 1 cm below.
  const ForceDataset d = syntheticDataset(3, {-0.04, -0.03, -0.02, -0.01, 0.0}, {0.0, 0.3, 0.6});
  const RbfFitOutcome fit = fitRbfToDataset(d, FitConfig{}, "synthetic");
  EXPECT_EQ(fit.geometry.cutoff, 0.0);
  EXPECT_EQ(fit.geometry.cutoff_width, 0.01);
  expectAll(formatRbfFitReport(fit.record),
            {"decided from the data: geometry.cutoff = 0", "decided from the data: geometry.cutoff_width = 0.01"});
  // Every fitted point keeps its value under the cut-off (σ = 1 at −1 cm; the points at and above
  // the surface are zero), and the model is zero everywhere above the surface.
  const Eigen::MatrixXd at_points = modelAt(fit, fit.record.points.features);
  const double scale = fit.record.points.values.cwiseAbs().maxCoeff();
  EXPECT_LT((at_points - fit.record.points.values).cwiseAbs().maxCoeff(), 1e-9 * scale);
  Eigen::MatrixX2d above(4, 2);
  above << 1e-9, 0.1, 0.005, -0.45, 0.01, 0.6, 0.5, 0.0;
  EXPECT_EQ(modelAt(fit, above).cwiseAbs().maxCoeff(), 0.0);

  // No surface row in the data: the surface itself is the cut-off.
  EXPECT_EQ(*resolve(syntheticDataset(2, {-0.03, -0.02, -0.01}, {0.0, 0.3})).config.cutoff, 0.0);

  // A wrench at the surface: the cut-off at the first zero-wrench height above it (0.01 × 2/7 for
  // data 2 cm deep), blended over the band from the surface.
  ForceDataset loaded = syntheticDataset(2, {-0.02, -0.01, 0.0}, {0.0, 0.3});
  for (Eigen::Index r = 0; r < loaded.features.rows(); ++r)
    if (loaded.features(r, 0) == 0.0) loaded.wrench.row(r).array() += 1.0;
  const ResolvedFitConfig at_surface = resolve(loaded);
  EXPECT_DOUBLE_EQ(*at_surface.config.cutoff, 0.01 * 0.02 / 0.07);
  EXPECT_EQ(*at_surface.config.cutoff_width, *at_surface.config.cutoff);
  const RbfFitOutcome loaded_fit = fitRbfToDataset(loaded, FitConfig{}, "loaded");
  const Eigen::MatrixXd kept = modelAt(loaded_fit, loaded_fit.record.points.features);
  EXPECT_LT((kept - loaded_fit.record.points.values).cwiseAbs().maxCoeff(),
            1e-9 * loaded_fit.record.points.values.cwiseAbs().maxCoeff());

  // An explicit cut-off gets the band from the highest wrench to it; an explicit band is kept.
  FitConfig cut;
  cut.cutoff = 0.05;
  const ResolvedFitConfig given = resolve(d, cut);
  EXPECT_EQ(*given.config.cutoff, 0.05);
  EXPECT_DOUBLE_EQ(*given.config.cutoff_width, 0.06);
  EXPECT_FALSE(mentions(given.from_data, "geometry.cutoff ="));
  FitConfig band;
  band.cutoff_width = 0.003;
  const ResolvedFitConfig width = resolve(d, band);
  EXPECT_EQ(*width.config.cutoff, 0.0);
  EXPECT_EQ(*width.config.cutoff_width, 0.003);
}

TEST(FitDefaults, SettingsRecordWhatWasUsedAndReproduceTheFit) {
  TempDir dir;
  const ForceDataset d = syntheticDataset(3, {-0.03, -0.02, -0.01, 0.0}, {0.0, 0.4});
  const RbfFitOutcome fit = fitRbfToDataset(d, FitConfig{}, "synthetic.h5");
  const nlohmann::ordered_json& s = fit.record.settings;
  EXPECT_EQ(s["augmentation"]["mirror"], true);
  EXPECT_EQ(s["augmentation"]["above_surface"]["heights"].size(), kPublishedHeights.size());
  EXPECT_EQ(s["geometry"]["cutoff"], 0.0);
  EXPECT_EQ(s["geometry"]["cutoff_width"], 0.01);
  ASSERT_EQ(fit.record.from_data.size(), 4u) << "mirror, heights, cutoff, cutoff_width";

  const std::string path = dir.file("model.h5");
  saveRbfFit(path, fit.record, fit.geometry);
  const h5::File f = h5::File::openRead(path);
  expectAll(f.readStringAttribute("/fit", "from_data"),
            {"augmentation.mirror = true", "augmentation.above_surface.heights = [", "geometry.cutoff = 0",
             "geometry.cutoff_width = 0.01"});
  EXPECT_EQ(f.readStringAttribute("/fit", "settings"), s.dump());

  // The recorded settings, given back as FIT.json, decide nothing and give the same model.
  const FitConfig again = parseFitConfig(json::parse(s.dump()), {"settings", ""});
  const RbfFitOutcome refit = fitRbfToDataset(d, again, "synthetic.h5");
  EXPECT_TRUE(refit.record.from_data.empty());
  EXPECT_EQ(refit.record.fit.parameters.weights, fit.record.fit.parameters.weights);
  EXPECT_EQ(refit.geometry.cutoff, fit.geometry.cutoff);
  EXPECT_EQ(refit.geometry.cutoff_width, fit.geometry.cutoff_width);
}

TEST(FitDefaults, DataAsAValueAsksForTheDefault) {
  const ConfigContext ctx{"fit.json", ""};
  const FitConfig asked = parseFitConfig(
      json{{"augmentation", {{"mirror", "data"}, {"above_surface", {{"heights", "data"}}}}},
           {"geometry", {{"cutoff", "data"}, {"cutoff_width", "data"}}}},
      ctx);
  EXPECT_FALSE(asked.augmentation.mirror.has_value());
  EXPECT_FALSE(asked.augmentation.above_heights.has_value());
  EXPECT_FALSE(asked.cutoff.has_value());
  EXPECT_FALSE(asked.cutoff_width.has_value());
  const json unresolved = json::parse(fitConfigJson(asked, 0.1).dump());
  EXPECT_EQ(unresolved["augmentation"]["mirror"], "data");
  EXPECT_EQ(unresolved["geometry"]["cutoff"], "data");

  const FitConfig given = parseFitConfig(
      json{{"augmentation", {{"mirror", false}, {"above_surface", {{"heights", json::array()}}}}},
           {"geometry", {{"cutoff", 0.1}, {"cutoff_width", 0.02}}}},
      ctx);
  EXPECT_EQ(given.augmentation.mirror, std::optional<bool>(false));
  EXPECT_EQ(given.augmentation.above_heights, std::optional<std::vector<double>>(std::vector<double>{}));
  EXPECT_EQ(given.cutoff, std::optional<double>(0.1));
  EXPECT_EQ(given.cutoff_width, std::optional<double>(0.02));
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"augmentation", {{"mirror", "yes"}}}}, ctx); }),
            {"fit.json.augmentation.mirror"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"geometry", {{"cutoff", "high"}}}}, ctx); }),
            {"fit.json.geometry.cutoff"});
}

// ==== warnings ==================================================================================

bool hasWarning(const std::vector<FitWarning>& warnings, const std::string& part) {
  for (const FitWarning& w : warnings)
    if (w.what.find(part) != std::string::npos) {
      EXPECT_FALSE(w.suggestion.empty()) << w.what;
      EXPECT_EQ(w.suggestion.find('\n'), std::string::npos) << "one line: " << w.suggestion;
      return true;
    }
  return false;
}

TEST(FitWarnings, LeaveOneOutWarnsWhenTheSamplesDoNotPinTheModel) {
  const std::vector<double> phis = {-0.04, -0.03, -0.02, -0.01, 0.0};
  const std::vector<double> betas = {-0.6, -0.3, 0.0, 0.3, 0.6};
  // Smooth wrenches sampled densely: left-out points are predicted well.
  const RbfFitOutcome smooth = fitRbfToDataset(syntheticDataset(3, phis, betas), FitConfig{}, "smooth");
  EXPECT_LT(measuredRms(smooth.record.fit.loo_relative, smooth.record.points), kLooWarnRms);
  EXPECT_FALSE(hasWarning(smooth.record.warnings, "leave-one-point-out"));
  expectAll(formatRbfFitReport(smooth.record), {"warnings: none"});

  // The same points with unrelated wrenches: nothing between the samples is pinned down.
  ForceDataset noisy = syntheticDataset(3, phis, betas);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(10.0, 100.0);
  for (Eigen::Index r = 0; r < noisy.wrench.rows(); ++r)
    if (noisy.features(r, 0) < 0.0) noisy.wrench.row(r) << u(rng), u(rng), u(rng);
  const RbfFitOutcome fit = fitRbfToDataset(noisy, FitConfig{}, "noisy");
  const double rms = measuredRms(fit.record.fit.loo_relative, fit.record.points);
  EXPECT_GT(rms, kLooWarnRms);
  EXPECT_TRUE(hasWarning(fit.record.warnings, "leave-one-point-out error is large"));
  const std::string report = formatRbfFitReport(fit.record);
  expectAll(report, {"warning: the leave-one-point-out error is large", "  suggestion: add samples"});
}

TEST(FitWarnings, AboveSurfaceWarnsWhenTheModelPushesAboveTheGround) {
  const ForceDataset d = syntheticDataset(3, {-0.04, -0.03, -0.02, -0.01, 0.0}, {0.0, 0.3, 0.6});
  // The old defaults (no augmentation, cut-off 0.1 m over 2 cm): the interpolant carries on above
  // the surface up to the cut-off.
  FitConfig old_defaults = noAugmentation();
  old_defaults.cutoff = 0.1;
  old_defaults.cutoff_width = 0.02;
  const RbfFitOutcome pushing = fitRbfToDataset(d, old_defaults, "old");
  const AboveSurfaceCheck& check = pushing.record.above_surface;
  EXPECT_EQ(check.grid_points, (kAboveSurfaceHeights - 1) * kAboveSurfaceAngles);
  EXPECT_GT(check.share(), kAboveSurfaceWarnShare);
  EXPECT_GT(check.phi, 0.0);
  EXPECT_LT(check.phi, 0.1);
  EXPECT_TRUE(hasWarning(pushing.record.warnings, "the model pushes above the surface"));
  expectAll(formatRbfFitReport(pushing.record), {"warning: the model pushes above the surface", "suggestion: "});
  {
    TempDir dir;
    const std::string path = dir.file("old.h5");
    saveRbfFit(path, pushing.record, pushing.geometry);
    const h5::File f = h5::File::openRead(path);
    expectAll(f.readStringAttribute("/fit", "warnings"), {"the model pushes above the surface"});
    EXPECT_EQ(f.readDoubleAttribute("/fit", "above_surface_share"), check.share());
  }

  // The defaults: zero above the surface, nothing to warn about.
  const RbfFitOutcome zero = fitRbfToDataset(d, FitConfig{}, "default");
  EXPECT_EQ(zero.record.above_surface.grid_points, 0);
  EXPECT_FALSE(hasWarning(zero.record.warnings, "above the surface"));
  expectAll(formatRbfFitReport(zero.record), {"above the surface: zero"});
}

// A feature function that is `above` at every φ > 0 and `below` elsewhere, for every entry.
class StepFunction : public FeatureWrenchFunction {
 public:
  StepFunction(double below, double above) : below_(below), above_(above) {}
  int vertexCount() const override { return 1; }
  DerivativeSupport derivative() const override { return DerivativeSupport::None; }
  std::string describe() const override { return "step"; }
  void evaluate(const Eigen::MatrixX2d& f, Eigen::MatrixXd& W, Eigen::MatrixXd*, Eigen::MatrixXd*) const override {
    W.resize(f.rows(), 3);
    for (Eigen::Index i = 0; i < f.rows(); ++i) W.row(i).setConstant(f(i, 0) > 0.0 ? above_ : below_);
  }

 private:
  double below_, above_;
};

TEST(FitWarnings, AboveSurfaceCheckAppliesTheCutoffAndWarnsAboveOnePercent) {
  PlanarPoints pts;
  pts.features.resize(3, 2);
  pts.features << -0.02, -0.5, -0.01, 0.5, 0.01, 0.0;
  pts.values.resize(3, 3);
  pts.values << 100, -200, 50, 10, 20, 30, 0, 0, 0;
  pts.origin = {PointOrigin::Measured, PointOrigin::Measured, PointOrigin::AboveSurface};
  PlanarGeometry g;
  g.cutoff = 0.1;
  g.cutoff_width = 0.1;
  // 1 above the surface, 200 below: the largest on the grid is at its lowest row, φ = 0.005, where
  // the step is σ(0.95).
  const AboveSurfaceCheck c = checkAboveSurface(StepFunction(5.0, 1.0), g, pts);
  EXPECT_EQ(c.largest_below, 200.0);
  EXPECT_DOUBLE_EQ(c.phi, 0.005);
  EXPECT_DOUBLE_EQ(c.largest_above, cutoffStep(g, 0.005, nullptr));
  EXPECT_GE(c.beta, -0.5);
  EXPECT_LE(c.beta, 0.5);
  EXPECT_LT(c.share(), kAboveSurfaceWarnShare);
  EXPECT_FALSE(aboveSurfaceWarning(c, g).has_value());
  const AboveSurfaceCheck big = checkAboveSurface(StepFunction(5.0, 2.2), g, pts);
  EXPECT_GT(big.share(), kAboveSurfaceWarnShare);
  ASSERT_TRUE(aboveSurfaceWarning(big, g).has_value());
  expectAll(aboveSurfaceWarning(big, g)->what, {"1.10 % of the largest wrench below the surface, 200", "phi 0.005 m"});
  // A cut-off at the surface leaves nothing to check.
  g.cutoff = 0.0;
  EXPECT_EQ(checkAboveSurface(StepFunction(5.0, 100.0), g, pts).grid_points, 0);
}

}  // namespace
}  // namespace nmdp::test
