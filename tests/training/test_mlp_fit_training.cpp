// MLP fitting of wrench spaces (training/mlp/mlp_fit.hpp), the training itself: early stopping
// keeps the best validation epoch's weights; the split is stratified by origin and wrench; the
// teacher grid is fitted to the training points only, its depth rows packed towards the surface
// and refined beside the data angles; bad settings are InputErrors naming the configuration key,
// and the settings' JSON parses back to the same settings.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/registry.hpp"
#include "io/hdf5_file.hpp"
#include "terrain/plane.hpp"
#include "fit_fixtures.hpp"
#include "mlp_fit_fixtures.hpp"
#include "planar_foot.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp::test {
namespace {
using json = nlohmann::json;

// ==== training ==================================================================================

TEST(MlpFit, EarlyStoppingKeepsTheBestValidationEpoch) {
  FitConfig c = quickConfig();
  c.mlp.max_epochs = 3000;
  c.mlp.learning_rate = 5e-2;  // large steps: the validation loss wanders, so the best is not the last
  c.mlp.final_learning_rate = 5e-2;
  c.mlp.patience = 200;
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  ASSERT_EQ(fit.history.rows(), fit.epochs);
  ASSERT_GE(fit.best_epoch, 1);
  const Eigen::VectorXd val = fit.history.col(1);
  Eigen::Index argmin;
  val.minCoeff(&argmin);
  EXPECT_EQ(fit.best_epoch, argmin + 1);
  EXPECT_EQ(fit.validation_loss, val[argmin]);
  if (fit.stopped_early) {
    EXPECT_EQ(fit.epochs - fit.best_epoch, c.mlp.patience);
  } else {
    EXPECT_EQ(fit.epochs, c.mlp.max_epochs);
  }
  // The kept weights give that validation loss (recomputed from the recorded errors: the relative loss
  // of mlp_fit.hpp, here in the units of the data).
  const MlpPoints& pts = out.record.points;
  const double floor = c.mlp.relative_floor * largestTrainingWrench(pts, fit.validation);
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < pts.pointCount(); ++i) {
    if (!fit.validation[i]) continue;
    const double s = std::max(pts.values.row(i).cwiseAbs().maxCoeff(), floor);
    sum += (fit.error.row(i) / s).squaredNorm();
    count += static_cast<int>(fit.error.cols());
  }
  ASSERT_GT(count, 0);
  EXPECT_NEAR(sum / count, fit.validation_loss, 1e-9 * fit.validation_loss + 1e-15);
  // And the validation loss did get better than the initial network's.
  EXPECT_LT(fit.validation_loss, 0.1 * val[0]);
}

TEST(MlpFit, SplitIsStratifiedByOriginAndWrench) {
  FitConfig c = quickConfig();
  c.augmentation.mirror = true;
  c.mlp.max_epochs = 1;
  c.mlp.validation_fraction = 0.3;
  const ForceDataset positive = syntheticDataset(4, {-0.04, -0.03, -0.02, -0.01, 0.0}, {0.0, 0.3, 0.6});
  const MlpFitOutcome out = fitMlpToDataset(positive, c, "synthetic");
  const MlpPoints& pts = out.record.points;
  // Strata: origin × (zero wrench, a wrench); the surface rows of the measured and mirrored points
  // are zero.
  int total[6] = {0, 0, 0, 0, 0, 0}, held[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < pts.pointCount(); ++i) {
    const int stratum = 2 * static_cast<int>(pts.origin[i]) + (pts.values.row(i).isZero(0) ? 0 : 1);
    ++total[stratum];
    if (out.record.fit.validation[i]) ++held[stratum];
  }
  for (int stratum : {0, 1, 2, 3, 4}) EXPECT_GT(total[stratum], 0) << "stratum " << stratum;
  for (int stratum = 0; stratum < 6; ++stratum)
    EXPECT_EQ(held[stratum], std::lround(0.3 * total[stratum])) << "stratum " << stratum;
  // Stratified by origin only, the 12 measured points with a wrench could have lost their share to the
  // 3 zero ones: here 4 of them are held out (12 · 0.3 = 3.6), whatever the seed.
  EXPECT_EQ(held[1], 4);
  c.mlp.validation_fraction = 0;
  const MlpFitOutcome none = fitMlpToDataset(smallDataset(), c, "synthetic");
  EXPECT_EQ(std::count(none.record.fit.validation.begin(), none.record.fit.validation.end(), true), 0);
  EXPECT_TRUE(std::isnan(none.record.fit.validation_loss));
  expectAll(formatMlpFitReport(none.record), {"no validation points", "worst training points"});
}

TEST(MlpFit, TeacherGridIsFittedToTheTrainingPointsOnly) {
  FitConfig c = quickConfig();
  c.mlp.max_epochs = 1;
  c.mlp.teacher_grid = {3, 4};
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  EXPECT_EQ(out.record.fit.teacher_samples, 12);
  expectAll(formatMlpFitReport(out.record), {"plus 12 teacher samples"});
  // The teacher must not see the validation points: moving a validation point's data changes
  // nothing in the fit (the same split, the same teacher, the same training).
  ForceDataset moved = smallDataset();
  const MlpPoints& pts = out.record.points;
  int held = -1;
  for (int i = 0; i < pts.pointCount() && held < 0; ++i)
    if (out.record.fit.validation[i] && pts.origin[i] == PointOrigin::Measured) held = i;
  ASSERT_GE(held, 0);
  for (Eigen::Index r = 0; r < moved.features.rows(); ++r)
    if (moved.features.row(r) == pts.features.row(held)) moved.wrench.row(r) *= 3.0;
  const MlpFitOutcome again = fitMlpToDataset(moved, c, "synthetic");
  ASSERT_EQ(again.record.fit.validation, out.record.fit.validation);
  EXPECT_EQ(again.record.fit.parameters.layers.back().weight, out.record.fit.parameters.layers.back().weight);
  EXPECT_NE(again.record.fit.error.row(held), out.record.fit.error.row(held));
}

TEST(MlpFit, TeacherDepthRowsPackTowardsTheSurface) {
  const std::vector<double> even = teacherDepthRows(-0.07, 0.0, 8, 1.0);
  ASSERT_EQ(even.size(), 8u);
  for (int a = 0; a < 8; ++a) EXPECT_EQ(even[a], -0.07 + 0.07 * a / 7.0) << a;
  const std::vector<double> rows = teacherDepthRows(-0.07, 0.0, 5, 3.0);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows.front(), -0.07);
  EXPECT_EQ(rows.back(), 0.0);
  for (int a = 1; a < 4; ++a) EXPECT_NEAR(rows[a], -0.07 * std::pow(1.0 - a / 4.0, 3), 1e-15) << a;
  EXPECT_EQ(teacherDepthRows(-0.07, 0.0, 1, 3.0), std::vector<double>{-0.07});
  // The option reaches the grid: the same settings with another power give another fit.
  FitConfig c = quickConfig();
  c.mlp.max_epochs = 5;
  c.mlp.teacher_grid = {4, 3};
  const MlpFit uniform = fitMlpToDataset(smallDataset(), c, "synthetic").record.fit;
  c.mlp.teacher_depth_power = 3.0;
  const MlpFit packed = fitMlpToDataset(smallDataset(), c, "synthetic").record.fit;
  EXPECT_EQ(packed.teacher_samples, 12);
  EXPECT_NE(packed.history, uniform.history);
}

TEST(MlpFit, TeacherRefinementAddsColumnsBesideTheDataAngles) {
  FitConfig c = quickConfig();
  c.mlp.max_epochs = 5;
  c.mlp.validation_fraction = 0;
  c.mlp.teacher_grid = {3, 4};  // columns −0.6, −0.2, 0.2, 0.6
  const MlpFit plain = fitMlpToDataset(smallDataset(), c, "synthetic").record.fit;
  EXPECT_EQ(plain.teacher_samples, 12);
  c.mlp.teacher_refinement = {0.05};
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  // The data's angles −0.6, −0.3, 0, 0.3, 0.6, each ± 0.05 inside [−0.6, 0.6]: 8 more columns.
  EXPECT_EQ(out.record.fit.teacher_samples, 3 * 12);
  EXPECT_NE(out.record.fit.history, plain.history);
  EXPECT_EQ(out.record.settings["mlp"]["teacher_refinement"].dump(), "[0.05]");
  // An offset that lands on an existing column to round-off adds nothing there (−0.6 + 0.4 and
  // 0.6 − 0.4 are the columns ∓0.2): 0.1, ±0.4 and −0.1 only.
  c.mlp.teacher_refinement = {0.4};
  EXPECT_EQ(fitMlpToDataset(smallDataset(), c, "synthetic").record.fit.teacher_samples, 3 * (4 + 4));
}

// ==== bad settings ==============================================================================

TEST(MlpFitBadSettings, NameTheConfigurationKey) {
  const ConfigContext ctx{"fit.json", ""};
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"widht", 32}}}}, ctx); }),
            {"fit.json.mlp.widht", "did you mean 'width'"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"max_epochs", 0}}}}, ctx); }),
            {"fit.json.mlp.max_epochs", "at least 1"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"activation", "relu"}}}}, ctx); }),
            {"fit.json.mlp.activation", "ReLU", "C1", "tanh, softplus or silu"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"activation", "sigmoidal"}}}}, ctx); }),
            {"fit.json.mlp.activation", "unknown activation"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"validation_fraction", 1}}}}, ctx); }),
            {"fit.json.mlp.validation_fraction", "[0, 1)"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"learning_rate", 0}}}}, ctx); }),
            {"fit.json.mlp.learning_rate", "> 0"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"seed", -1}}}}, ctx); }),
            {"fit.json.mlp.seed", "integer"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"loss", "l1"}}}}, ctx); }),
            {"fit.json.mlp.loss", "\"relative\" or \"mse\""});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"hidden_layers", -1}}}}, ctx); }),
            {"fit.json.mlp.hidden_layers"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"teacher_grid", {10, 0}}}}}, ctx); }),
            {"fit.json.mlp.teacher_grid", "[n_phi, n_beta]"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"output_envelope", "sqrt"}}}}, ctx); }),
            {"fit.json.mlp.output_envelope", "\"none\"", "\"depth\"", "\"soft_depth\"", "got \"sqrt\""});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"output_envelope", 1}}}}, ctx); }),
            {"fit.json.mlp.output_envelope"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"mlp", {{"output_envelope", "depth"}, {"zero_anchors", true}}}}, ctx);
            }),
            {"fit.json.mlp.zero_anchors", "output_envelope"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"lbfgs_iterations", -1}}}}, ctx); }),
            {"fit.json.mlp.lbfgs_iterations"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"lbfgs_history", 0}}}}, ctx); }),
            {"fit.json.mlp.lbfgs_history"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"teacher_depth_power", 0.5}}}}, ctx); }),
            {"fit.json.mlp.teacher_depth_power", "[1, 100]"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"envelope_width", 0}}}}, ctx); }),
            {"fit.json.mlp.envelope_width", "(0, 10]"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"teacher_refinement", {0.01, -0.1}}}}}, ctx); }),
            {"fit.json.mlp.teacher_refinement", "(0, 10)"});
  expectAll(inputErrorMessage([&] { parseFitConfig(json{{"mlp", {{"teacher_refinement", 0.01}}}}, ctx); }),
            {"fit.json.mlp.teacher_refinement"});
  {  // the soft depth envelope goes with the anchors
    const FitConfig soft =
        parseFitConfig(json{{"mlp", {{"output_envelope", "soft_depth"}, {"zero_anchors", true}, {"envelope_width", 0.003}}}}, ctx);
    EXPECT_EQ(soft.mlp.output_envelope, MlpOutputEnvelope::SoftDepth);
    EXPECT_EQ(soft.mlp.envelope_width, 0.003);
    EXPECT_TRUE(soft.mlp.zero_anchors);
  }
  EXPECT_EQ(parseFitConfig(json::object(), ctx).mlp.output_envelope, MlpOutputEnvelope::None);
  EXPECT_EQ(parseFitConfig(json{{"mlp", {{"output_envelope", "depth"}}}}, ctx).mlp.output_envelope,
            MlpOutputEnvelope::Depth);

  // A validation fraction that leaves no training point (every origin rounds up to all its points).
  FitConfig c = quickConfig();
  c.augmentation.above_heights = std::vector<double>{};
  c.mlp.validation_fraction = 0.99;
  expectAll(inputErrorMessage([&] { fitMlpToDataset(syntheticDataset(2, {-0.02, -0.01}, {0.0}), c, "two.h5"); }),
            {"two.h5", "mlp.validation_fraction", "no point is left to train on"});
  // A single point: the data path says so first.
  expectAll(inputErrorMessage(
                [&] { fitMlpToDataset(syntheticDataset(2, {-0.02}, {0.0}), noAugmentation(), "one.h5"); }),
            {"one.h5", "1 feature point", "at least 2"});
}

TEST(MlpFitConfig, SettingsJsonParsesBackToTheSameSettings) {
  FitConfig c = fitConfigFile("data/granular/sand_mlp_fit.json");
  const json j = json::parse(fitConfigJson(c, 0.1572, "mlp").dump());
  for (const char* key : {"hidden_layers", "width", "activation", "max_epochs", "learning_rate", "final_learning_rate",
                          "batch_size", "validation_fraction", "patience", "seed", "weight_decay", "loss",
                          "relative_floor", "threads", "teacher_grid", "output_envelope", "lbfgs_iterations",
                          "lbfgs_history", "zero_anchors", "teacher_depth_power", "envelope_width", "teacher_refinement"})
    EXPECT_TRUE(j["mlp"].contains(key)) << key;
  EXPECT_EQ(j.contains("rbf"), c.mlp.teacher_grid[0] > 0) << "the rbf section only for a teacher";
  const FitConfig back = parseFitConfig(j, {"settings", ""});
  EXPECT_EQ(fitConfigJson(back, 0.1572, "mlp").dump(), fitConfigJson(c, 0.1572, "mlp").dump());
}

}  // namespace
}  // namespace nmdp::test
