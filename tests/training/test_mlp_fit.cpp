// MLP fitting of wrench spaces (training/mlp/mlp_fit.hpp):
//  * acceptance: an MLP trained on 3 × ../shared/granular/sand_samples with the published
//    augmentation (data/granular/sand_mlp_fit.json) stays within 10 % of the published RBF model
//    at random points of the valid range (depth −0.07..0, angle −0.9..0.9), measured as the RBF
//    acceptance of test_fit.cpp: per point, the largest |W_mlp − W_pub| over vertices and components
//    divided by the largest |W_pub| entry at that point;
//  * the same seed gives the same model bit for bit, another seed another model;
//  * the model file loads through the registry ({"type": "mlp"}) and gives the trainer's prediction,
//    with the /fit group (which loadMlpModel ignores) holding the report;
//  * early stopping keeps the best validation epoch's weights; the split is stratified by origin and wrench;
//  * bad settings are InputErrors naming the configuration key.
// The acceptance test skips with a message when ../shared is absent.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>

#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/registry.hpp"
#include "io/hdf5_file.hpp"
#include "terrain/plane.hpp"
#include "fit_fixtures.hpp"
#include "planar_foot.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/mlp/mlp_fit.hpp"

namespace nmdp::test {
namespace {
using json = nlohmann::json;

ForceDataset smallDataset() { return syntheticDataset(4, {-0.04, -0.03, -0.02, -0.01, 0.0}, {-0.6, -0.3, 0.0, 0.3, 0.6}); }

// The relative loss's scale (mlp_fit.hpp): the largest wrench entry over the training points.
double largestTrainingWrench(const PlanarPoints& pts, const std::vector<bool>& validation) {
  double largest = 0.0;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!validation[i]) largest = std::max(largest, pts.values.row(i).cwiseAbs().maxCoeff());
  return largest;
}

FitConfig quickConfig() {
  FitConfig c;
  c.augmentation.above_heights = {0.02, 0.05};
  c.mlp.hidden_layers = 2;
  c.mlp.width = 16;
  c.mlp.max_epochs = 300;
  c.mlp.learning_rate = 1e-2;
  c.mlp.final_learning_rate = 1e-3;
  c.mlp.validation_fraction = 0.2;
  c.mlp.patience = 0;
  return c;
}

// ==== acceptance ================================================================================

// With sand_mlp_fit.json (a 2-128-128-78 tanh network under the soft depth envelope, zero anchors, a
// 20 × 73 thin-plate teacher packed towards the surface with extra columns beside the measured angles,
// 300 Adam epochs then 8000 L-BFGS iterations; about 4.5 min of one core) the largest error on these
// points was 4.8 % on the machine of 2026-11-22 (seeds 2 and 3: 3.0 % and 3.4 %); training/README.md,
// "Acceptance", has the runs. Before the envelope and the refinement it was 61 % (disabled then).
TEST(MlpFitAcceptance, SandSamplesWithinTenPercentOfThePublishedModel) {
  NMDP_REQUIRE_SHARED("granular/sand_samples");
  NMDP_REQUIRE_SHARED("granular/robosimian_sand_rbf");
  const ForceDataset data = importSandSamplesCsv(sharedPath("granular/sand_samples"));
  const FitConfig config = fitConfigFile("data/granular/sand_mlp_fit.json");
  const MlpFitOutcome fit = fitMlpToDataset(data, config, "sand_samples");
  EXPECT_EQ(fit.record.points.pointCount(), 103) << "the published model's 103 points";
  std::cout << formatMlpFitReport(fit.record);

  const MlpFunction mlp(fit.record.fit.parameters);
  const Eigen::MatrixX2d f = acceptancePoints();  // those of the RBF acceptance in test_fit.cpp
  const int kPoints = static_cast<int>(f.rows());
  Eigen::MatrixXd W_pub, W_mlp;
  publishedSandModel().evaluate(f, W_pub, nullptr, nullptr);
  mlp.evaluate(f, W_mlp, nullptr, nullptr);
  const std::vector<double> e = errorRelativeToPublished(f, W_mlp, W_pub);
  int worst = 0;
  double worst_deep = 0.0;  // below 1 cm, for the record
  for (int i = 0; i < kPoints; ++i) {
    if (e[i] > e[worst]) worst = i;
    if (f(i, 0) < -0.01) worst_deep = std::max(worst_deep, e[i]);
  }
  std::vector<double> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  const auto pct = [&](double q) { return 100 * sorted[static_cast<size_t>(q * (kPoints - 1))]; };
  const long over = std::count_if(e.begin(), e.end(), [](double x) { return x > 0.1; });
  std::cout << "[ mlp vs published ] relative error (% of the largest wrench at the point, " << kPoints
            << " random points): median " << pct(0.5) << ", 90th " << pct(0.9) << ", 99th " << pct(0.99) << ", max "
            << 100 * e[worst] << " at (depth " << f(worst, 0) << ", angle " << f(worst, 1) << "); max below 1 cm "
            << 100 * worst_deep << "; points over 10 %: " << over << "\n";
  // For scale (not the acceptance measure): the largest error against the largest published entry
  // over all the points, which says how large the errors near the surface are in newtons.
  const double published_largest = W_pub.cwiseAbs().maxCoeff();
  const double largest_error = (W_mlp - W_pub).cwiseAbs().maxCoeff();
  std::cout << "[ mlp vs published ] largest error " << largest_error << " (data units) against the largest published "
            << "entry " << published_largest << ": " << 100 * largest_error / published_largest << " %\n";
  // The same per wrench component (F_x, F_z, τ_y), each against its own largest published value, so
  // that newtons are not compared with newton-metres.
  const char* const kComponent[3] = {"F_x", "F_z", "tau_y"};
  for (int c = 0; c < 3; ++c) {
    double published = 0.0, error = 0.0;
    for (Eigen::Index j = c; j < W_pub.cols(); j += 3) {
      published = std::max(published, W_pub.col(j).cwiseAbs().maxCoeff());
      error = std::max(error, (W_mlp.col(j) - W_pub.col(j)).cwiseAbs().maxCoeff());
    }
    std::cout << "[ mlp vs published ] " << kComponent[c] << ": largest error " << error << " against its largest "
              << "published value " << published << ": " << 100 * error / published << " %\n";
  }
  RecordProperty("max_relative_error_percent", std::to_string(100 * e[worst]));
  EXPECT_LT(e[worst], 0.10) << "at (depth " << f(worst, 0) << ", angle " << f(worst, 1) << ")";

  // The model file loads through the registry and gives the trainer's function.
  TempDir tmp;
  const std::string path = tmp.file("sand_mlp.h5");
  saveMlpFit(path, fit.record, fit.geometry);
  const MlpModelFile back = loadMlpModel(path);
  EXPECT_EQ(back.parameters.layers.back().weight, fit.record.fit.parameters.layers.back().weight);
  Eigen::MatrixXd W_back;
  MlpFunction(back.parameters).evaluate(f, W_back, nullptr, nullptr);
  EXPECT_EQ(W_back, W_mlp);
}

// ==== determinism ===============================================================================

void expectSameModelFiles(const std::string& a, const std::string& b, bool same) {
  const MlpModelFile ma = loadMlpModel(a), mb = loadMlpModel(b);
  bool equal = ma.parameters.input_mean == mb.parameters.input_mean &&
               ma.parameters.input_std == mb.parameters.input_std &&
               ma.parameters.output_scale == mb.parameters.output_scale &&
               ma.parameters.output_offset == mb.parameters.output_offset &&
               ma.parameters.layers.size() == mb.parameters.layers.size();
  for (size_t i = 0; equal && i < ma.parameters.layers.size(); ++i)
    equal = ma.parameters.layers[i].weight == mb.parameters.layers[i].weight &&
            ma.parameters.layers[i].bias == mb.parameters.layers[i].bias;
  EXPECT_EQ(equal, same) << a << " vs " << b;
  const h5::File fa = h5::File::openRead(a), fb = h5::File::openRead(b);
  for (const char* d : {"/fit/history", "/fit/error", "/fit/validation"})
    EXPECT_EQ(fa.readMatrix(d) == fb.readMatrix(d), same) << d;
}

TEST(MlpFit, SameSeedGivesTheSameModelBitForBit) {
  TempDir dir;
  const ForceDataset d = smallDataset();
  FitConfig c = quickConfig();
  c.mlp.batch_size = 8;  // the mini-batch order is seeded too
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), other = dir.file("other.h5");
  for (const std::string& path : {a, b}) {
    const MlpFitOutcome fit = fitMlpToDataset(d, c, "synthetic");
    saveMlpFit(path, fit.record, fit.geometry);
  }
  expectSameModelFiles(a, b, true);
  {
    const h5::File fa = h5::File::openRead(a), fb = h5::File::openRead(b);
    EXPECT_EQ(fa.readStringAttribute("/fit", "settings"), fb.readStringAttribute("/fit", "settings"));
  }
  c.mlp.seed = 2;
  const MlpFitOutcome fit = fitMlpToDataset(d, c, "synthetic");
  saveMlpFit(other, fit.record, fit.geometry);
  expectSameModelFiles(a, other, false);
}

TEST(MlpFit, SameSeedGivesTheSameModelBitForBitWithTheDepthEnvelope) {
  TempDir dir;
  const ForceDataset d = smallDataset();
  FitConfig c = quickConfig();
  c.mlp.batch_size = 8;
  c.mlp.output_envelope = MlpOutputEnvelope::Depth;
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), other = dir.file("other.h5");
  for (const std::string& path : {a, b}) {
    const MlpFitOutcome fit = fitMlpToDataset(d, c, "synthetic");
    saveMlpFit(path, fit.record, fit.geometry);
  }
  expectSameModelFiles(a, b, true);
  EXPECT_EQ(loadMlpModel(a).parameters.output_envelope, MlpOutputEnvelope::Depth);
  c.mlp.seed = 2;
  const MlpFitOutcome fit = fitMlpToDataset(d, c, "synthetic");
  saveMlpFit(other, fit.record, fit.geometry);
  expectSameModelFiles(a, other, false);
}

// ==== the depth envelope ========================================================================

TEST(MlpFit, DepthEnvelopeFitsTheWrenchAndVanishesAtTheSurface) {
  FitConfig c = quickConfig();
  c.mlp.output_envelope = MlpOutputEnvelope::Depth;
  c.mlp.max_epochs = 1500;
  c.augmentation.above_heights = std::vector<double>{};  // the data is then (−φ) times a function of β alone
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  const PlanarPoints& pts = out.record.points;
  ASSERT_EQ(fit.parameters.output_envelope, MlpOutputEnvelope::Depth);

  // The output normalization is that of N = W / (−φ) over the training points below the surface.
  std::vector<int> below;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i] && pts.features(i, 0) < 0.0) below.push_back(i);
  ASSERT_GT(below.size(), 2u);
  Eigen::MatrixXd N(below.size(), pts.values.cols());
  for (size_t r = 0; r < below.size(); ++r) N.row(r) = pts.values.row(below[r]) / -pts.features(below[r], 0);
  const Eigen::RowVectorXd mean = N.colwise().mean();
  EXPECT_LT((fit.parameters.output_offset.transpose() - mean).cwiseAbs().maxCoeff(),
            1e-12 * mean.cwiseAbs().maxCoeff());
  const Eigen::RowVectorXd sd = ((N.rowwise() - mean).array().square().colwise().mean()).sqrt();
  EXPECT_LT((fit.parameters.output_scale.transpose() - sd).cwiseAbs().maxCoeff(), 1e-12 * sd.cwiseAbs().maxCoeff());

  // The recorded errors are those of W = (−φ) N: exactly zero at the points on the surface (whose
  // data is zero), and the training loss of the kept weights is the relative loss on W.
  double largest = 0.0;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i]) largest = std::max(largest, pts.values.row(i).cwiseAbs().maxCoeff());
  const double floor = c.mlp.relative_floor * largest;
  double sum = 0.0;
  int count = 0, surface = 0;
  for (int i = 0; i < pts.pointCount(); ++i) {
    if (pts.features(i, 0) == 0.0) {
      ++surface;
      EXPECT_EQ(pts.values.row(i).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ(fit.error.row(i).cwiseAbs().maxCoeff(), 0.0) << "point " << i;
    }
    if (fit.validation[i]) continue;
    const double si = std::max(pts.values.row(i).cwiseAbs().maxCoeff(), floor);
    sum += (fit.error.row(i) / si).squaredNorm();
    count += static_cast<int>(fit.error.cols());
  }
  EXPECT_EQ(surface, 5);
  ASSERT_GT(count, 0);
  EXPECT_NEAR(sum / count, fit.train_loss, 1e-9 * fit.train_loss + 1e-15);
  // And it learnt: the loss fell by orders of magnitude, and on this data, proportional to the depth,
  // the model is within 1 % of every measured point (measured: 0.13 %, and a validation loss of 5e-7
  // against 9e-3 for the same network without the envelope, 10 % off at worst).
  EXPECT_LT(fit.train_loss, 1e-3 * fit.history(0, 0));
  for (int i = 0; i < pts.pointCount(); ++i) {
    if (pts.origin[i] == PointOrigin::Measured) {
      EXPECT_LT(fit.relative.row(i).maxCoeff(), 0.01) << "point " << i << " " << pts.features.row(i);
    }
  }
  FitConfig plain = c;
  plain.mlp.output_envelope = MlpOutputEnvelope::None;
  EXPECT_LT(fit.validation_loss, 0.01 * fitMlpToDataset(smallDataset(), plain, "synthetic").record.fit.validation_loss);

  // "mse" with the envelope: the mean of ((W_fit − W_data)_c / σ_c)², σ_c the spread of output c of W
  // over the training points.
  FitConfig mse = c;
  mse.mlp.loss = MlpLoss::Mse;
  mse.mlp.max_epochs = 50;
  const MlpFitOutcome m = fitMlpToDataset(smallDataset(), mse, "synthetic");
  ASSERT_EQ(m.record.fit.validation, fit.validation);  // the same split
  std::vector<int> train;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i]) train.push_back(i);
  Eigen::MatrixXd Yt(train.size(), pts.values.cols()), Et(train.size(), pts.values.cols());
  for (size_t r = 0; r < train.size(); ++r) {
    Yt.row(r) = pts.values.row(train[r]);
    Et.row(r) = m.record.fit.error.row(train[r]);
  }
  const Eigen::RowVectorXd sigma = (Yt.rowwise() - Yt.colwise().mean()).array().square().colwise().mean().sqrt();
  ASSERT_GT(sigma.minCoeff(), 0.0);
  const double mse_loss = (Et.array().rowwise() / sigma.array()).square().mean();
  EXPECT_NEAR(mse_loss, m.record.fit.train_loss, 1e-9 * mse_loss);

  // The file keeps the envelope, and the settings record it.
  TempDir dir;
  const std::string path = dir.file("envelope.h5");
  saveMlpFit(path, out.record, out.geometry);
  EXPECT_EQ(loadMlpModel(path).parameters.output_envelope, MlpOutputEnvelope::Depth);
  EXPECT_EQ(out.record.settings["mlp"]["output_envelope"], "depth");
  expectAll(formatMlpFitReport(out.record), {"\"output_envelope\":\"depth\""});
}

// ==== L-BFGS and zero anchors ===================================================================

TEST(MlpFit, LbfgsAfterAdamRecordsItsEpochsAndLowersTheLoss) {
  FitConfig c = quickConfig();
  const MlpFit adam = fitMlpToDataset(smallDataset(), c, "synthetic").record.fit;
  c.mlp.lbfgs_iterations = 95;  // 10 per recorded epoch: 10 epochs, the last of 5 iterations
  const MlpFit both = fitMlpToDataset(smallDataset(), c, "synthetic").record.fit;
  EXPECT_EQ(both.epochs, c.mlp.max_epochs + 10);
  EXPECT_EQ(both.history.rows(), both.epochs);
  // The Adam epochs are the same; L-BFGS then lowers the validation loss well below Adam's best.
  EXPECT_TRUE(both.history.topRows(c.mlp.max_epochs) == adam.history);
  EXPECT_GT(both.best_epoch, c.mlp.max_epochs);
  EXPECT_LT(both.validation_loss, 0.5 * adam.validation_loss);
}

TEST(MlpFit, ZeroAnchorsMakeTheModelVanishAtTheZeroWrenchTrainingPoints) {
  FitConfig c = quickConfig();
  c.mlp.zero_anchors = true;
  c.mlp.lbfgs_iterations = 50;
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  const PlanarPoints& pts = out.record.points;
  // The anchors are the training points with an exactly zero wrench, in order.
  std::vector<int> zero;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i] && pts.values.row(i).cwiseAbs().maxCoeff() == 0.0) zero.push_back(i);
  ASSERT_GT(zero.size(), 2u);
  const MlpParameters& p = fit.parameters;
  ASSERT_EQ(p.anchors.rows(), static_cast<Eigen::Index>(zero.size()));
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t a = 0; a < zero.size(); ++a) {
    EXPECT_EQ(p.anchors.row(a), pts.features.row(zero[a]));
    for (size_t b = a + 1; b < zero.size(); ++b)
      nearest = std::min(nearest, ((pts.features.row(zero[a]) - pts.features.row(zero[b])).transpose().array() /
                                   p.input_std.array()).matrix().norm());
  }
  EXPECT_DOUBLE_EQ(p.anchor_radius, nearest);
  // The recorded error there is zero to round-off, while the network itself is not zero there.
  const double scale = pts.values.cwiseAbs().maxCoeff();
  MlpParameters bare = p;
  bare.anchors.resize(0, 2);
  Eigen::MatrixXd N;
  MlpFunction(bare).evaluate(p.anchors, N, nullptr, nullptr);
  EXPECT_GT(N.cwiseAbs().maxCoeff(), 1e-6 * scale);
  for (int i : zero) EXPECT_LT(fit.error.row(i).cwiseAbs().maxCoeff(), 1e-12 * scale) << "point " << i;
  // The training loss recorded is the relative loss of the anchored model, with the network itself
  // at the anchors (where the anchored model is zero), there relative to the largest wrench.
  const double largest = largestTrainingWrench(pts, fit.validation);
  const double floor = c.mlp.relative_floor * largest;
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < pts.pointCount(); ++i) {
    if (fit.validation[i]) continue;
    const bool anchor = std::find(zero.begin(), zero.end(), i) != zero.end();
    const Eigen::RowVectorXd e = anchor ? Eigen::RowVectorXd(N.row(std::find(zero.begin(), zero.end(), i) - zero.begin()))
                                        : Eigen::RowVectorXd(fit.error.row(i));
    sum += (e / (anchor ? std::max(floor, largest) : std::max(pts.values.row(i).cwiseAbs().maxCoeff(), floor)))
               .squaredNorm();
    count += static_cast<int>(e.size());
  }
  EXPECT_NEAR(sum / count, fit.train_loss, 1e-9 * fit.train_loss);
  // The file keeps the anchors; the settings record the option; the same seed gives the same bits.
  TempDir dir;
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5");
  saveMlpFit(a, out.record, out.geometry);
  const MlpFitOutcome again = fitMlpToDataset(smallDataset(), c, "synthetic");
  saveMlpFit(b, again.record, again.geometry);
  expectSameModelFiles(a, b, true);
  EXPECT_EQ(loadMlpModel(a).parameters.anchors, p.anchors);
  EXPECT_EQ(out.record.settings["mlp"]["zero_anchors"], true);
  expectAll(formatMlpFitReport(out.record), {"zero anchors: the " + std::to_string(zero.size()) + " zero-wrench"});
  FitConfig both = c;
  both.mlp.output_envelope = MlpOutputEnvelope::Depth;
  EXPECT_THROW(fitMlpToDataset(smallDataset(), both, "synthetic"), std::invalid_argument);
  EXPECT_EQ(out.record.settings["mlp"]["lbfgs_iterations"], 50);
}

// ==== the model file ============================================================================

TEST(MlpFit, ModelFileLoadsThroughTheRegistryAndMatchesTheTrainer) {
  TempDir dir;
  const FitConfig c = quickConfig();
  const MlpFitOutcome fit = fitMlpToDataset(smallDataset(), c, "synthetic.h5");
  const std::string path = dir.file("model.h5");
  saveMlpFit(path, fit.record, fit.geometry);

  // loadMlpModel ignores /fit and reads back exactly the trained parameters and the geometry.
  const MlpModelFile m = loadMlpModel(path);
  ASSERT_EQ(m.parameters.layers.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(m.parameters.layers[i].weight, fit.record.fit.parameters.layers[i].weight);
    EXPECT_EQ(m.parameters.layers[i].bias, fit.record.fit.parameters.layers[i].bias);
  }
  EXPECT_EQ(m.parameters.input_mean, fit.record.fit.parameters.input_mean);
  EXPECT_EQ(m.parameters.output_scale, fit.record.fit.parameters.output_scale);
  EXPECT_EQ(m.geometry.torque_centre, 0.05);
  EXPECT_EQ(m.geometry.cutoff, fit.geometry.cutoff);
  EXPECT_EQ(fit.geometry.cutoff, 0.0) << "the data's surface row is zero: the cut-off decided from the data";

  // /fit: the report, the settings, the trainer's prediction (values + error) at the points.
  const h5::File f = h5::File::openRead(path);
  const std::string report = f.readStringAttribute("/fit", "report");
  EXPECT_EQ(report, formatMlpFitReport(fit.record));
  expectAll(report, {"MLP fit of synthetic.h5", "2-16-16-12 tanh", "best epoch", "validation", "25 measured",
                     "\"max_epochs\":300"});
  EXPECT_EQ(f.readStringAttribute("/fit", "settings"), fit.record.settings.dump());
  const Eigen::MatrixXd prediction = f.readMatrix("/fit/values") + f.readMatrix("/fit/error");

  // The registry builds {"type": "mlp", "file": ...}; its wrenches are the trainer's, placed by the
  // planar geometry: the same as a PlanarWrenchModel around the trainer's own parameters.
  const std::unique_ptr<ContactModel> loaded =
      ContactModelRegistry::withBuiltins().build(json{{"type", "mlp"}, {"file", path}}, ConfigContext{"test", ""});
  const PlanarWrenchModel direct(std::make_shared<const MlpFunction>(fit.record.fit.parameters), fit.geometry, "mlp",
                                 json::object());
  ASSERT_EQ(loaded->vertexCount(), 4);
  const PlaneTerrain ground;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> depth(-0.04, 0.0), tilt(-0.6, 0.6);
  for (int n = 0; n < 50; ++n) {
    const double t = tilt(rng);  // drawn before the depth, as the frames always were
    std::vector<ContactFrame> frames{planarFoot(0.02, depth(rng), t, 0.1)};
    std::vector<ContactWrenches> a(1), b(1);
    a[0].resize(4);
    b[0].resize(4);
    loaded->evaluate(frames, ground, a, false);
    direct.evaluate(frames, ground, b, false);
    EXPECT_EQ(a[0].V, b[0].V);
  }
  // And the function at the fit points is the prediction the trainer recorded.
  Eigen::MatrixXd W;
  MlpFunction(m.parameters).evaluate(fit.record.points.features, W, nullptr, nullptr);
  EXPECT_LT((W - prediction).cwiseAbs().maxCoeff(), 1e-9 * (1 + prediction.cwiseAbs().maxCoeff()));
}

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
  const PlanarPoints& pts = out.record.points;
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
  const PlanarPoints& pts = out.record.points;
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
  const PlanarPoints& pts = out.record.points;
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

TEST(MlpFit, SoftDepthEnvelopeWithZeroAnchors) {
  FitConfig c = quickConfig();
  c.mlp.zero_anchors = true;
  c.mlp.output_envelope = MlpOutputEnvelope::SoftDepth;
  c.mlp.envelope_width = 0.01;
  c.mlp.lbfgs_iterations = 50;
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  const PlanarPoints& pts = out.record.points;
  const MlpParameters& p = fit.parameters;
  ASSERT_EQ(p.output_envelope, MlpOutputEnvelope::SoftDepth);
  EXPECT_EQ(p.envelope_width, 0.01);
  ASSERT_GT(p.anchors.rows(), 2);
  const double scale = pts.values.cwiseAbs().maxCoeff();
  std::vector<int> zero;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i] && pts.values.row(i).cwiseAbs().maxCoeff() == 0.0) zero.push_back(i);
  ASSERT_EQ(p.anchors.rows(), static_cast<Eigen::Index>(zero.size()));
  for (int i : zero) EXPECT_LT(fit.error.row(i).cwiseAbs().maxCoeff(), 1e-12 * scale) << "point " << i;
  // It learns: the error at the training points is a few per cent of the largest wrench.
  double worst = 0.0;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i]) worst = std::max(worst, fit.error.row(i).cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 0.1 * scale);
  // The recorded training loss is the documented one: relative to the point's largest wrench, with
  // the floor scaled by m(min(φ, 0)) / m(φ of the largest wrench); at the anchors m N(ξ_a) relative
  // to the largest wrench.
  const auto m = [&](double phi) {
    double v, dm;
    mlpEnvelopeFactor(MlpOutputEnvelope::SoftDepth, 0.01, phi, &v, &dm);
    return v;
  };
  double largest = 0.0, m_largest = 1.0;
  for (int i = 0; i < pts.pointCount(); ++i)
    if (!fit.validation[i] && pts.values.row(i).cwiseAbs().maxCoeff() > largest) {
      largest = pts.values.row(i).cwiseAbs().maxCoeff();
      m_largest = m(pts.features(i, 0));
    }
  MlpParameters bare = p;  // the network under its envelope, without the anchors
  bare.anchors.resize(0, 2);
  Eigen::MatrixXd mN;
  MlpFunction(bare).evaluate(p.anchors, mN, nullptr, nullptr);
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < pts.pointCount(); ++i) {
    if (fit.validation[i]) continue;
    const auto at = std::find(zero.begin(), zero.end(), i);
    const double floor = c.mlp.relative_floor * largest * m(std::min(pts.features(i, 0), 0.0)) / m_largest;
    const Eigen::RowVectorXd e = at != zero.end() ? Eigen::RowVectorXd(mN.row(at - zero.begin()))
                                                  : Eigen::RowVectorXd(fit.error.row(i));
    const double s = at != zero.end() ? std::max(c.mlp.relative_floor * largest, largest)
                                      : std::max(pts.values.row(i).cwiseAbs().maxCoeff(), floor);
    sum += (e / s).squaredNorm();
    count += static_cast<int>(e.size());
  }
  EXPECT_NEAR(sum / count, fit.train_loss, 1e-9 * fit.train_loss);
  // The file keeps the envelope; the settings record it; the same seed gives the same bits.
  TempDir dir;
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5");
  saveMlpFit(a, out.record, out.geometry);
  saveMlpFit(b, fitMlpToDataset(smallDataset(), c, "synthetic").record, out.geometry);
  expectSameModelFiles(a, b, true);
  const MlpModelFile loaded = loadMlpModel(a);
  EXPECT_EQ(loaded.parameters.output_envelope, MlpOutputEnvelope::SoftDepth);
  EXPECT_EQ(loaded.parameters.envelope_width, 0.01);
  EXPECT_EQ(out.record.settings["mlp"]["output_envelope"], "soft_depth");
  EXPECT_EQ(out.record.settings["mlp"]["envelope_width"], 0.01);
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
