// Fitting wrench spaces from force data (DESIGN.md §9), the library half (training/):
//  * acceptance: 3 × ../shared/granular/sand_samples with the published augmentation, a thin-plate
//    kernel and diag(5, 1) reproduce the published model within 1 % of the largest wrench at random
//    points of the valid range;
//  * the HDF5 force dataset round trip, and the sand_samples CSV importer;
//  * augmentation: mirrored copies negate F_x and τ_y, keep F_z; zero points above the surface;
//  * the closed-form leave-one-point-out error against brute-force refits (kernels, ridge, tail);
//  * bad data (NaN, wrong columns, a single point, duplicate points, a missing vertex) and bad
//    configurations give one InputError naming the file and the field;
//  * the model file written after a fit reads back with readRbfHdf5, with the report in /fit.
// Tests on ../shared data skip with a message when it is absent.
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>

#include "contact_models/rbf_function.hpp"
#include "io/hdf5_file.hpp"
#include "fit_fixtures.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "training/augmentation.hpp"
#include "training/fit_config.hpp"
#include "training/force_dataset.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp::test {
namespace {

const char* kSandSamples = "granular/sand_samples";
const char* kSandModel = "granular/robosimian_sand_rbf";

FitConfig publishedFitConfig() { return fitConfigFile("data/granular/sand_rbf_fit.json"); }

// Writes a dataset file field by field, to plant bad values the writer would refuse.
void writeRawDataset(const std::string& path, const Eigen::MatrixXd& features, const Eigen::VectorXi& vertex,
                     const Eigen::MatrixXd& wrench, const std::string& feature_names = "phi, beta") {
  h5::File f = h5::File::createAtomic(path);
  f.writeStringAttribute("/", "nmdp_dataset", "force_samples");
  f.writeDoubleAttribute("/", "format_version", 1);
  f.writeMatrix("/features", features);
  f.writeStringAttribute("/features", "names", feature_names);
  f.writeStringAttribute("/features", "units", features.cols() == 2 ? "m, rad" : "m, rad, m/s");
  f.writeIntegerVector("/vertex", vertex);
  f.writeMatrix("/wrench", wrench);
  f.writeStringAttribute("/wrench", "names", "F_x, F_z, tau_y");
  f.writeStringAttribute("/wrench", "units", "N, N, N m");
  f.commit();
}

// ==== acceptance ================================================================================

TEST(FitAcceptance, SandSamplesReproduceThePublishedModelWithinOnePercent) {
  NMDP_REQUIRE_SHARED(kSandModel);
  NMDP_REQUIRE_SHARED(kSandSamples);
  const ForceDataset data = importSandSamplesCsv(sharedPath(kSandSamples));
  const FitConfig config = publishedFitConfig();
  const RbfFitOutcome fit = fitRbfToDataset(data, config, "sand_samples");
  EXPECT_EQ(fit.record.points.pointCount(), 103) << "the published model has 103 centres";
  EXPECT_EQ(fit.record.points.vertexCount(), 26);
  EXPECT_DOUBLE_EQ(fit.geometry.torque_centre, 0.1572) << "cT of scalars.txt";

  const Eigen::MatrixX2d f = acceptancePoints();
  Eigen::MatrixXd W_pub, W_fit;
  publishedSandModel().evaluate(f, W_pub, nullptr, nullptr);
  RbfFunction(fit.record.fit.parameters).evaluate(f, W_fit, nullptr, nullptr);
  const std::vector<double> e = errorRelativeToPublished(f, W_fit, W_pub);
  const double worst = *std::max_element(e.begin(), e.end());
  std::cout << "[ fit vs published ] largest error " << 100 * worst << " % of the largest wrench at the point ("
            << f.rows() << " random points)\n";
  RecordProperty("max_relative_error_percent", std::to_string(100 * worst));
  EXPECT_LT(worst, 0.01);
}

TEST(FitAcceptance, PublishedModelConfirmsTheMirrorRule) {
  // The published weights at (φ, −β) give the sand samples at (φ, β) with F_x and τ_y negated,
  // vertex for vertex ("same"), which is what augment() does.
  NMDP_REQUIRE_SHARED(kSandModel);
  NMDP_REQUIRE_SHARED(kSandSamples);
  const PlanarPoints measured = groupPlanarSamples(importSandSamplesCsv(sharedPath(kSandSamples)), "sand");
  AugmentationSettings mirror;
  mirror.scale = 3;
  mirror.mirror = true;
  mirror.above_heights = std::vector<double>{};
  const PlanarPoints points = augment(measured, mirror);
  const std::string dir = sharedPath(kSandModel);
  const RbfFunction published(readPublishedRbf(dir + "/inputs.txt", dir + "/weights.txt"));
  Eigen::MatrixXd W;
  published.evaluate(points.features, W, nullptr, nullptr);
  int mirrored = 0;
  for (int i = 0; i < points.pointCount(); ++i) {
    if (points.origin[i] != PointOrigin::Mirrored) continue;
    ++mirrored;
    EXPECT_LT((W.row(i) - points.values.row(i)).cwiseAbs().maxCoeff(),
              1e-5 * points.values.row(i).cwiseAbs().maxCoeff() + 1e-6)
        << "at " << points.features.row(i);
  }
  EXPECT_EQ(mirrored, 14);
}

// ==== the dataset file ==========================================================================

TEST(ForceDatasetFile, RoundTripIsExact) {
  TempDir dir;
  const ForceDataset d = syntheticDataset(4, {-0.02, -0.01, 0.0}, {-0.5, 0.0, 0.5});
  const std::string path = dir.file("data.h5");
  writeForceDataset(path, d);
  const ForceDataset r = readForceDataset(path);
  EXPECT_EQ(r.features, d.features);
  EXPECT_EQ(r.vertex, d.vertex);
  EXPECT_EQ(r.wrench, d.wrench);
  EXPECT_EQ(r.feature_names, d.feature_names);
  EXPECT_EQ(r.feature_units, d.feature_units);
  EXPECT_EQ(r.wrench_names, d.wrench_names);
  EXPECT_EQ(r.wrench_units, d.wrench_units);
  EXPECT_EQ(r.source, d.source);
  ASSERT_TRUE(r.torque_centre.has_value());
  EXPECT_EQ(*r.torque_centre, 0.05);
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
}

TEST(ForceDatasetFile, BadFilesNameTheFileAndTheField) {
  TempDir dir;
  const ForceDataset d = syntheticDataset(3, {-0.02, -0.01}, {0.0, 0.5});
  const Eigen::Index N = d.features.rows();

  Eigen::MatrixXd nan_wrench = d.wrench;
  nan_wrench(4, 1) = std::numeric_limits<double>::quiet_NaN();
  const std::string nan = dir.file("nan.h5");
  writeRawDataset(nan, d.features, d.vertex, nan_wrench);
  expectAll(inputErrorMessage([&] { readForceDataset(nan); }), {nan, "'/wrench'", "non-finite", "row 4, column 1"});

  Eigen::MatrixXd inf_features = d.features;
  inf_features(2, 0) = std::numeric_limits<double>::infinity();
  const std::string inf = dir.file("inf.h5");
  writeRawDataset(inf, inf_features, d.vertex, d.wrench);
  expectAll(inputErrorMessage([&] { readForceDataset(inf); }), {inf, "'/features'", "non-finite", "row 2, column 0"});

  const std::string wide = dir.file("wide.h5");
  writeRawDataset(wide, d.features, d.vertex, Eigen::MatrixXd::Ones(N, 4));
  expectAll(inputErrorMessage([&] { readForceDataset(wide); }), {wide, "'/wrench'", "N x 3", std::to_string(N) + " x 4"});

  const std::string short_vertex = dir.file("short.h5");
  writeRawDataset(short_vertex, d.features, d.vertex.head(N - 1), d.wrench);
  expectAll(inputErrorMessage([&] { readForceDataset(short_vertex); }),
            {short_vertex, "'/vertex'", std::to_string(N - 1) + " entries", std::to_string(N) + " rows"});

  const std::string short_wrench = dir.file("short_wrench.h5");
  writeRawDataset(short_wrench, d.features, d.vertex, d.wrench.topRows(N - 2));
  expectAll(inputErrorMessage([&] { readForceDataset(short_wrench); }),
            {short_wrench, "'/wrench'", std::to_string(N - 2) + " x 3"});

  const std::string names = dir.file("names.h5");
  writeRawDataset(names, d.features, d.vertex, d.wrench, "phi");
  expectAll(inputErrorMessage([&] { readForceDataset(names); }),
            {names, "'names'", "'/features'", "1 entries", "2 columns"});

  Eigen::VectorXi negative = d.vertex;
  negative[3] = -1;
  const std::string neg = dir.file("negative.h5");
  writeRawDataset(neg, d.features, negative, d.wrench);
  expectAll(inputErrorMessage([&] { readForceDataset(neg); }), {neg, "'/vertex'", "-1", "row 3"});

  const std::string model = sourcePath("data/granular/handmade_sand_rbf.h5");
  expectAll(inputErrorMessage([&] { readForceDataset(model); }), {model, "not an nmdp force dataset", "nmdp_dataset"});

  // The writer validates too, and writes nothing.
  ForceDataset bad = d;
  bad.wrench(0, 2) = std::numeric_limits<double>::quiet_NaN();
  const std::string refused = dir.file("refused.h5");
  expectAll(inputErrorMessage([&] { writeForceDataset(refused, bad); }), {refused, "'/wrench'", "row 0, column 2"});
  EXPECT_FALSE(std::filesystem::exists(refused));
}

// ==== the CSV importer ==========================================================================

TEST(SandSamplesCsv, ImportsThePublishedSamples) {
  NMDP_REQUIRE_SHARED(kSandSamples);
  const ForceDataset d = importSandSamplesCsv(sharedPath(kSandSamples));
  ASSERT_EQ(d.features.rows(), 494);
  EXPECT_EQ(d.vertex.maxCoeff(), 25);
  EXPECT_EQ(d.feature_names, (std::vector<std::string>{"phi", "beta"}));
  EXPECT_EQ(d.wrench_names, (std::vector<std::string>{"F_x", "F_z", "tau_y"}));
  ASSERT_TRUE(d.torque_centre.has_value());
  EXPECT_EQ(*d.torque_centre, 0.1572);
  // The first data row of wrench_samples.csv: -0.01,0,0,-1.315661583,6.446356058,0.1116724277
  EXPECT_EQ(d.features.row(0), Eigen::RowVector2d(-0.01, 0.0));
  EXPECT_EQ(d.vertex[0], 0);
  EXPECT_EQ(d.wrench.row(0), Eigen::RowVector3d(-1.315661583, 6.446356058, 0.1116724277));
  const PlanarPoints points = groupPlanarSamples(d, "sand");
  EXPECT_EQ(points.pointCount(), 19);
  EXPECT_EQ(points.vertexCount(), 26);
}

// A sand_samples-layout folder with 2 points and 2 vertices; `edit` changes the files' text.
std::string writeCsvFolder(const TempDir& dir, const std::string& name, const std::string& features,
                           const std::string& samples, const std::string& scalars = "Nvel 2\nNtheta 2\ncT 0.1\n") {
  dir.write(name + "/features.csv", features);
  dir.write(name + "/wrench_samples.csv", samples);
  dir.write(name + "/scalars.txt", scalars);
  return dir.file(name);
}
const std::string kGoodFeatures = "depth,theta\n-0.01,0\n-0.02,0.3\n";
const std::string kGoodSamples =
    "depth,theta,vel_index,fx,fz,wy\n-0.01,0,0,1,2,3\n-0.01,0,1,4,5,6\n-0.02,0.3,0,7,8,9\n-0.02,0.3,1,10,11,12\n";

TEST(SandSamplesCsv, ImportsAndRoundTripsASmallFolder) {
  TempDir dir;
  const std::string folder = writeCsvFolder(dir, "good", kGoodFeatures, kGoodSamples);
  const ForceDataset d = importSandSamplesCsv(folder);
  ASSERT_EQ(d.features.rows(), 4);
  EXPECT_EQ(d.wrench.row(3), Eigen::RowVector3d(10, 11, 12));
  EXPECT_EQ(d.features.row(2), Eigen::RowVector2d(-0.02, 0.3));
  EXPECT_EQ(d.vertex, (Eigen::VectorXi(4) << 0, 1, 0, 1).finished());
  EXPECT_EQ(*d.torque_centre, 0.1);
  writeForceDataset(dir.file("good.h5"), d);
  EXPECT_EQ(readForceDataset(dir.file("good.h5")).wrench, d.wrench);
}

TEST(SandSamplesCsv, BadFilesNameTheFileLineAndColumn) {
  TempDir dir;
  {
    const std::string f = writeCsvFolder(dir, "columns", kGoodFeatures, "depth,theta,vel_index,fx,fz\n-0.01,0,0,1,2\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:1", "header", "depth, theta, vel_index, fx, fz, wy"});
  }
  {
    const std::string f =
        writeCsvFolder(dir, "short_row", kGoodFeatures, "depth,theta,vel_index,fx,fz,wy\n-0.01,0,0,1,2\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:2", "expected 6", "got 5"});
  }
  {
    const std::string f =
        writeCsvFolder(dir, "nan", kGoodFeatures, "depth,theta,vel_index,fx,fz,wy\n-0.01,0,0,1,nan,3\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:2", "column 'fz'", "non-finite", "'nan'"});
  }
  {
    const std::string f =
        writeCsvFolder(dir, "text", kGoodFeatures, "depth,theta,vel_index,fx,fz,wy\n-0.01,0,0,1,abc,3\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:2", "'abc' is not a number"});
  }
  {
    std::string samples = kGoodSamples;
    samples += "-0.02,0.3,1,10,11,12\n";
    const std::string f = writeCsvFolder(dir, "duplicate", kGoodFeatures, samples);
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:6", "duplicate sample", "vel_index 1", "line 5"});
  }
  {
    const std::string samples = "depth,theta,vel_index,fx,fz,wy\n-0.01,0,0,1,2,3\n-0.01,0,1,4,5,6\n-0.02,0.3,0,7,8,9\n";
    const std::string f = writeCsvFolder(dir, "missing", kGoodFeatures, samples);
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv", "no sample of vel_index 1", "features.csv:3"});
  }
  {
    std::string samples = kGoodSamples;
    samples += "-0.03,0,0,1,1,1\n";
    const std::string f = writeCsvFolder(dir, "unlisted", kGoodFeatures, samples);
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:6", "not listed", "features.csv"});
  }
  {
    const std::string f = writeCsvFolder(dir, "count", kGoodFeatures, kGoodSamples, "Nvel 2\nNtheta 3\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/features.csv", "2 feature points", "Ntheta 3"});
  }
  {
    const std::string f =
        writeCsvFolder(dir, "index", kGoodFeatures, "depth,theta,vel_index,fx,fz,wy\n-0.01,0,2,1,2,3\n");
    expectAll(inputErrorMessage([&] { importSandSamplesCsv(f); }),
              {f + "/wrench_samples.csv:2", "'vel_index'", "[0, 1]"});
  }
  expectAll(inputErrorMessage([&] { importSandSamplesCsv(dir.file("absent")); }), {dir.file("absent"), "not a folder"});
}

// ==== augmentation ==============================================================================

PlanarPoints twoPoints() {
  PlanarPoints p;
  p.features.resize(2, 2);
  p.features << -0.01, 0.0, -0.02, 0.4;
  p.values.resize(2, 9);                  // 3 vertices
  p.values << 1, 2, 3, 4, 5, 6, 7, 8, 9,  //
      10, 20, 30, 40, 50, 60, 70, 80, 90;
  p.origin.assign(2, PointOrigin::Measured);
  return p;
}

TEST(Augmentation, MirrorNegatesFxAndTauKeepsFz) {
  AugmentationSettings s;
  s.scale = 3;
  s.mirror = true;
  s.above_heights = std::vector<double>{};
  const PlanarPoints a = augment(twoPoints(), s);
  ASSERT_EQ(a.pointCount(), 3) << "the point at beta = 0 lies on the mirror plane and is not copied";
  EXPECT_EQ(a.values.row(0), 3 * twoPoints().values.row(0));
  EXPECT_EQ(a.features.row(2), Eigen::RowVector2d(-0.02, -0.4));
  EXPECT_EQ(a.origin[2], PointOrigin::Mirrored);
  Eigen::RowVectorXd expected(9);
  expected << -30, 60, -90, -120, 150, -180, -210, 240, -270;
  EXPECT_EQ(a.values.row(2), expected);

  s.mirror_vertices = MirrorVertices::Reversed;  // j → (3 − j) mod 3: 0 → 0, 1 → 2, 2 → 1
  const PlanarPoints r = augment(twoPoints(), s);
  expected << -30, 60, -90, -210, 240, -270, -120, 150, -180;
  EXPECT_EQ(r.values.row(2), expected);
}

TEST(Augmentation, ZeroWrenchPointsAboveTheSurface) {
  AugmentationSettings s;
  s.mirror = true;
  s.above_heights = {0.01, 0.05};
  const PlanarPoints a = augment(twoPoints(), s);
  // 2 measured, 1 mirrored, 2 heights × the 3 angles (0, 0.4, −0.4) in order of appearance.
  ASSERT_EQ(a.pointCount(), 9);
  const double expected[6][2] = {{0.01, 0.0}, {0.01, 0.4}, {0.01, -0.4}, {0.05, 0.0}, {0.05, 0.4}, {0.05, -0.4}};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(a.features.row(3 + i), Eigen::RowVector2d(expected[i][0], expected[i][1]));
    EXPECT_EQ(a.origin[3 + i], PointOrigin::AboveSurface);
    EXPECT_TRUE(a.values.row(3 + i).isZero(0));
  }
  // Explicit angles; a point that exists already is skipped (measured data wins).
  s.mirror = false;
  s.above_heights = {0.02};
  s.above_angles = {0.0, 1.0};
  PlanarPoints above = twoPoints();
  above.features(1, 0) = 0.02;
  above.features(1, 1) = 1.0;
  const PlanarPoints b = augment(above, s);
  ASSERT_EQ(b.pointCount(), 3);
  EXPECT_EQ(b.features.row(2), Eigen::RowVector2d(0.02, 0.0));
  EXPECT_EQ(b.values.row(1), above.values.row(1));
}

// ==== leave-one-point-out =======================================================================

struct LooCase {
  RbfKernel kernel;
  double ridge;
  bool tail;
};

void PrintTo(const LooCase& c, std::ostream* os) {
  *os << rbfKernelName(c.kernel) << ", ridge " << c.ridge << (c.tail ? ", linear tail" : "");
}

class RbfLoo : public ::testing::TestWithParam<LooCase> {};

TEST_P(RbfLoo, ClosedFormMatchesBruteForceRefits) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int P = 12, K = 2;
  PlanarPoints pts;
  pts.features.resize(P, 2);
  pts.values.resize(P, 3 * K);
  for (int i = 0; i < P; ++i) {
    pts.features.row(i) << 0.05 * u(rng), 0.8 * u(rng);
    for (int c = 0; c < 3 * K; ++c) pts.values(i, c) = 10 * u(rng);
  }
  pts.origin.assign(P, PointOrigin::Measured);
  RbfFitSettings s;
  s.spec.kernel = GetParam().kernel;
  s.spec.scaling = Eigen::Vector2d(10.0, 1.5);
  s.spec.epsilon = 0.7;
  s.ridge = GetParam().ridge;
  s.polynomial = GetParam().tail;
  const RbfFit fit = fitRbf(pts, s, "loo");

  for (int i = 0; i < P; ++i) {
    PlanarPoints rest;
    rest.features.resize(P - 1, 2);
    rest.values.resize(P - 1, 3 * K);
    for (int k = 0, n = 0; k < P; ++k)
      if (k != i) {
        rest.features.row(n) = pts.features.row(k);
        rest.values.row(n++) = pts.values.row(k);
      }
    rest.origin.assign(P - 1, PointOrigin::Measured);
    const RbfFunction refit(fitRbf(rest, s, "refit").parameters);
    Eigen::MatrixXd W;
    refit.evaluate(Eigen::MatrixX2d(pts.features.row(i)), W, nullptr, nullptr);
    const Eigen::RowVectorXd brute = pts.values.row(i) - W.row(0);
    EXPECT_LT((fit.loo_error.row(i) - brute).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + brute.cwiseAbs().maxCoeff()))
        << "point " << i << "\nclosed form " << fit.loo_error.row(i) << "\nbrute force " << brute;
    for (int j = 0; j < K; ++j)
      EXPECT_DOUBLE_EQ(fit.loo_relative(i, j), fit.loo_error.block(i, 3 * j, 1, 3).cwiseAbs().maxCoeff() /
                                                   pts.values.row(i).cwiseAbs().maxCoeff());
  }
  if (GetParam().ridge == 0.0) {  // interpolation: the fit reproduces the data
    Eigen::MatrixXd W;
    RbfFunction(fit.parameters).evaluate(pts.features, W, nullptr, nullptr);
    EXPECT_LT((W - pts.values).cwiseAbs().maxCoeff(), 1e-8);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Kernels, RbfLoo,
    ::testing::Values(LooCase{RbfKernel::ThinPlate, 0.0, false}, LooCase{RbfKernel::ThinPlate, 0.5, false},
                      LooCase{RbfKernel::ThinPlate, 0.0, true}, LooCase{RbfKernel::ThinPlate, 0.1, true},
                      LooCase{RbfKernel::Gaussian, 0.0, false}, LooCase{RbfKernel::Multiquadric, 0.0, true},
                      LooCase{RbfKernel::InverseMultiquadric, 0.01, false}, LooCase{RbfKernel::Cubic, 0.0, true},
                      LooCase{RbfKernel::Linear, 0.0, false}),
    [](const ::testing::TestParamInfo<LooCase>& info) {
      return std::string(rbfKernelName(info.param.kernel)) + (info.param.ridge > 0 ? "_ridge" : "") +
             (info.param.tail ? "_tail" : "");
    });

// ==== bad data ==================================================================================

TEST(FitBadData, SinglePoint) {
  const ForceDataset d = syntheticDataset(3, {-0.02}, {0.3});
  const std::string m = inputErrorMessage([&] { fitRbfToDataset(d, noAugmentation(), "one.h5"); });
  expectAll(m, {"one.h5", "1 feature point", "(phi -0.02, beta 0.3)", "at least 2"});
}

TEST(FitBadData, DuplicatePointsMakeTheSystemSingular) {
  ForceDataset d = syntheticDataset(2, {-0.03, -0.02, -0.01}, {0.0, 0.5});
  // The last point moved within rounding of the first: distinct rows, the same kernel columns.
  const Eigen::Index last = d.features.rows() - 2;
  for (Eigen::Index r = last; r < last + 2; ++r) d.features.row(r) << -0.03 * (1 + 1e-15), 0.0;
  d.wrench.row(last) *= 1.5;
  const std::string m = inputErrorMessage([&] { fitRbfToDataset(d, noAugmentation(), "dup.h5"); });
  expectAll(m, {"dup.h5", "singular", "reciprocal condition number", "closest points are 0 (phi -0.03, beta 0)",
                "remove duplicate", "rbf.ridge > 0"});
  // A ridge makes it a (well-posed) regression.
  FitConfig ridge = noAugmentation();
  ridge.rbf.ridge = 1e-3;
  const RbfFitOutcome fit = fitRbfToDataset(d, ridge, "dup.h5");
  EXPECT_TRUE(fit.record.fit.parameters.weights.allFinite());
  EXPECT_GT(fit.record.fit.rcond, kRbfMinRcond);
}

TEST(FitBadData, ExactDuplicateSamplesAndMissingVertices) {
  ForceDataset d = syntheticDataset(2, {-0.02, -0.01}, {0.0});
  d.features.row(3) = d.features.row(1);  // row 3 becomes a second vertex 1 at the first point
  const std::string m = inputErrorMessage([&] { groupPlanarSamples(d, "dup.h5"); });
  expectAll(m, {"dup.h5", "duplicate sample", "rows 1 and 3", "vertex 1", "(phi -0.02"});

  ForceDataset gap = syntheticDataset(3, {-0.02, -0.01}, {0.0});
  gap.vertex[4] = 0;  // the second point: vertices 0, 0, 2
  const std::string g = inputErrorMessage([&] { groupPlanarSamples(gap, "gap.h5"); });
  expectAll(g, {"gap.h5", "duplicate sample", "vertex 0"});
  // The second point without its vertex 2.
  ForceDataset missing = syntheticDataset(3, {-0.02, -0.01}, {0.0});
  missing.features.conservativeResize(5, 2);
  missing.vertex.conservativeResize(5);
  missing.wrench.conservativeResize(5, 3);
  const std::string v = inputErrorMessage([&] { groupPlanarSamples(missing, "missing.h5"); });
  expectAll(v, {"missing.h5", "(phi -0.01, beta 0)", "no sample of vertex 2", "all 3 vertices"});

  ForceDataset huge = syntheticDataset(2, {-0.02, -0.01}, {0.0});
  huge.vertex[2] = 1000000000;  // would size the grouping by 1e9 vertices
  expectAll(inputErrorMessage([&] { groupPlanarSamples(huge, "huge.h5"); }),
            {"huge.h5", "'/vertex'", "index 1000000000 at row 2", "at most 256 vertices"});
}

TEST(FitBadData, WrongColumns) {
  TempDir dir;
  const ForceDataset good = syntheticDataset(2, {-0.02, -0.01}, {0.0, 0.3});
  Eigen::MatrixXd three(good.features.rows(), 3);
  three << good.features, Eigen::VectorXd::Zero(good.features.rows());
  const std::string path = dir.file("three.h5");
  writeRawDataset(path, three, good.vertex, good.wrench, "phi, beta, speed");
  const ForceDataset d = readForceDataset(path);  // a valid dataset, not a planar one
  expectAll(inputErrorMessage([&] { fitRbfToDataset(d, FitConfig{}, path); }),
            {path, "'/features'", "\"phi, beta\"", "\"phi, beta, speed\""});

  ForceDataset renamed = good;
  renamed.feature_names = {"depth", "theta"};
  expectAll(inputErrorMessage([&] { fitRbfToDataset(renamed, FitConfig{}, "renamed.h5"); }),
            {"renamed.h5", "\"depth, theta\""});

  ForceDataset no_torque = good;
  no_torque.torque_centre.reset();
  expectAll(inputErrorMessage([&] { fitRbfToDataset(no_torque, FitConfig{}, "nt.h5"); }),
            {"nt.h5", "torque_centre", "geometry.torque_centre"});
}

// ==== configuration =============================================================================

TEST(FitConfigFile, UnknownKeysAndBadValuesNameTheKey) {
  const ConfigContext ctx{"fit.json", ""};
  using json = nlohmann::json;
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"rbf", {{"kernal", "thin_plate"}}}}, ctx);
            }),
            {"fit.json.rbf.kernal", "unknown key", "did you mean 'kernel'"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"augmentaton", json::object()}}, ctx);
            }),
            {"fit.json.augmentaton", "did you mean 'augmentation'"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"augmentation", {{"above_surface", {{"height", {0.1}}}}}}}, ctx);
            }),
            {"fit.json.augmentation.above_surface.height", "did you mean 'heights'"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"rbf", {{"kernel", "spline"}}}}, ctx);
            }),
            {"fit.json.rbf.kernel", "\"spline\"", "thin_plate"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"rbf", {{"scaling", {5}}}}}, ctx);
            }),
            {"fit.json.rbf.scaling", "two positive numbers"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"rbf", {{"ridge", -1}}}}, ctx);
            }),
            {"fit.json.rbf.ridge", "out of range"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"augmentation", {{"scale", 0}}}}, ctx);
            }),
            {"fit.json.augmentation.scale", "non-zero"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"augmentation", {{"above_surface", {{"heights", {0.1, -0.1}}}}}}}, ctx);
            }),
            {"fit.json.augmentation.above_surface.heights", "> 0"});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"augmentation", {{"mirror_vertices", "flipped"}}}}, ctx);
            }),
            {"fit.json.augmentation.mirror_vertices", "\"same\" or \"reversed\""});
  expectAll(inputErrorMessage([&] {
              parseFitConfig(json{{"geometry", {{"cutoff_width", 0}}}}, ctx);
            }),
            {"fit.json.geometry.cutoff_width", "> 0"});
}

TEST(FitConfigFile, SettingsJsonParsesBackToTheSameSettings) {
  const FitConfig c = publishedFitConfig();
  EXPECT_EQ(c.augmentation.scale, 3.0);
  EXPECT_EQ(c.augmentation.mirror, std::optional<bool>(true));
  ASSERT_TRUE(c.augmentation.above_heights.has_value());
  EXPECT_EQ(c.augmentation.above_heights->size(), 10u);
  EXPECT_EQ(c.rbf.spec.scaling, Eigen::Vector2d(5, 1));
  const nlohmann::ordered_json j = fitConfigJson(c, 0.1572);
  const FitConfig back = parseFitConfig(nlohmann::json::parse(j.dump()), {"settings", ""});
  EXPECT_EQ(fitConfigJson(back, 0.1572).dump(), j.dump());
  ASSERT_TRUE(back.torque_centre.has_value());
  EXPECT_EQ(*back.torque_centre, 0.1572);
}

// ==== the model file ============================================================================

TEST(FitModelFile, ReadsBackAsAnRbfModelWithTheReport) {
  TempDir dir;
  const ForceDataset d = syntheticDataset(3, {-0.03, -0.02, -0.01, 0.0}, {-0.4, 0.0, 0.4});
  FitConfig c;
  c.augmentation.above_heights = {0.02};
  c.rbf.polynomial = true;
  c.cutoff = 0.01;
  c.cutoff_width = 0.005;
  const RbfFitOutcome fit = fitRbfToDataset(d, c, "synthetic.h5");
  const std::string path = dir.file("model.h5");
  saveRbfFit(path, fit.record, fit.geometry);
  const RbfModelFile m = readRbfHdf5(path);
  EXPECT_EQ(m.parameters.centres, fit.record.fit.parameters.centres);
  EXPECT_EQ(m.parameters.weights, fit.record.fit.parameters.weights);
  EXPECT_EQ(m.parameters.polynomial, fit.record.fit.parameters.polynomial);
  EXPECT_EQ(m.geometry.torque_centre, 0.05);
  EXPECT_EQ(m.geometry.cutoff, 0.01);
  EXPECT_EQ(m.geometry.cutoff_width, 0.005);

  const h5::File f = h5::File::openRead(path);
  const std::string report = f.readStringAttribute("/fit", "report");
  EXPECT_EQ(report, formatRbfFitReport(fit.record));
  expectAll(report,
            {"synthetic.h5", "leave-one-point-out", "12 measured", "3 zero-wrench", "\"polynomial_tail\":true"});
  EXPECT_EQ(f.readStringAttribute("/fit", "settings"), fit.record.settings.dump());
  EXPECT_EQ(f.readMatrix("/fit/loo_relative"), fit.record.fit.loo_relative);
  EXPECT_EQ(f.readMatrix("/fit/origin").col(0).cast<int>().sum(), 3 * 2);  // three points of origin 2
}

}  // namespace
}  // namespace nmdp::test
