// Fitting 3-D RBF wrench spaces (training/spatial_rbf_fit.hpp) by the planar fit's code path:
//  * interpolation (ridge 0) reproduces the data; with the linear tail a linear function is
//    reproduced everywhere, and a smooth function between the points within a stated bound;
//  * the closed-form leave-one-point-out error equals brute-force refits without each point (with
//    and without the ridge and the tail);
//  * the augmentation adds zero-wrench points at every (beta, gamma) of the data;
//  * the report lists the leave-one-point-out error per vertex;
//  * bad 3-D data and keys 3-D data cannot take give one InputError naming the file and the key.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include "fit_fixtures.hpp"
#include "test_support.hpp"
#include "training/fit_config.hpp"
#include "training/spatial_points.hpp"
#include "training/spatial_rbf_fit.hpp"

namespace nmdp::test {
namespace {

// A smooth made-up 6-D wrench at (phi, beta, gamma) for vertex v, zero above the surface.
Eigen::Matrix<double, 1, 6> smoothWrench(double phi, double beta, double gamma, int v) {
  const double depth = std::max(0.0, -phi);
  Eigen::Matrix<double, 1, 6> w;
  w << depth * 10 * std::sin(v + gamma), depth * 20 * std::cos(v - beta), depth * 5 * std::sin(beta + gamma),
      depth * 100 * std::sin(v + beta), depth * 150 * std::sin(v - gamma), depth * 1000 * (1.5 + std::cos(beta * gamma));
  return w;
}

// A 3-D dataset: the points phis × tilts, K vertices each, values from `wrench`.
template <class Wrench>
ForceDataset spatialDataset(int K, const std::vector<double>& phis, const std::vector<Eigen::Vector2d>& tilts,
                            Wrench wrench) {
  ForceDataset d;
  const int P = static_cast<int>(phis.size() * tilts.size());
  d.features.resize(P * K, 3);
  d.vertex.resize(P * K);
  d.wrench.resize(P * K, 6);
  int row = 0;
  for (double phi : phis)
    for (const Eigen::Vector2d& t : tilts)
      for (int v = 0; v < K; ++v, ++row) {
        d.features.row(row) << phi, t[0], t[1];
        d.vertex[row] = v;
        d.wrench.row(row) = wrench(phi, t[0], t[1], v);
      }
  d.feature_names = {"phi", "beta", "gamma"};
  d.feature_units = {"m", "rad", "rad"};
  d.wrench_names = {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};
  d.wrench_units = {"N m", "N m", "N m", "N", "N", "N"};
  d.source = "synthetic";
  return d;
}

const std::vector<double> kPhis = {-0.06, -0.045, -0.03, -0.015, -0.005};
const std::vector<Eigen::Vector2d> kTilts = {{0, 0}, {0.6, 0}, {-0.6, 0}, {0, 0.6}, {0, -0.6}, {0.6, 0.6}, {-0.6, -0.6}};

ForceDataset smoothDataset(int K = 2) {
  return spatialDataset(K, kPhis, kTilts, [](double p, double b, double g, int v) { return smoothWrench(p, b, g, v); });
}

// The interpolant by hand from its parameters (the formula of spatial_rbf_function.hpp), independent
// of the model's own evaluation.
Eigen::MatrixXd evaluateByHand(const SpatialRbfParameters& p, const Eigen::MatrixX3d& f) {
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(f.rows(), p.weights.cols());
  for (Eigen::Index b = 0; b < f.rows(); ++b) {
    for (Eigen::Index i = 0; i < p.centres.rows(); ++i) {
      double kappa = 0.0, g = 0.0;
      const Eigen::RowVector3d d = (f.row(b) - p.centres.row(i)).cwiseProduct(p.scaling.transpose());
      rbfKernel(p.kernel, p.epsilon, d.squaredNorm(), &kappa, &g);
      W.row(b) += kappa * p.weights.row(i);
    }
    if (p.polynomial.size())
      W.row(b) += p.polynomial.row(0) + f(b, 0) * p.polynomial.row(1) + f(b, 1) * p.polynomial.row(2) +
                  f(b, 2) * p.polynomial.row(3);
  }
  return W;
}

FitConfig spatialConfig(RbfKernel kernel, bool tail, double ridge = 0.0) {
  FitConfig c;
  c.augmentation.above_heights = std::vector<double>{};
  c.rbf.spec.kernel = kernel;
  c.rbf.polynomial = tail;
  c.rbf.ridge = ridge;
  c.rbf.scaling_given = 3;
  c.rbf.spatial_scaling = Eigen::Vector3d(20.0, 1.0, 1.0);
  return c;
}

TEST(SpatialRbfFit, InterpolatesItsData) {
  const ForceDataset data = smoothDataset();
  for (RbfKernel kernel : {RbfKernel::ThinPlate, RbfKernel::Cubic}) {
    const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(data, spatialConfig(kernel, true), "synthetic");
    const SpatialRbfFitRecord& r = fit.record;
    ASSERT_EQ(r.points.pointCount(), static_cast<int>(kPhis.size() * kTilts.size()));
    ASSERT_EQ(r.parameters.weights.cols(), 12);
    ASSERT_EQ(r.parameters.polynomial.rows(), 4);
    const Eigen::MatrixXd W = evaluateByHand(r.parameters, r.points.features);
    EXPECT_LT((W - r.points.values).cwiseAbs().maxCoeff(), 1e-8 * r.points.values.cwiseAbs().maxCoeff())
        << rbfKernelName(kernel);
  }
}

// With the linear tail the fit reproduces a linear function exactly, also between the points.
TEST(SpatialRbfFit, ReproducesALinearFunctionEverywhere) {
  const auto linear = [](double p, double b, double g, int v) {
    Eigen::Matrix<double, 1, 6> w;
    for (int c = 0; c < 6; ++c) w[c] = (c + 1 + v) * (1.0 + 30 * p) + (c - 2) * b + (3 - c + v) * g;
    return w;
  };
  const ForceDataset data = spatialDataset(2, kPhis, kTilts, linear);
  const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(data, spatialConfig(RbfKernel::Cubic, true), "linear");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> phi(-0.06, -0.005), tilt(-0.6, 0.6);
  Eigen::MatrixX3d f(50, 3);
  Eigen::MatrixXd expected(50, 12);
  for (int b = 0; b < 50; ++b) {
    f.row(b) << phi(rng), tilt(rng), tilt(rng);
    for (int v = 0; v < 2; ++v) expected.block(b, 6 * v, 1, 6) = linear(f(b, 0), f(b, 1), f(b, 2), v);
  }
  EXPECT_LT((evaluateByHand(fit.record.parameters, f) - expected).cwiseAbs().maxCoeff(), 1e-9);
}

// Between the points of a 5 x 3 x 3 grid (depth 1.5 cm, tilt 0.6 rad apart) a smooth function is
// reproduced within 0.5 % of its largest value (measured: 0.18 %, the cubic kernel with the tail).
TEST(SpatialRbfFit, ReproducesASmoothFunctionBetweenThePoints) {
  std::vector<Eigen::Vector2d> grid;
  for (double b : {-0.6, 0.0, 0.6})
    for (double g : {-0.6, 0.0, 0.6}) grid.emplace_back(b, g);
  const auto smooth = [](double p, double b, double g, int v) { return smoothWrench(p, b, g, v); };
  const ForceDataset data = spatialDataset(2, kPhis, grid, smooth);
  const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(data, spatialConfig(RbfKernel::Cubic, true), "smooth");
  // Midpoints of the grid cells, inside the data's range.
  Eigen::MatrixX3d f(4 * 2 * 2, 3);
  Eigen::MatrixXd expected(f.rows(), 12);
  int b = 0;
  for (int i = 0; i + 1 < static_cast<int>(kPhis.size()); ++i)
    for (double beta : {-0.3, 0.3})
      for (double gamma : {-0.3, 0.3}) {
        f.row(b) << 0.5 * (kPhis[i] + kPhis[i + 1]), beta, gamma;
        for (int v = 0; v < 2; ++v) expected.block(b, 6 * v, 1, 6) = smooth(f(b, 0), beta, gamma, v);
        ++b;
      }
  const double error = (evaluateByHand(fit.record.parameters, f) - expected).cwiseAbs().maxCoeff();
  const double largest = data.wrench.cwiseAbs().maxCoeff();
  std::cout << "largest error between the points: " << 100 * error / largest << " % of the largest value\n";
  EXPECT_LT(error, 0.005 * largest);
}

struct LooCase {
  RbfKernel kernel;
  double ridge;
  bool tail;
};
class SpatialLoo : public ::testing::TestWithParam<LooCase> {};

// Rippa's closed form against refitting without the point, for a few points.
TEST_P(SpatialLoo, EqualsBruteForceRefits) {
  const ForceDataset data = smoothDataset();
  const FitConfig config = spatialConfig(GetParam().kernel, GetParam().tail, GetParam().ridge);
  const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(data, config, "loo");
  const SpatialPoints& pts = fit.record.points;
  for (int i : {0, 7, 18, 34}) {
    ForceDataset rest = data;
    const int K = pts.vertexCount();
    rest.features.resize(data.features.rows() - K, 3);
    rest.vertex.resize(data.vertex.rows() - K);
    rest.wrench.resize(data.wrench.rows() - K, 6);
    for (Eigen::Index s = 0, n = 0; s < data.features.rows(); ++s)
      if (data.features.row(s) != pts.features.row(i)) {
        rest.features.row(n) = data.features.row(s);
        rest.vertex[n] = data.vertex[s];
        rest.wrench.row(n++) = data.wrench.row(s);
      }
    const SpatialRbfFitOutcome refit = fitSpatialRbfToDataset(rest, config, "refit");
    const Eigen::RowVectorXd brute =
        pts.values.row(i) - evaluateByHand(refit.record.parameters, Eigen::MatrixX3d(pts.features.row(i)));
    EXPECT_LT((fit.record.fit.loo_error.row(i) - brute).cwiseAbs().maxCoeff(),
              1e-7 * (1.0 + brute.cwiseAbs().maxCoeff()))
        << "point " << i << "\nclosed form " << fit.record.fit.loo_error.row(i) << "\nbrute force " << brute;
    for (int j = 0; j < K; ++j)  // per vertex: the largest of its six entries, relative to the point's largest
      EXPECT_DOUBLE_EQ(fit.record.fit.loo_relative(i, j),
                       fit.record.fit.loo_error.block(i, 6 * j, 1, 6).cwiseAbs().maxCoeff() /
                           pts.values.row(i).cwiseAbs().maxCoeff());
  }
}

INSTANTIATE_TEST_SUITE_P(KernelsRidgeTail, SpatialLoo,
                         ::testing::Values(LooCase{RbfKernel::ThinPlate, 0.0, false},
                                           LooCase{RbfKernel::Cubic, 0.0, true},
                                           LooCase{RbfKernel::Gaussian, 1e-3, true}));

TEST(SpatialRbfFit, AddsZeroPointsAtEveryTiltOfTheData) {
  const SpatialPoints grouped = groupSpatialSamples(smoothDataset(), "synthetic");
  const SpatialPoints out = augmentSpatial(grouped, 2.0, {0.01, 0.03});
  ASSERT_EQ(out.pointCount(), grouped.pointCount() + 2 * static_cast<int>(kTilts.size()));
  EXPECT_EQ(out.values.topRows(grouped.pointCount()), 2.0 * grouped.values);
  for (int n = 0; n < 2 * static_cast<int>(kTilts.size()); ++n) {
    const int i = grouped.pointCount() + n;
    EXPECT_EQ(out.origin[i], PointOrigin::AboveSurface);
    EXPECT_EQ(out.features(i, 0), n < static_cast<int>(kTilts.size()) ? 0.01 : 0.03);
    EXPECT_EQ(out.features(i, 1), kTilts[n % kTilts.size()][0]);
    EXPECT_EQ(out.features(i, 2), kTilts[n % kTilts.size()][1]);
    EXPECT_EQ(out.values.row(i).cwiseAbs().maxCoeff(), 0.0);
  }
  // Left to the data: the published heights scaled to the data's 6 cm, the cut-off at the surface.
  FitConfig c = spatialConfig(RbfKernel::ThinPlate, false);
  c.augmentation.above_heights.reset();
  const SpatialRbfFitOutcome fit = fitSpatialRbfToDataset(smoothDataset(), c, "synthetic");
  EXPECT_EQ(fit.record.points.pointCount(), grouped.pointCount() + 10 * static_cast<int>(kTilts.size()));
  EXPECT_EQ(fit.geometry.cutoff, 0.0);
  EXPECT_DOUBLE_EQ(fit.geometry.cutoff_width, 0.005);
}

TEST(SpatialRbfFit, ReportListsTheLeaveOneOutErrorPerVertex) {
  const SpatialRbfFitOutcome fit =
      fitSpatialRbfToDataset(smoothDataset(3), spatialConfig(RbfKernel::ThinPlate, true), "synthetic.h5");
  const std::string report = formatSpatialRbfFitReport(fit.record);
  expectAll(report, {"3-D RBF fit of synthetic.h5", "\"scaling\":[20.0,1.0,1.0]", "3 vertices",
                     "max(measured)  rms(measured)", "worst points"});
  const Eigen::MatrixXd& loo = fit.record.fit.loo_relative;  // all points are measured here
  for (int j = 0; j < 3; ++j) {
    Eigen::Index worst = 0;
    loo.col(j).maxCoeff(&worst);
    const Eigen::RowVector3d f = fit.record.points.features.row(worst);
    std::ostringstream row;  // vertex, largest, RMS, largest of all, the worst point by its three features
    row << std::setw(8) << j << std::fixed << std::setprecision(2) << std::setw(15) << 100 * loo.col(j).maxCoeff()
        << std::setw(15) << 100 * std::sqrt(loo.col(j).squaredNorm() / loo.rows()) << std::setw(11)
        << 100 * loo.col(j).maxCoeff() << std::defaultfloat << std::setprecision(4) << "   " << worst << " (" << f[0]
        << ", " << f[1] << ", " << f[2] << ", measured)\n";
    EXPECT_NE(report.find(row.str()), std::string::npos) << "no row '" << row.str() << "' in\n" << report;
  }
  // The settings recorded parse back to the same fit.
  const FitConfig again = parseFitConfig(nlohmann::json::parse(fit.record.settings.dump()), {"settings", ""});
  const SpatialRbfFitOutcome refit = fitSpatialRbfToDataset(smoothDataset(3), again, "synthetic.h5");
  EXPECT_EQ(refit.record.parameters.weights, fit.record.parameters.weights);
  EXPECT_EQ(refit.record.parameters.polynomial, fit.record.parameters.polynomial);
}

TEST(SpatialRbfFit, BadDataGivesOneMessageNamingTheDataset) {
  ForceDataset three = smoothDataset();
  three.wrench = three.wrench.leftCols(3).eval();
  three.wrench_names = {"F_x", "F_z", "tau_y"};
  three.wrench_units = {"N", "N", "N m"};
  expectAll(inputErrorMessage([&] { fitSpatialRbfToDataset(three, FitConfig{}, "data3d.h5"); }),
            {"data3d.h5", "'/wrench'", "N x 6", "N x 3"});

  ForceDataset planar_six = syntheticDataset(2, {-0.03, -0.01}, {-0.3, 0.3});
  planar_six.wrench = Eigen::MatrixXd::Ones(planar_six.wrench.rows(), 6);
  planar_six.wrench_names = {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};
  planar_six.wrench_units = {"N m", "N m", "N m", "N", "N", "N"};
  expectAll(inputErrorMessage([&] { fitRbfToDataset(planar_six, FitConfig{}, "planar.h5"); }),
            {"planar.h5", "'/wrench'", "N x 3", "N x 6"});

  ForceDataset names = smoothDataset();
  names.feature_names = {"phi", "beta", "theta"};
  expectAll(inputErrorMessage([&] { fitSpatialRbfToDataset(names, FitConfig{}, "names.h5"); }),
            {"names.h5", "'/features'", "phi, beta, gamma", "phi, beta, theta"});

  ForceDataset missing = smoothDataset();
  missing.vertex[3] = 0;  // point 1 has vertex 0 twice
  expectAll(inputErrorMessage([&] { fitSpatialRbfToDataset(missing, FitConfig{}, "dup.h5"); }),
            {"dup.h5", "duplicate sample", "gamma"});
}

TEST(SpatialRbfFit, KeysThatMakeNoSenseFor3dDataAreRefused) {
  const ConfigContext ctx{"fit.json", ""};
  using json = nlohmann::json;
  const ForceDataset data = smoothDataset();
  const auto refused = [&](const json& config) {
    const FitConfig c = parseFitConfig(config, ctx);
    return inputErrorMessage([&] { fitSpatialRbfToDataset(data, c, "data3d.h5"); });
  };
  expectAll(refused({{"geometry", {{"torque_centre", 0.1}}}}), {"fit.json.geometry.torque_centre", "foot point"});
  expectAll(refused({{"augmentation", {{"mirror", true}}}}), {"fit.json.augmentation.mirror", "data3d.h5"});
  expectAll(refused({{"augmentation", {{"mirror_vertices", "reversed"}}}}), {"fit.json.augmentation.mirror_vertices"});
  expectAll(refused({{"augmentation", {{"above_surface", {{"angles", {0.1}}}}}}}),
            {"fit.json.augmentation.above_surface.angles"});
  expectAll(refused({{"rbf", {{"scaling", {5, 1}}}}}), {"fit.json.rbf.scaling", "three numbers"});
  // And the other way round: three numbers on planar data.
  const FitConfig three = parseFitConfig({{"rbf", {{"scaling", {20, 1, 1}}}}}, ctx);
  expectAll(inputErrorMessage([&] { fitRbfToDataset(syntheticDataset(2, {-0.03, -0.01}, {-0.3, 0.3}), three, "planar.h5"); }),
            {"fit.json.rbf.scaling", "planar.h5", "[s_phi, s_beta]"});
  expectAll(inputErrorMessage([&] { parseFitConfig({{"rbf", {{"scaling", {20, 1, 1, 1}}}}}, ctx); }),
            {"fit.json.rbf.scaling", "three"});
  // Mirror false and the keys 3-D data takes are accepted.
  EXPECT_NO_THROW(fitSpatialRbfToDataset(
      data,
      parseFitConfig({{"augmentation", {{"mirror", false}, {"scale", 2.0}, {"above_surface", {{"heights", {0.01}}}}}},
                      {"rbf", {{"kernel", "cubic"}, {"scaling", {10, 1, 2}}, {"ridge", 1e-9}, {"polynomial_tail", true}}},
                      {"geometry", {{"cutoff", 0.0}, {"cutoff_width", 0.004}}}},
                     ctx),
      "data3d.h5"));
}

}  // namespace
}  // namespace nmdp::test
