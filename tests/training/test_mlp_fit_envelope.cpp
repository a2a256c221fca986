// MLP fitting of wrench spaces (training/mlp/mlp_fit.hpp) under an output envelope: the depth
// envelope fits the wrench and vanishes at the surface; L-BFGS after Adam lowers the loss; zero
// anchors make the model vanish at the zero-wrench training points, also under the soft depth
// envelope.
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

// ==== the depth envelope ========================================================================

TEST(MlpFit, DepthEnvelopeFitsTheWrenchAndVanishesAtTheSurface) {
  FitConfig c = quickConfig();
  c.mlp.output_envelope = MlpOutputEnvelope::Depth;
  c.mlp.max_epochs = 1500;
  c.augmentation.above_heights = std::vector<double>{};  // the data is then (−φ) times a function of β alone
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  const MlpPoints& pts = out.record.points;
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
  const MlpPoints& pts = out.record.points;
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

TEST(MlpFit, SoftDepthEnvelopeWithZeroAnchors) {
  FitConfig c = quickConfig();
  c.mlp.zero_anchors = true;
  c.mlp.output_envelope = MlpOutputEnvelope::SoftDepth;
  c.mlp.envelope_width = 0.01;
  c.mlp.lbfgs_iterations = 50;
  const MlpFitOutcome out = fitMlpToDataset(smallDataset(), c, "synthetic");
  const MlpFit& fit = out.record.fit;
  const MlpPoints& pts = out.record.points;
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

}  // namespace
}  // namespace nmdp::test
