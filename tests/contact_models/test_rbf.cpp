// The RBF granular contact model (DESIGN.md §7.2, §7.4, §10):
//  * the published sand model (../shared/granular/robosimian_sand_rbf) reproduces 3 × the sand
//    samples at the 15 measured points below the surface (and zero at the surface);
//  * PlanarWrenchModel places the planar wrenches in the world, is exactly zero above the cut-off
//    and continuous across the cut-off band;
//  * dW/df of every kernel and the full dV/dξ (tilted legs, tilted terrain, radius, fixed lateral)
//    against central finite differences;
//  * HDF5 save → load is bit-identical; bad files and bad JSON give an InputError naming the file;
//  * evaluation allocates nothing once warmed up (bench/bench_contact_models.cpp times it).
// Tests on ../shared data skip with a message when it is absent; the others use synthetic models.
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "contact_models/finite_difference_derivative.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "contact_models/rbf_function.hpp"
#include "contact_models/rbf_model.hpp"
#include "io/hdf5_file.hpp"
#include "common/input_error.hpp"
#include "terrain/plane.hpp"
#include "contact_derivative_check.hpp"
#include "test_support.hpp"
#include "test_terrains.hpp"

// Allocation counting: on glibc the malloc family is interposed (operator new calls malloc).
#define NMDP_COUNT_MALLOC
#include "test_allocation_counter.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;

const char* kSandModel = "granular/robosimian_sand_rbf";
const char* kSandSamples = "granular/sand_samples";

// Rows of a CSV file with a header line, as numbers.
std::vector<std::vector<double>> readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

std::shared_ptr<const RbfFunction> loadSandFunction() {
  const std::string dir = sharedPath(kSandModel);
  return std::make_shared<const RbfFunction>(readPublishedRbf(dir + "/inputs.txt", dir + "/weights.txt"));
}

std::unique_ptr<ContactModel> loadSandModel() {
  ConfigContext ctx{"test: contacts.model", sharedPath("granular")};
  return makeRbfModel({{"type", "rbf"}, {"file", "robosimian_sand_rbf"}}, ctx);
}

// A random RBF with N centres in the feature range of the sand data and K vertices.
RbfParameters syntheticRbf(RbfKernel kernel, bool polynomial, std::mt19937& rng, int N = 12, int K = 4) {
  std::uniform_real_distribution<double> depth(-0.08, 0.12), angle(-1.0, 1.0), weight(-100.0, 100.0);
  RbfParameters p;
  p.spec.kernel = kernel;
  p.spec.scaling = Eigen::Vector2d(5.0, 1.0);
  p.spec.epsilon = 2.0;
  p.centres.resize(N, 2);
  for (int i = 0; i < N; ++i) p.centres.row(i) << depth(rng), angle(rng);
  p.weights.resize(N, 3 * K);
  for (int i = 0; i < N; ++i)
    for (int c = 0; c < 3 * K; ++c) p.weights(i, c) = weight(rng);
  if (polynomial) {
    p.polynomial.resize(3, 3 * K);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3 * K; ++c) p.polynomial(r, c) = weight(rng);
  }
  return p;
}

Eigen::RowVectorXd evalRow(const FeatureWrenchFunction& f, double phi, double beta) {
  Eigen::MatrixX2d x(1, 2);
  x << phi, beta;
  Eigen::MatrixXd W;
  f.evaluate(x, W, nullptr, nullptr);
  return W.row(0);
}

// Expected world vertex matrix of one contact from the planar wrenches (DESIGN.md §7.2 geometry).
Mat6X placeInWorld(const Eigen::RowVectorXd& w, double sigma, const Vec3& x, const Vec3& y, const Vec3& n,
                   const Vec3& arm) {
  const int K = static_cast<int>(w.size() / 3);
  Mat6X V(6, K);
  for (int j = 0; j < K; ++j) {
    const Vec3 F = sigma * (w[3 * j] * x + w[3 * j + 1] * n);
    V.col(j).head<3>() = sigma * w[3 * j + 2] * y + arm.cross(F);
    V.col(j).tail<3>() = F;
  }
  return V;
}

Mat6X evaluateOne(const ContactModel& model, const ContactFrame& frame, const Terrain& terrain) {
  std::vector<ContactWrenches> out(1);
  out[0].resize(model.vertexCount());
  model.evaluate({frame}, terrain, out, false);
  return out[0].V;
}

template <class F>
void expectInputError(F&& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "expected an InputError mentioning '" << needles.front() << "'";
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& needle : needles)
      EXPECT_NE(message.find(needle), std::string::npos) << "message '" << message << "' lacks '" << needle << "'";
  }
}

// ===== (a) the published model reproduces the sand samples ====================================

TEST(RbfPublished, ReproducesThreeTimesTheSandSamples) {
  NMDP_REQUIRE_SHARED(kSandModel);
  NMDP_REQUIRE_SHARED(kSandSamples);
  const auto f = loadSandFunction();
  ASSERT_EQ(f->centreCount(), 103);
  ASSERT_EQ(f->vertexCount(), 26);

  const auto features = readCsv(sharedPath(std::string(kSandSamples) + "/features.csv"));
  const auto samples = readCsv(sharedPath(std::string(kSandSamples) + "/wrench_samples.csv"));
  ASSERT_EQ(features.size(), 19u);
  ASSERT_EQ(samples.size(), 19u * 26u);
  double largest_sample = 0.0;
  for (const auto& s : samples)
    for (int c = 3; c < 6; ++c) largest_sample = std::max(largest_sample, std::abs(s[c]));

  int below = 0;
  double worst = 0.0;
  for (const auto& feature : features) {
    const double depth = feature[0], theta = feature[1];
    Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(78);
    int found = 0;
    for (const auto& s : samples) {
      if (s[0] != depth || s[1] != theta) continue;
      const int v = static_cast<int>(s[2]);
      for (int c = 0; c < 3; ++c) expected[3 * v + c] = 3.0 * s[3 + c];
      ++found;
    }
    ASSERT_EQ(found, 26) << "depth " << depth << ", theta " << theta;
    const Eigen::RowVectorXd W = evalRow(*f, depth, theta);
    if (depth < 0.0) {
      ++below;
      const double rel = (W - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff();
      worst = std::max(worst, rel);
      EXPECT_LT(rel, 1e-6) << "depth " << depth << ", theta " << theta;
    } else {
      // At the surface the published model was fitted to zero wrenches.
      EXPECT_LT(W.cwiseAbs().maxCoeff(), 1e-6 * 3.0 * largest_sample) << "depth " << depth << ", theta " << theta;
    }
  }
  EXPECT_EQ(below, 15);
  // How much the thin-plate sum cancels (it bounds the rounding error of any evaluation order).
  double cancellation = 0.0;
  {
    const RbfParameters& p = f->parameters();
    for (const auto& feature : features) {
      if (feature[0] >= 0.0) continue;
      Eigen::VectorXd kappa(p.centres.rows());
      for (int i = 0; i < p.centres.rows(); ++i) {
        const Eigen::Vector2d d =
            p.spec.scaling.cwiseProduct(Eigen::Vector2d(feature[0], feature[1]) - p.centres.row(i).transpose());
        double g;
        rbfKernel(p.spec.kernel, p.spec.epsilon, d.squaredNorm(), &kappa[i], &g);
      }
      const Eigen::RowVectorXd terms = kappa.cwiseAbs().transpose() * p.weights.cwiseAbs();
      cancellation =
          std::max(cancellation, terms.maxCoeff() / evalRow(*f, feature[0], feature[1]).cwiseAbs().maxCoeff());
    }
  }
  std::cout << "[ info ] published RBF vs 3 x sand samples at the 15 points below the surface: max relative error "
            << worst << " (sum of |terms| / |result| up to " << cancellation << ")\n";
}

TEST(RbfPublished, FactoryLoadsFolderAndCentresFile) {
  NMDP_REQUIRE_SHARED(kSandModel);
  const auto model = loadSandModel();
  EXPECT_EQ(model->vertexCount(), 26);
  EXPECT_EQ(model->derivative(), DerivativeSupport::Analytic);
  EXPECT_NE(model->describe().find("rbf"), std::string::npos);
  EXPECT_NE(model->describe().find("103 centres"), std::string::npos);
  const auto& pw = dynamic_cast<const PlanarWrenchModel&>(*model);
  EXPECT_DOUBLE_EQ(pw.geometry().torque_centre, 0.1572);
  EXPECT_DOUBLE_EQ(pw.geometry().cutoff, 0.1);

  // The centres file itself (weights.txt next to it), relative to the context's folder.
  ConfigContext ctx{"test", sharedPath(kSandModel)};
  const auto by_file = makeRbfModel({{"file", "inputs.txt"}, {"cutoff_width", 0.01}}, ctx);
  const auto& pw2 = dynamic_cast<const PlanarWrenchModel&>(*by_file);
  EXPECT_DOUBLE_EQ(pw2.geometry().cutoff_width, 0.01);
  EXPECT_EQ(evalRow(pw.function(), -0.04, 0.2), evalRow(pw2.function(), -0.04, 0.2));
}

// ===== (b) placement in the world and the cut-off ==============================================

void checkPlacement(const ContactModel& model, const FeatureWrenchFunction& f, double L) {
  const PlaneTerrain flat;
  for (double beta : {0.0, 0.3, -0.6}) {
    for (double phi : {-0.07, -0.05, -0.031, -0.01, 0.0, 0.02, 0.05, 0.079}) {
      ContactFrame frame;
      frame.position = Vec3(0.3, -0.2, phi);
      frame.radius = 0.0;
      frame.leg_axis = Vec3(std::sin(beta), 0.0, std::cos(beta));  // leaning toward +x for β > 0
      frame.lateral = Vec3::UnitY();
      const Mat6X V = evaluateOne(model, frame, flat);
      const Vec3 arm = L * frame.leg_axis;  // Q − c with Q = c + L a
      const Mat6X expected = placeInWorld(evalRow(f, phi, beta), 1.0, Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), arm);
      EXPECT_LE(relativeError(V, expected), 1e-13) << "phi " << phi << ", beta " << beta;
    }
  }
}

TEST(RbfPublished, PlanarWrenchModelPlacesWrenchesInTheWorld) {
  NMDP_REQUIRE_SHARED(kSandModel);
  const auto model = loadSandModel();
  const auto& pw = dynamic_cast<const PlanarWrenchModel&>(*model);
  checkPlacement(*model, pw.function(), 0.1572);
}

TEST(RbfSynthetic, PlanarWrenchModelPlacesWrenchesInTheWorld) {
  std::mt19937 rng(7);
  auto f = std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::ThinPlate, true, rng));
  PlanarWrenchModel model(f, publishedRbfGeometry(), "rbf");
  checkPlacement(model, *f, 0.1572);
}

void checkCutoff(const ContactModel& model) {
  const PlaneTerrain flat;
  ContactFrame frame;
  frame.leg_axis = Vec3(0.2, 0.1, 1.0).normalized();
  // Exactly zero at and above the cut-off.
  for (double phi : {0.1, 0.1 + 1e-15, 0.100001, 0.12, 0.5, 0.99, 1.0, 1.5, 10.0}) {
    frame.position = Vec3(0.0, 0.0, phi);
    const Mat6X V = evaluateOne(model, frame, flat);
    EXPECT_TRUE((V.array() == 0.0).all()) << "phi " << phi << ": max |V| " << V.cwiseAbs().maxCoeff();
  }
  // Continuous across the band [0.08, 0.1]: the largest jump between neighbouring samples shrinks
  // in proportion to the sample step.
  const auto maxJump = [&](double step) {
    double jump = 0.0, largest = 0.0;
    frame.position = Vec3(0.0, 0.0, 0.06);
    Mat6X previous = evaluateOne(model, frame, flat);
    for (double phi = 0.06 + step; phi <= 0.11; phi += step) {
      frame.position.z() = phi;
      const Mat6X V = evaluateOne(model, frame, flat);
      jump = std::max(jump, (V - previous).cwiseAbs().maxCoeff());
      largest = std::max(largest, V.cwiseAbs().maxCoeff());
      previous = V;
    }
    return std::make_pair(jump, largest);
  };
  const auto [coarse, largest] = maxJump(1e-4);
  const auto [fine, unused] = maxJump(1e-5);
  (void)unused;
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(coarse, 0.05 * largest) << "coarse jump " << coarse;
  EXPECT_LT(fine, 0.15 * coarse) << "jumps do not shrink with the step: " << coarse << " -> " << fine;
}

TEST(RbfPublished, ZeroAboveTheCutoffAndContinuousAcrossIt) {
  NMDP_REQUIRE_SHARED(kSandModel);
  checkCutoff(*loadSandModel());
}

TEST(RbfSynthetic, ZeroAboveTheCutoffAndContinuousAcrossIt) {
  std::mt19937 rng(8);
  // The polynomial tail and the multiquadric grow away from the data: the cut-off still zeroes them.
  PlanarWrenchModel model(std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::Multiquadric, true, rng)),
                          publishedRbfGeometry(), "rbf");
  checkCutoff(model);
}

// ===== (c) dW/df against central finite differences ============================================

// Checks dW/dφ and dW/dβ at the rows of `points` (evaluated as one batch) against central
// differences; returns the largest relative error (relative to the largest derivative entry).
double featureDerivativeError(const FeatureWrenchFunction& f, const Eigen::MatrixX2d& points, double h) {
  Eigen::MatrixXd W, dphi, dbeta;
  f.evaluate(points, W, &dphi, &dbeta);
  EXPECT_TRUE(W.allFinite() && dphi.allFinite() && dbeta.allFinite());
  // Without derivatives, and one point at a time, the values agree to rounding (the summation
  // order of the matrix product depends on the batch shape).
  const double scale = std::max(W.cwiseAbs().maxCoeff(), 1e-9);
  Eigen::MatrixXd W_plain;
  f.evaluate(points, W_plain, nullptr, nullptr);
  EXPECT_LE((W_plain - W).cwiseAbs().maxCoeff() / scale, 1e-10);
  double worst = 0.0;
  const Eigen::MatrixXd fd_phi = centralFeatureDerivative(f, points, 0, h);
  const Eigen::MatrixXd fd_beta = centralFeatureDerivative(f, points, 1, h);
  for (int b = 0; b < points.rows(); ++b) {
    EXPECT_LE((evalRow(f, points(b, 0), points(b, 1)) - W.row(b)).cwiseAbs().maxCoeff() / scale, 1e-10);
    Eigen::MatrixXd analytic(2, W.cols()), numeric(2, W.cols());
    analytic << dphi.row(b), dbeta.row(b);
    numeric << fd_phi.row(b), fd_beta.row(b);
    worst = std::max(worst, relativeError(analytic, numeric, 1e-9));
  }
  return worst;
}

TEST(RbfPublished, FeatureDerivativesMatchFiniteDifferences) {
  NMDP_REQUIRE_SHARED(kSandModel);
  const auto f = loadSandFunction();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> depth(-0.07, 0.1), angle(-0.9, 0.9);
  Eigen::MatrixX2d random(50, 2);
  for (int b = 0; b < random.rows(); ++b) random.row(b) << depth(rng), angle(rng);
  const double random_error = featureDerivativeError(*f, random, 3e-6);
  EXPECT_LT(random_error, 1e-6);
  // Exactly at the centres in the data range (thin-plate at ρ = 0: κ = 0, gradient 0, no NaN).
  const Eigen::MatrixX2d centres = f->parameters().centres.topRows(40);
  const double centre_error = featureDerivativeError(*f, centres, 3e-6);
  EXPECT_LT(centre_error, 1e-6);
  std::cout << "[ info ] published RBF dW/df vs central differences: random points " << random_error << ", at centres "
            << centre_error << "\n";
}

class RbfKernels : public ::testing::TestWithParam<RbfKernel> {};

TEST_P(RbfKernels, FeatureDerivativesMatchFiniteDifferences) {
  for (bool polynomial : {false, true}) {
    std::mt19937 rng(100 + static_cast<int>(GetParam()) + (polynomial ? 50 : 0));
    const RbfFunction f(syntheticRbf(GetParam(), polynomial, rng));
    std::uniform_real_distribution<double> depth(-0.07, 0.1), angle(-0.9, 0.9);
    Eigen::MatrixX2d points(30, 2);
    for (int b = 0; b < points.rows(); ++b) points.row(b) << depth(rng), angle(rng);
    EXPECT_LT(featureDerivativeError(f, points, 1e-6), 1e-6)
        << rbfKernelName(GetParam()) << " polynomial " << polynomial;
    // At the centres: smooth kernels match; thin-plate and cubic have a zero gradient contribution
    // from the centre itself, and so has the linear kernel by convention (its zero subgradient),
    // which the symmetric central difference also gives.
    EXPECT_LT(featureDerivativeError(f, f.parameters().centres, 1e-6), 1e-6)
        << rbfKernelName(GetParam()) << " polynomial " << polynomial << " at the centres";
  }
}

TEST(RbfKernel, ValuesAndGradientFactorAtTheCentre) {
  for (RbfKernel k : {RbfKernel::ThinPlate, RbfKernel::Gaussian, RbfKernel::Multiquadric,
                      RbfKernel::InverseMultiquadric, RbfKernel::Cubic, RbfKernel::Linear}) {
    double kappa = -1, g = -1;
    rbfKernel(k, 2.0, 0.0, &kappa, &g);
    EXPECT_TRUE(std::isfinite(kappa) && std::isfinite(g)) << rbfKernelName(k);
    RbfKernel parsed;
    ASSERT_TRUE(parseRbfKernel(rbfKernelName(k), &parsed));
    EXPECT_EQ(parsed, k);
  }
  double kappa, g;
  rbfKernel(RbfKernel::ThinPlate, 1.0, 0.0, &kappa, &g);
  EXPECT_EQ(kappa, 0.0);
  EXPECT_EQ(g, 0.0);
  rbfKernel(RbfKernel::ThinPlate, 1.0, 4.0, &kappa, &g);  // ρ = 2
  EXPECT_NEAR(kappa, 4.0 * std::log(2.0), 1e-15);
  EXPECT_NEAR(g, 2.0 * std::log(2.0) + 1.0, 1e-15);
  rbfKernel(RbfKernel::Gaussian, 2.0, 0.25, &kappa, &g);  // ερ = 1
  EXPECT_NEAR(kappa, std::exp(-1.0), 1e-15);
  rbfKernel(RbfKernel::Linear, 1.0, 0.0, &kappa, &g);
  EXPECT_EQ(kappa, 0.0);
  EXPECT_EQ(g, 0.0);  // the zero subgradient
  rbfKernel(RbfKernel::Multiquadric, 2.0, 0.25, &kappa, &g);
  EXPECT_NEAR(kappa, std::sqrt(2.0), 1e-15);
  rbfKernel(RbfKernel::InverseMultiquadric, 2.0, 0.25, &kappa, &g);
  EXPECT_NEAR(kappa, 1.0 / std::sqrt(2.0), 1e-15);
  rbfKernel(RbfKernel::Cubic, 1.0, 4.0, &kappa, &g);
  EXPECT_NEAR(kappa, 8.0, 1e-14);
  rbfKernel(RbfKernel::Linear, 1.0, 4.0, &kappa, &g);
  EXPECT_NEAR(kappa, 2.0, 1e-15);
  // g = κ'(ρ)/ρ against a central difference in ρ.
  for (RbfKernel k : {RbfKernel::ThinPlate, RbfKernel::Gaussian, RbfKernel::Multiquadric,
                      RbfKernel::InverseMultiquadric, RbfKernel::Cubic, RbfKernel::Linear}) {
    for (double rho : {0.05, 0.7, 1.0, 2.3}) {
      const double h = 1e-6;
      double kp, km, unused_g;
      rbfKernel(k, 1.3, (rho + h) * (rho + h), &kp, &unused_g);
      rbfKernel(k, 1.3, (rho - h) * (rho - h), &km, &unused_g);
      rbfKernel(k, 1.3, rho * rho, &kappa, &g);
      EXPECT_NEAR(g * rho, (kp - km) / (2 * h), 1e-7 * std::max(1.0, std::abs(g * rho)))
          << rbfKernelName(k) << " rho " << rho;
    }
  }
  RbfKernel unused;
  EXPECT_FALSE(parseRbfKernel("thinplate", &unused));
}

// The batched, vectorized evaluation equals the plain sum Σ_i W_i κ(‖S(f − c_i)‖) + tail.
TEST_P(RbfKernels, BatchEvaluationEqualsTheDefiningSum) {
  std::mt19937 rng(200 + static_cast<int>(GetParam()));
  const RbfFunction f(syntheticRbf(GetParam(), true, rng, 15, 3));
  const RbfParameters& p = f.parameters();
  std::uniform_real_distribution<double> depth(-0.07, 0.1), angle(-0.9, 0.9);
  Eigen::MatrixX2d points(7, 2);
  for (int b = 0; b < points.rows(); ++b) points.row(b) << depth(rng), angle(rng);
  points.row(6) = p.centres.row(4);  // exactly at a centre
  Eigen::MatrixXd W;
  f.evaluate(points, W, nullptr, nullptr);
  for (int b = 0; b < points.rows(); ++b) {
    Eigen::RowVectorXd expected =
        p.polynomial.row(0) + points(b, 0) * p.polynomial.row(1) + points(b, 1) * p.polynomial.row(2);
    for (int i = 0; i < p.centres.rows(); ++i) {
      const Eigen::Vector2d d = p.spec.scaling.cwiseProduct(points.row(b).transpose() - p.centres.row(i).transpose());
      double kappa, g;
      rbfKernel(p.spec.kernel, p.spec.epsilon, d.squaredNorm(), &kappa, &g);
      expected += kappa * p.weights.row(i);
    }
    EXPECT_LE(relativeError(W.row(b), expected), 1e-12) << rbfKernelName(GetParam()) << " point " << b;
  }
}

INSTANTIATE_TEST_SUITE_P(All, RbfKernels,
                         ::testing::Values(RbfKernel::ThinPlate, RbfKernel::Gaussian, RbfKernel::Multiquadric,
                                           RbfKernel::InverseMultiquadric, RbfKernel::Cubic, RbfKernel::Linear),
                         [](const ::testing::TestParamInfo<RbfKernel>& info) {
                           return std::string(rbfKernelName(info.param));
                         });

// ===== (d) the full dV/dξ against central finite differences ====================================

// Evaluates all frames in one batch with derivatives and compares each dV/dξ_i with central
// differences of the batch evaluation, relative to the contact's largest derivative entry. Returns the
// worst relative error.
double frameDerivativeError(const ContactModel& model, const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            double eps) {
  VertexDerivativeCheck check;
  check.rotation_step = check.translation_step = eps;
  check.tolerance = 1e-6;
  check.scale_floor = 1e-9;
  const VertexDerivativeResult r = checkVertexDerivative(model, frames, terrain, check);
  for (size_t c = 0; c < frames.size(); ++c) {
    // V without derivatives equals V with them.
    std::vector<ContactWrenches> plain(1);
    plain[0].resize(model.vertexCount());
    model.evaluate({frames[c]}, terrain, plain, false);
    EXPECT_LE(relativeError(plain[0].V, r.analytic[c].V), 1e-9);
  }
  return r.worst;
}

struct FrameCase {
  std::string name;
  Vec3 normal;
  double offset;
  double radius;
  bool lateral_rotates;
};

std::vector<ContactFrame> framesFor(const FrameCase& fc, const PlaneTerrain& terrain) {
  // Four contacts: depths in the data (−0.05, −0.02), in the cut-off band (0.09) and just below it;
  // legs leaning in x and y; a lateral axis not orthogonal to the normal.
  const std::vector<double> depths = {-0.05, -0.02, 0.09, 0.075};
  const std::vector<Vec3> legs = {Vec3(0.3, -0.25, 1.0), Vec3(-0.4, 0.2, 1.0), Vec3(0.5, 0.4, 1.0),
                                  Vec3(-0.1, -0.3, 1.0)};
  const std::vector<Vec3> laterals = {Vec3(0.1, 1.0, 0.05), Vec3(-0.2, 1.0, 0.3), Vec3(0.0, 1.0, 0.0),
                                      Vec3(0.3, 0.9, -0.2)};
  std::vector<ContactFrame> frames;
  for (size_t c = 0; c < depths.size(); ++c) {
    ContactFrame f;
    f.radius = fc.radius;
    f.leg_axis = legs[c].normalized();
    f.lateral = laterals[c].normalized();
    f.lateral_rotates = fc.lateral_rotates;
    // Put the sphere centre so that φ = depth: along the normal from a point on the plane.
    const Vec3 on_plane = terrain.normal() * terrain.offset() + Vec3(0.1 * c, -0.05 * c, 0.0) -
                          terrain.normal() * terrain.normal().dot(Vec3(0.1 * c, -0.05 * c, 0.0));
    f.position = on_plane + (depths[c] + fc.radius) * terrain.normal();
    frames.push_back(f);
  }
  return frames;
}

const std::vector<FrameCase>& frameCases() {
  static const std::vector<FrameCase> cases = {
      {"flat", Vec3::UnitZ(), 0.0, 0.0, true},
      {"flat_radius", Vec3::UnitZ(), 0.0, 0.03, true},
      {"tilted_plane", Vec3(0.2, -0.15, 1.0), 0.05, 0.0, true},
      {"tilted_plane_radius", Vec3(-0.3, 0.25, 1.0), -0.1, 0.025, true},
      {"tilted_plane_fixed_lateral", Vec3(0.2, -0.15, 1.0), 0.05, 0.02, false},
      {"flat_fixed_lateral", Vec3::UnitZ(), 0.0, 0.0, false},
  };
  return cases;
}

void checkFrameDerivatives(const ContactModel& model, const char* what) {
  for (const FrameCase& fc : frameCases()) {
    const PlaneTerrain terrain(fc.normal, fc.offset);
    const auto frames = framesFor(fc, terrain);
    // φ as intended (the setup itself).
    TerrainQuery q;
    terrain.query(frames[0].position, q, false);
    ASSERT_NEAR(q.distance - fc.radius, -0.05, 1e-12);
    // Step 3e-6 (m and rad): the published thin-plate sum cancels by ~1e3, so rounding dominates
    // below ~1e-6 and truncation above ~1e-5.
    const double err = frameDerivativeError(model, frames, terrain, 3e-6);
    std::cout << "[ info ] " << what << " dV/dxi vs central differences, " << fc.name << ": " << err << "\n";
  }
}

// A curved terrain (a ball-shaped hill of radius R around o, test_terrains.hpp): unlike a plane, its
// normal changes with the query point, which exercises the ∂n/∂p terms of the sagittal frame.
void checkCurvedTerrainDerivatives(const ContactModel& model, const char* what) {
  const BallTerrain hill(Vec3(0.1, -0.2, -0.8), 0.8);
  const std::vector<Vec3> directions = {Vec3(0.3, 0.2, 1.0), Vec3(-0.5, 0.1, 1.0), Vec3(0.1, -0.6, 1.0),
                                        Vec3(0.4, 0.4, 1.0)};
  const std::vector<double> depths = {-0.05, -0.02, 0.09, 0.075};
  for (bool lateral_rotates : {true, false}) {
    for (double radius : {0.0, 0.03}) {
      std::vector<ContactFrame> frames;
      for (size_t c = 0; c < directions.size(); ++c) {
        ContactFrame f;
        f.radius = radius;
        f.position = hill.centre() + (hill.radius() + depths[c] + radius) * directions[c].normalized();
        f.leg_axis = Vec3(0.2 - 0.1 * c, 0.15 * c - 0.2, 1.0).normalized();
        f.lateral = Vec3(0.1 * c, 1.0, -0.1).normalized();
        f.lateral_rotates = lateral_rotates;
        frames.push_back(f);
      }
      const double err = frameDerivativeError(model, frames, hill, 3e-6);
      std::cout << "[ info ] " << what << " dV/dxi vs central differences, curved terrain, radius " << radius
                << (lateral_rotates ? "" : ", fixed lateral") << ": " << err << "\n";
    }
  }
}

TEST(RbfPublished, FrameDerivativesMatchFiniteDifferences) {
  NMDP_REQUIRE_SHARED(kSandModel);
  checkFrameDerivatives(*loadSandModel(), "published");
  checkCurvedTerrainDerivatives(*loadSandModel(), "published");
}

TEST(RbfSynthetic, FrameDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(21);
  PlanarWrenchModel model(std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::Gaussian, true, rng)),
                          publishedRbfGeometry(), "rbf");
  checkFrameDerivatives(model, "synthetic gaussian");
  checkCurvedTerrainDerivatives(model, "synthetic gaussian");
}

// ===== (e) HDF5 round trip =====================================================================

void checkRoundTrip(const std::shared_ptr<const RbfFunction>& f, const PlanarGeometry& geometry) {
  TempDir tmp;
  const std::string path = tmp.file("model.h5");
  saveRbfModel(path, *f, geometry);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));

  const RbfModelFile loaded = readRbfHdf5(path);
  const RbfParameters& a = f->parameters();
  const RbfParameters& b = loaded.parameters;
  EXPECT_EQ(a.spec.kernel, b.spec.kernel);
  EXPECT_EQ(a.spec.scaling, b.spec.scaling);
  EXPECT_EQ(a.spec.epsilon, b.spec.epsilon);
  EXPECT_EQ(a.centres, b.centres);
  EXPECT_EQ(a.weights, b.weights);
  ASSERT_EQ(a.polynomial.size(), b.polynomial.size());
  if (a.polynomial.size()) {
    EXPECT_EQ(a.polynomial, b.polynomial);
  }
  EXPECT_EQ(geometry.torque_centre, loaded.geometry.torque_centre);
  EXPECT_EQ(geometry.cutoff, loaded.geometry.cutoff);
  EXPECT_EQ(geometry.cutoff_width, loaded.geometry.cutoff_width);

  // Bit-identical values and derivatives, directly and through the factory.
  const RbfFunction g(b);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> depth(-0.07, 0.1), angle(-0.9, 0.9);
  Eigen::MatrixX2d points(20, 2);
  for (int r = 0; r < points.rows(); ++r) points.row(r) << depth(rng), angle(rng);
  Eigen::MatrixXd W1, P1, B1, W2, P2, B2;
  f->evaluate(points, W1, &P1, &B1);
  g.evaluate(points, W2, &P2, &B2);
  EXPECT_TRUE((W1.array() == W2.array()).all());
  EXPECT_TRUE((P1.array() == P2.array()).all());
  EXPECT_TRUE((B1.array() == B2.array()).all());

  const auto model = makeRbfModel({{"type", "rbf"}, {"file", "model.h5"}}, ConfigContext{"test", tmp.dir()});
  const PlanarWrenchModel original(f, geometry, "rbf");
  const PlaneTerrain terrain(Vec3(0.1, 0.0, 1.0), 0.0);
  const auto frames = framesFor(frameCases()[2], terrain);
  std::vector<ContactWrenches> o1(frames.size()), o2(frames.size());
  for (size_t c = 0; c < frames.size(); ++c) {
    o1[c].resize(f->vertexCount());
    o2[c].resize(f->vertexCount());
  }
  original.evaluate(frames, terrain, o1, true);
  model->evaluate(frames, terrain, o2, true);
  for (size_t c = 0; c < frames.size(); ++c) {
    EXPECT_TRUE((o1[c].V.array() == o2[c].V.array()).all());
    for (int i = 0; i < 6; ++i) EXPECT_TRUE((o1[c].dV[i].array() == o2[c].dV[i].array()).all());
  }
  // Geometry keys override the file's.
  const auto overridden =
      makeRbfModel({{"file", "model.h5"}, {"cutoff", 0.2}, {"torque_centre", 0.3}}, ConfigContext{"test", tmp.dir()});
  const auto& pw = dynamic_cast<const PlanarWrenchModel&>(*overridden);
  EXPECT_EQ(pw.geometry().cutoff, 0.2);
  EXPECT_EQ(pw.geometry().torque_centre, 0.3);
  EXPECT_EQ(pw.geometry().cutoff_width, geometry.cutoff_width);

  // Readable layout (the documented datasets and attributes).
  const h5::File file = h5::File::openRead(path);
  EXPECT_TRUE(file.hasAttribute("/", "nmdp_model"));
  EXPECT_TRUE(file.hasAttribute("/rbf", "units"));
  EXPECT_EQ(file.readStrings("/rbf/kernel"), (std::vector<std::string>{rbfKernelName(a.spec.kernel)}));
  EXPECT_EQ(file.readMatrix("/rbf/weights").rows(), a.centres.rows());
  EXPECT_EQ(file.readDoubleAttribute("/rbf", "format_version"), 1.0);
  EXPECT_EQ(file.readStrings("/rbf/feature_names"), (std::vector<std::string>{"phi", "beta"}));
}

TEST(RbfPublished, Hdf5RoundTripIsBitIdentical) {
  NMDP_REQUIRE_SHARED(kSandModel);
  checkRoundTrip(loadSandFunction(), publishedRbfGeometry());
}

TEST(RbfSynthetic, Hdf5RoundTripIsBitIdentical) {
  std::mt19937 rng(31);
  PlanarGeometry g;
  g.torque_centre = 0.12;
  g.cutoff = 0.08;
  g.cutoff_width = 0.015;
  checkRoundTrip(std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::Gaussian, true, rng)), g);
  checkRoundTrip(std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::ThinPlate, false, rng)), g);
}

// ===== (f) bad input ===========================================================================

// A small published-format model: 3 centres, 2 vertices.
const char* kInputs = "-0.01 0.0\n-0.03 0.3\n0.05 -0.3\n";
std::string weightsText(int lines) {
  std::string s;
  for (int i = 0; i < lines; ++i) s += std::to_string(i) + ".5 -" + std::to_string(i) + " 1e-3\n";
  return s;
}

TEST(RbfBadInput, PublishedFormat) {
  TempDir tmp;
  const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
  // A valid one first.
  tmp.write("ok/inputs.txt", kInputs);
  tmp.write("ok/weights.txt", "# comment\n" + weightsText(6) + "\n");
  const auto ok = makeRbfModel({{"file", "ok"}}, ctx);
  EXPECT_EQ(ok->vertexCount(), 2);

  // Missing folder, missing weights file.
  expectInputError(
      [&] {
        makeRbfModel({{"file", "nowhere"}}, ctx);
      },
      {"scene.json: contacts.model.file", tmp.file("nowhere"), "no such file"});
  tmp.write("noweights/inputs.txt", kInputs);
  expectInputError(
      [&] {
        makeRbfModel({{"file", "noweights"}}, ctx);
      },
      {"contacts.model.file", tmp.file("noweights/weights.txt"), "no such file"});
  expectInputError([&] { readPublishedRbf(tmp.file("absent.txt"), tmp.file("ok/weights.txt")); },
                   {tmp.file("absent.txt"), "no such file"});
  // Wrong shapes.
  tmp.write("cols/inputs.txt", "-0.01 0.0\n-0.03 0.3 0.7\n0.05 -0.3\n");
  tmp.write("cols/weights.txt", weightsText(6));
  expectInputError([&] { makeRbfModel({{"file", "cols"}}, ctx); }, {tmp.file("cols/inputs.txt") + ":2", "expected 2"});
  tmp.write("wcols/inputs.txt", kInputs);
  tmp.write("wcols/weights.txt", "1 2 3\n4 5\n1 2 3\n1 2 3\n1 2 3\n1 2 3\n");
  expectInputError(
      [&] {
        makeRbfModel({{"file", "wcols"}}, ctx);
      },
      {tmp.file("wcols/weights.txt") + ":2", "expected 3"});
  tmp.write("count/inputs.txt", kInputs);
  tmp.write("count/weights.txt", weightsText(5));
  expectInputError(
      [&] {
        makeRbfModel({{"file", "count"}}, ctx);
      },
      {tmp.file("count/weights.txt"), "5 weight lines", "multiple of the 3 centres"});
  tmp.write("empty/inputs.txt", "\n# nothing\n");
  tmp.write("empty/weights.txt", weightsText(6));
  expectInputError([&] { makeRbfModel({{"file", "empty"}}, ctx); }, {tmp.file("empty/inputs.txt"), "no centres"});
  // NaN and non-numeric values.
  tmp.write("nan/inputs.txt", kInputs);
  tmp.write("nan/weights.txt", "1 2 3\n4 nan 6\n1 2 3\n1 2 3\n1 2 3\n1 2 3\n");
  expectInputError([&] { makeRbfModel({{"file", "nan"}}, ctx); }, {tmp.file("nan/weights.txt") + ":2", "non-finite"});
  tmp.write("inf/inputs.txt", "-0.01 inf\n");
  tmp.write("inf/weights.txt", "1 2 3\n");
  expectInputError([&] { makeRbfModel({{"file", "inf"}}, ctx); }, {tmp.file("inf/inputs.txt") + ":1", "non-finite"});
  tmp.write("text/inputs.txt", kInputs);
  tmp.write("text/weights.txt", "1 2 3\n\n1 2 abc\n1 2 3\n");
  expectInputError(
      [&] {
        makeRbfModel({{"file", "text"}}, ctx);
      },
      {tmp.file("text/weights.txt") + ":3", "'abc' is not a number"});
  // Finite but huge: a centre at 3e306 made every wrench infinite (found by fuzz_rbf_text).
  tmp.write("huge/inputs.txt", "-0.01 0\n-0.031e308 2.3\n0.06 0\n");
  tmp.write("huge/weights.txt", weightsText(6));
  expectInputError([&] { makeRbfModel({{"file", "huge"}}, ctx); }, {tmp.file("huge/inputs.txt"), "centre 2", "|phi| = 3.1e+306 > 1000"});
  tmp.write("bigw/inputs.txt", kInputs);
  tmp.write("bigw/weights.txt", "1 2 3\n1 2 3\n1 2 1e200\n1 2 3\n1 2 3\n1 2 3\n");
  expectInputError([&] { makeRbfModel({{"file", "bigw"}}, ctx); }, {tmp.file("bigw/weights.txt"), "weight of magnitude 1e+200"});
  tmp.write("junk/inputs.txt", "-0.01 0.0x\n");
  tmp.write("junk/weights.txt", "1 2 3\n");
  expectInputError([&] { makeRbfModel({{"file", "junk"}}, ctx); }, {tmp.file("junk/inputs.txt") + ":1", "'0.0x'"});
}

TEST(RbfBadInput, Hdf5Format) {
  TempDir tmp;
  const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
  std::mt19937 rng(41);
  const RbfFunction f(syntheticRbf(RbfKernel::ThinPlate, true, rng, 5, 2));
  saveRbfModel(tmp.file("good.h5"), f, publishedRbfGeometry());
  EXPECT_EQ(makeRbfModel({{"file", "good.h5"}}, ctx)->vertexCount(), 2);

  // Writes a model file with one thing changed.
  const auto writeModel = [&](const std::string& name, const std::function<void(h5::File&)>& change) {
    h5::File file = h5::File::createAtomic(tmp.file(name));
    file.createGroup("/rbf");
    change(file);
    file.commit();
    return tmp.file(name);
  };
  const RbfParameters& p = f.parameters();
  const auto standard = [&](h5::File& file, bool centres, bool weights, bool kernel) {
    file.writeDoubleAttribute("/rbf", "format_version", 1);
    if (kernel) file.writeStrings("/rbf/kernel", {"thin_plate"});
    file.writeDoubleAttribute("/rbf", "epsilon", 1.0);
    file.writeDoubleAttribute("/rbf", "torque_centre", 0.1572);
    file.writeDoubleAttribute("/rbf", "cutoff", 0.1);
    file.writeDoubleAttribute("/rbf", "cutoff_width", 0.02);
    file.writeVector("/rbf/scaling", p.spec.scaling);
    if (centres) file.writeMatrix("/rbf/centres", p.centres);
    if (weights) file.writeMatrix("/rbf/weights", p.weights);
  };

  expectInputError(
      [&] {
        makeRbfModel({{"file", "absent.h5"}}, ctx);
      },
      {"contacts.model.file", tmp.file("absent.h5"), "no such file"});
  expectInputError([&] { readRbfHdf5(tmp.write("text.h5", "not hdf5")); }, {tmp.file("text.h5"), "not an HDF5 file"});
  {
    h5::File file = h5::File::createAtomic(tmp.file("nogroup.h5"));
    file.writeMatrix("/other", Eigen::MatrixXd::Zero(2, 2));
    file.commit();
  }
  expectInputError([&] { readRbfHdf5(tmp.file("nogroup.h5")); }, {tmp.file("nogroup.h5"), "'/rbf'"});

  const std::string rows = writeModel("rows.h5", [&](h5::File& file) {
    standard(file, true, false, true);
    Eigen::MatrixXd w(p.weights.rows() + 1, p.weights.cols());
    w.setOnes();
    file.writeMatrix("/rbf/weights", w);
  });
  expectInputError([&] { makeRbfModel({{"file", "rows.h5"}}, ctx); }, {rows, "'/rbf/weights'", "N x 3K"});
  const std::string cols = writeModel("cols.h5", [&](h5::File& file) {
    standard(file, true, false, true);
    file.writeMatrix("/rbf/weights", Eigen::MatrixXd::Ones(p.weights.rows(), 4));
  });
  expectInputError([&] { readRbfHdf5(cols); }, {cols, "'/rbf/weights'"});
  const std::string centres = writeModel("centres.h5", [&](h5::File& file) {
    standard(file, false, true, true);
    file.writeMatrix("/rbf/centres", Eigen::MatrixXd::Zero(p.centres.rows(), 3));
  });
  expectInputError([&] { readRbfHdf5(centres); }, {centres, "'/rbf/centres'", "N x 2"});
  const std::string nan = writeModel("nan.h5", [&](h5::File& file) {
    standard(file, true, false, true);
    Eigen::MatrixXd w = p.weights;
    w(2, 3) = std::numeric_limits<double>::quiet_NaN();
    file.writeMatrix("/rbf/weights", w);
  });
  expectInputError(
      [&] {
        makeRbfModel({{"file", "nan.h5"}}, ctx);
      },
      {"contacts.model.file", nan, "'/rbf/weights'", "non-finite", "row 2, column 3"});
  const std::string missing = writeModel("missing.h5", [&](h5::File& file) { standard(file, true, false, true); });
  expectInputError([&] { readRbfHdf5(missing); }, {missing, "'/rbf/weights'", "missing"});
  const std::string poly = writeModel("poly.h5", [&](h5::File& file) {
    standard(file, true, true, true);
    file.writeMatrix("/rbf/polynomial", Eigen::MatrixXd::Zero(2, p.weights.cols()));
  });
  expectInputError([&] { readRbfHdf5(poly); }, {poly, "'/rbf/polynomial'"});
  const std::string kernel = writeModel("kernel.h5", [&](h5::File& file) {
    standard(file, true, true, false);
    file.writeStrings("/rbf/kernel", {"thinplate"});
  });
  expectInputError([&] { readRbfHdf5(kernel); }, {kernel, "'/rbf/kernel'", "thinplate", "thin_plate"});
  const std::string nokernel = writeModel("nokernel.h5", [&](h5::File& file) { standard(file, true, true, false); });
  expectInputError([&] { readRbfHdf5(nokernel); }, {nokernel, "'/rbf/kernel'", "missing"});
  const std::string version = writeModel("version.h5", [&](h5::File& file) {
    standard(file, true, true, true);
    file.writeDoubleAttribute("/rbf", "format_version", 2);
  });
  expectInputError([&] { readRbfHdf5(version); }, {version, "format_version"});
  const std::string width = writeModel("width.h5", [&](h5::File& file) {
    standard(file, true, true, true);
    file.writeDoubleAttribute("/rbf", "cutoff_width", 0.0);
  });
  expectInputError([&] { readRbfHdf5(width); }, {width, "cutoff_width"});
  const std::string names = writeModel("names.h5", [&](h5::File& file) {
    standard(file, true, true, true);
    file.writeStrings("/rbf/feature_names", {"depth", "velocity"});
  });
  expectInputError([&] { readRbfHdf5(names); }, {names, "feature_names"});
}

// configuration() holds every key the format accepts with the value used, and builds the same model.
TEST(RbfConfiguration, ListsEveryKeyWithTheValueUsedAndRebuildsTheSameModel) {
  TempDir tmp;
  const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
  tmp.write("pub/inputs.txt", kInputs);
  tmp.write("pub/weights.txt", weightsText(6));
  std::mt19937 rng(52);
  PlanarGeometry file_geometry{0.12, 0.09, 0.015};
  saveRbfModel(tmp.file("m.h5"), RbfFunction(syntheticRbf(RbfKernel::Gaussian, false, rng)), file_geometry);

  const PlanarGeometry published = publishedRbfGeometry();
  const RbfKernelSpec spec;
  const std::unique_ptr<ContactModel> pub_model = makeRbfModel({{"file", "pub"}}, ctx);
  const nlohmann::json pub = pub_model->configuration();
  EXPECT_EQ(pub, nlohmann::json({{"type", "rbf"},
                                 {"file", tmp.file("pub")},
                                 {"format", "published"},
                                 {"weights_file", tmp.file("pub/weights.txt")},
                                 {"kernel", rbfKernelName(spec.kernel)},
                                 {"scaling", {spec.scaling[0], spec.scaling[1]}},
                                 {"epsilon", spec.epsilon},
                                 {"torque_centre", published.torque_centre},
                                 {"cutoff", published.cutoff},
                                 {"cutoff_width", published.cutoff_width}}));
  for (const std::string& key : kRbfParameters) EXPECT_TRUE(pub.contains(key)) << key;

  // An HDF5 file: its geometry, or the override; kernel, scaling and epsilon belong to the file.
  const std::unique_ptr<ContactModel> h5_model = makeRbfModel({{"file", "m.h5"}, {"cutoff", 0.2}}, ctx);
  const nlohmann::json h5 = h5_model->configuration();
  EXPECT_EQ(h5, nlohmann::json({{"type", "rbf"},
                                {"file", tmp.file("m.h5")},
                                {"format", "hdf5"},
                                {"torque_centre", file_geometry.torque_centre},
                                {"cutoff", 0.2},
                                {"cutoff_width", file_geometry.cutoff_width}}));

  const PlaneTerrain flat;
  ContactFrame frame;
  frame.position = Vec3(0.1, 0.0, -0.02);
  frame.leg_axis = Vec3(std::sin(0.2), 0.0, std::cos(0.2));
  for (const ContactModel* first : {pub_model.get(), h5_model.get()}) {
    const nlohmann::json config = first->configuration();
    SCOPED_TRACE(config.dump());
    // From JSON text, in another folder: every path is absolute.
    const auto again = makeRbfModel(nlohmann::json::parse(config.dump()), ConfigContext{"again", "/nonexistent"});
    EXPECT_EQ(again->configuration(), config);
    const Mat6X a = evaluateOne(*first, frame, flat), b = evaluateOne(*again, frame, flat);
    EXPECT_TRUE((a.array() == b.array()).all());
    EXPECT_GT(a.cwiseAbs().maxCoeff(), 0.0) << "the test frame is in contact";
  }
  // A PlanarWrenchModel built in code has no configuration to report.
  EXPECT_TRUE(PlanarWrenchModel(std::make_shared<RbfFunction>(syntheticRbf(RbfKernel::Gaussian, false, rng)), published, "rbf")
                  .configuration()
                  .is_null());
}

TEST(RbfBadInput, Configuration) {
  TempDir tmp;
  const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
  tmp.write("ok/inputs.txt", kInputs);
  tmp.write("ok/weights.txt", weightsText(6));
  std::mt19937 rng(51);
  saveRbfModel(tmp.file("m.h5"), RbfFunction(syntheticRbf(RbfKernel::Gaussian, false, rng)), publishedRbfGeometry());
  tmp.write("model.bin", "?");

  expectInputError([&] { makeRbfModel(nlohmann::json::object(), ctx); },
                   {"scene.json: contacts.model.file", "missing"});
  expectInputError([&] { makeRbfModel({{"file", 3}}, ctx); }, {"contacts.model.file", "string"});
  expectInputError(
      [&] {
        makeRbfModel({{"file", "ok"}, {"scalling", {5, 1}}}, ctx);
      },
      {"contacts.model.scalling", "did you mean 'scaling'"});
  expectInputError([&] { makeRbfModel({{"type", "coulomb"}, {"file", "ok"}}, ctx); }, {"contacts.model.type"});
  expectInputError(
      [&] {
        makeRbfModel({{"file", "ok"}, {"kernel", "thinplate"}}, ctx);
      },
      {"contacts.model.kernel", "thin_plate"});
  expectInputError([&] { makeRbfModel({{"file", "ok"}, {"scaling", {5}}}, ctx); }, {"contacts.model.scaling"});
  expectInputError([&] { makeRbfModel({{"file", "ok"}, {"scaling", {5, -1}}}, ctx); }, {"contacts.model.scaling"});
  expectInputError([&] { makeRbfModel({{"file", "ok"}, {"epsilon", 0}}, ctx); }, {"contacts.model.epsilon"});
  expectInputError([&] { makeRbfModel({{"file", "ok"}, {"cutoff_width", 0}}, ctx); }, {"contacts.model.cutoff_width"});
  expectInputError([&] { makeRbfModel({{"file", "ok"}, {"format", "csv"}}, ctx); }, {"contacts.model.format"});
  expectInputError(
      [&] {
        makeRbfModel({{"file", "m.h5"}, {"kernel", "gaussian"}}, ctx);
      },
      {"contacts.model.kernel", "stored in the HDF5 model file"});
  expectInputError([&] { makeRbfModel({{"file", "model.bin"}}, ctx); }, {tmp.file("model.bin"), "format"});
  // An explicit format overrides the name.
  expectInputError(
      [&] {
        makeRbfModel({{"file", "model.bin"}, {"format", "hdf5"}}, ctx);
      },
      {tmp.file("model.bin"), "not an HDF5 file"});
  EXPECT_EQ(makeRbfModel({{"file", "ok/inputs.txt"}, {"weights_file", "ok/weights.txt"}, {"format", "published"}}, ctx)
                ->vertexCount(),
            2);
  // Every accepted key is listed.
  for (const char* key :
       {"file", "format", "weights_file", "kernel", "scaling", "epsilon", "torque_centre", "cutoff", "cutoff_width"})
    EXPECT_NE(std::find(kRbfParameters.begin(), kRbfParameters.end(), key), kRbfParameters.end()) << key;
  EXPECT_EQ(std::find(kRbfParameters.begin(), kRbfParameters.end(), "type"), kRbfParameters.end());
}

// ===== performance: no allocation once warmed up (bench_contact_models times it) =================

TEST(RbfPerformance, NoAllocationOnceWarmedUp) {
  std::shared_ptr<const RbfFunction> f;
  if (fs::exists(sharedPath(kSandModel))) {
    f = loadSandFunction();
  } else {
    std::mt19937 rng(61);
    f = std::make_shared<const RbfFunction>(syntheticRbf(RbfKernel::ThinPlate, false, rng, 103, 26));
  }
  const PlanarWrenchModel model(f, publishedRbfGeometry(), "rbf");
  const PlaneTerrain terrain(Vec3(0.1, -0.05, 1.0), 0.0);
  const auto frames = framesFor(frameCases()[2], terrain);
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& w : out) w.resize(model.vertexCount());
  model.evaluate(frames, terrain, out, true);  // warm up
  model.evaluate(frames, terrain, out, false);

  const AllocationCount count = countAllocations([&] {
    model.evaluate(frames, terrain, out, true);
    model.evaluate(frames, terrain, out, false);
  });
  if (NMDP_COUNTS_MALLOC) {
    EXPECT_EQ(count.mallocs, 0) << "PlanarWrenchModel(RBF)::evaluate allocated once warmed up";
  } else {
    std::cout << "[ info ] allocation counting unavailable in this build (sanitizer or non-glibc)\n";
  }
}

}  // namespace
}  // namespace nmdp::test
