// The 3-D RBF feature function (spatial_rbf_function.hpp): its values against the defining sum, its
// dW/df against central differences, the HDF5 round trip, the "rbf" factory's dispatch on the file
// and every bad file giving one message naming the file and the dataset.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <random>

#include "common/input_error.hpp"
#include "contact_models/rbf_model.hpp"
#include "contact_models/spatial_rbf_function.hpp"
#include "io/hdf5_file.hpp"
#include "spatial_sand.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

namespace fs = std::filesystem;

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

Eigen::MatrixX3d samplePoints() {
  Eigen::MatrixX3d x(5, 3);
  x << -0.05, 0.3, -0.2, -0.01, -0.4, 0.5, 0.015, 0.05, 0.0, -0.08, 0.9, -0.7, -0.03, 0.0, 0.25;
  return x;
}

const RbfKernel kSmoothKernels[] = {RbfKernel::ThinPlate, RbfKernel::Gaussian, RbfKernel::Multiquadric,
                                    RbfKernel::InverseMultiquadric, RbfKernel::Cubic};

TEST(SpatialRbf, BatchEvaluationEqualsTheDefiningSum) {
  std::mt19937 rng(3);
  for (RbfKernel kernel : kSmoothKernels) {
    const SpatialRbfParameters p = randomSpatialRbf(kernel, true, rng, 9, 4);
    const SpatialRbfFunction f(p);
    const Eigen::MatrixX3d x = samplePoints();
    Eigen::MatrixXd W;
    f.evaluate(x, W, nullptr);
    ASSERT_EQ(W.rows(), x.rows());
    ASSERT_EQ(W.cols(), 24);
    for (Eigen::Index b = 0; b < x.rows(); ++b) {
      Eigen::RowVectorXd expected = p.polynomial.row(0) + x(b, 0) * p.polynomial.row(1) +
                                    x(b, 1) * p.polynomial.row(2) + x(b, 2) * p.polynomial.row(3);
      for (Eigen::Index i = 0; i < p.centres.rows(); ++i) {
        const Eigen::Vector3d d = p.scaling.cwiseProduct(x.row(b).transpose() - p.centres.row(i).transpose());
        double kappa = 0.0, g = 0.0;
        rbfKernel(kernel, p.epsilon, d.squaredNorm(), &kappa, &g);
        expected += kappa * p.weights.row(i);
      }
      EXPECT_LT((W.row(b) - expected).cwiseAbs().maxCoeff(), 1e-11 * (1.0 + expected.cwiseAbs().maxCoeff()))
          << rbfKernelName(kernel) << ", point " << b;
    }
    // With derivatives the values are the same to the bit, and each row does not depend on the batch.
    std::array<Eigen::MatrixXd, 3> dW;
    Eigen::MatrixXd W2, W1;
    f.evaluate(x, W2, &dW);
    EXPECT_EQ(W, W2) << rbfKernelName(kernel) << "\n" << (W - W2);
    f.evaluate(x.topRows(1), W1, nullptr);
    EXPECT_EQ(W1.row(0), W.row(0)) << rbfKernelName(kernel);
  }
}

TEST(SpatialRbf, FeatureDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(5);
  for (RbfKernel kernel : kSmoothKernels)
    for (bool tail : {false, true}) {
      const SpatialRbfFunction f(randomSpatialRbf(kernel, tail, rng, 11, 3));
      const Eigen::MatrixX3d x = samplePoints();
      Eigen::MatrixXd W;
      std::array<Eigen::MatrixXd, 3> dW;
      f.evaluate(x, W, &dW);
      const double h = 1e-6;
      for (int c = 0; c < 3; ++c) {
        Eigen::MatrixX3d plus = x, minus = x;
        plus.col(c).array() += h;
        minus.col(c).array() -= h;
        Eigen::MatrixXd Wp, Wm;
        f.evaluate(plus, Wp, nullptr);
        f.evaluate(minus, Wm, nullptr);
        const Eigen::MatrixXd numeric = (Wp - Wm) / (2 * h);
        // Step 1e-6 on features of order 1 (scaled): truncation ~1e-12 relative, rounding ~1e-10.
        const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
        EXPECT_LT((dW[c] - numeric).cwiseAbs().maxCoeff() / scale, 1e-6)
            << rbfKernelName(kernel) << (tail ? " with tail" : "") << ", feature " << c;
      }
    }
}

TEST(SpatialRbf, SandFixtureInterpolatesItsFormula) {
  // The fixture the model tests use is what it says: exact at the centres, close between them.
  const SpatialRbfFunction f(sandSpatialRbf());
  EXPECT_EQ(f.vertexCount(), 26);
  EXPECT_EQ(f.centreCount(), 45);
  const std::vector<Vec3> d = defaultSpatialDirections();
  Eigen::MatrixX3d x(2, 3);
  x << -0.04, 0.4, 0.0, -0.025, 0.1, 0.1;  // a centre, and a point between centres
  Eigen::MatrixXd W;
  f.evaluate(x, W, nullptr);
  for (int v = 0; v < 26; ++v) {
    const Eigen::Matrix<double, 6, 1> at = sandWrench(x.row(0).transpose(), d[v]);
    const Eigen::Matrix<double, 6, 1> between = sandWrench(x.row(1).transpose(), d[v]);
    EXPECT_LT((W.block(0, 6 * v, 1, 6).transpose() - at).norm(), 1e-8 * (1 + at.norm())) << v;
    EXPECT_LT((W.block(1, 6 * v, 1, 6).transpose() - between).norm(), 0.1 * between.norm() + 1.0) << v;
  }
  // The vertex pushing down (direction (0, 0, −1), index 12) holds the foot up.
  EXPECT_GT(W(0, 6 * 12 + 5), 300.0);
}

TEST(SpatialRbf, Hdf5RoundTripIsBitIdenticalAndTheFactoryBuildsASpatialModel) {
  TempDir tmp;
  std::mt19937 rng(7);
  for (bool tail : {false, true}) {
    const SpatialRbfFunction f(randomSpatialRbf(RbfKernel::Gaussian, tail, rng, 8, 3));
    const SpatialGeometry geometry{0.01, 0.004};
    const std::string path = tmp.file(tail ? "tail.h5" : "plain.h5");
    saveSpatialRbfModel(path, f, geometry);
    EXPECT_FALSE(fs::exists(path + ".partial"));
    EXPECT_TRUE(isSpatialRbfFile(path));
    const SpatialRbfModelFile loaded = readSpatialRbfHdf5(path);
    EXPECT_EQ(loaded.parameters.kernel, RbfKernel::Gaussian);
    EXPECT_EQ(loaded.parameters.epsilon, f.parameters().epsilon);
    EXPECT_EQ(loaded.parameters.scaling, f.parameters().scaling);
    EXPECT_EQ(loaded.parameters.centres, f.parameters().centres);
    EXPECT_EQ(loaded.parameters.weights, f.parameters().weights);
    EXPECT_EQ(loaded.parameters.polynomial, f.parameters().polynomial);
    EXPECT_EQ(loaded.geometry.cutoff, 0.01);
    EXPECT_EQ(loaded.geometry.cutoff_width, 0.004);

    const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
    const auto model = makeRbfModel({{"type", "rbf"}, {"file", path}, {"cutoff_width", 0.003}}, ctx);
    const auto* spatial = dynamic_cast<const SpatialWrenchModel*>(model.get());
    ASSERT_NE(spatial, nullptr);
    EXPECT_EQ(spatial->vertexCount(), 3);
    EXPECT_EQ(spatial->geometry().cutoff, 0.01);
    EXPECT_EQ(spatial->geometry().cutoff_width, 0.003);
    const nlohmann::json config = model->configuration();
    EXPECT_EQ(config.at("type"), "rbf");
    EXPECT_EQ(config.at("file"), path);
    EXPECT_EQ(config.at("cutoff_width"), 0.003);
    EXPECT_FALSE(config.contains("torque_centre"));
    // The configuration builds the same model again.
    const auto again = makeRbfModel(config, ctx);
    EXPECT_EQ(again->describe(), model->describe());
    EXPECT_EQ(again->configuration(), config);
  }
  // A planar file is not spatial.
  RbfParameters planar;
  planar.centres = Eigen::MatrixX2d::Zero(1, 2);
  planar.weights = Eigen::MatrixXd::Ones(1, 3);
  saveRbfModel(tmp.file("planar.h5"), RbfFunction(planar), publishedRbfGeometry());
  EXPECT_FALSE(isSpatialRbfFile(tmp.file("planar.h5")));
}

TEST(SpatialRbfBadInput, EachBadFileGivesOneMessageNamingFileAndDataset) {
  TempDir tmp;
  const ConfigContext ctx{"scene.json: contacts.model", tmp.dir()};
  std::mt19937 rng(11);
  const SpatialRbfFunction f(randomSpatialRbf(RbfKernel::ThinPlate, true, rng, 5, 2));
  const SpatialRbfParameters& p = f.parameters();
  // Writes a model file with the standard content, then lets `change` alter it.
  struct Content {
    Eigen::MatrixXd centres, weights, polynomial;
    Eigen::VectorXd scaling;
    std::string kernel = "thin_plate";
    double version = 1.0;
    std::vector<std::string> names = {"phi", "beta", "gamma"};
  };
  const auto write = [&](const std::string& name, const std::function<void(Content&)>& change) {
    Content c{p.centres, p.weights, p.polynomial, p.scaling};
    change(c);
    h5::File file = h5::File::createAtomic(tmp.file(name));
    file.createGroup("/rbf");
    file.writeDoubleAttribute("/rbf", "format_version", c.version);
    file.writeDoubleAttribute("/rbf", "epsilon", 1.0);
    file.writeDoubleAttribute("/rbf", "cutoff", 0.0);
    file.writeDoubleAttribute("/rbf", "cutoff_width", 0.005);
    file.writeStrings("/rbf/kernel", {c.kernel});
    file.writeMatrix("/rbf/centres", c.centres);
    file.writeMatrix("/rbf/weights", c.weights);
    file.writeVector("/rbf/scaling", c.scaling);
    if (c.polynomial.size()) file.writeMatrix("/rbf/polynomial", c.polynomial);
    file.writeStrings("/rbf/feature_names", c.names);
    file.commit();
    return tmp.file(name);
  };
  const std::string good = write("good.h5", [](Content&) {});
  EXPECT_EQ(makeRbfModel({{"file", good}}, ctx)->vertexCount(), 2);

  struct Case {
    std::string name;
    std::function<void(Content&)> change;
    std::string dataset;
  };
  const double nan = std::nan("");
  const std::vector<Case> cases = {
      {"weights_rows", [](Content& c) { c.weights.conservativeResize(4, Eigen::NoChange); }, "'/rbf/weights'"},
      {"weights_columns", [](Content& c) { c.weights.conservativeResize(Eigen::NoChange, 9); }, "'/rbf/weights'"},
      {"centres_nan", [&](Content& c) { c.centres(2, 1) = nan; }, "'/rbf/centres'"},
      {"weights_nan", [&](Content& c) { c.weights(1, 3) = nan; }, "'/rbf/weights'"},
      {"polynomial_nan", [&](Content& c) { c.polynomial(3, 0) = nan; }, "'/rbf/polynomial'"},
      {"polynomial_rows", [](Content& c) { c.polynomial.conservativeResize(3, Eigen::NoChange); }, "'/rbf/polynomial'"},
      {"scaling_length", [](Content& c) { c.scaling = Eigen::Vector2d(20.0, 1.0); }, "'/rbf/scaling'"},
      {"scaling_four", [](Content& c) { c.scaling = Eigen::Vector4d(20.0, 1.0, 1.0, 1.0); }, "'/rbf/scaling'"},
      {"scaling_negative", [](Content& c) { c.scaling[2] = -1.0; }, "'/rbf/scaling'"},
      {"kernel", [](Content& c) { c.kernel = "wendland"; }, "'/rbf/kernel'"},
      {"version", [](Content& c) { c.version = 2.0; }, "'format_version'"},
      {"names", [](Content& c) { c.names = {"phi", "gamma", "beta"}; }, "'/rbf/feature_names'"},
      {"huge_centre", [](Content& c) { c.centres(0, 2) = 1e300; }, "gamma"},
  };
  for (const Case& c : cases) {
    const std::string path = write(c.name + ".h5", c.change);
    SCOPED_TRACE(c.name);
    expectInputError([&] { readSpatialRbfHdf5(path); }, {path, c.dataset});
    expectInputError([&] { makeRbfModel({{"file", path}}, ctx); }, {"contacts.model.file", path, c.dataset});
  }
  // Centres of 4 columns: not a model of either kind (the planar reader names the shape it wants).
  const std::string four = write("four.h5", [](Content& c) { c.centres = Eigen::MatrixXd::Zero(5, 4); });
  expectInputError([&] { makeRbfModel({{"file", four}}, ctx); }, {four, "'/rbf/centres'"});
  // The published-format keys and the torque centre are refused for a 3-D file.
  for (const char* key : {"kernel", "scaling", "epsilon", "weights_file", "torque_centre"}) {
    nlohmann::json params = {{"file", good}};
    params[key] = key == std::string("kernel") || key == std::string("weights_file") ? nlohmann::json("x") : nlohmann::json(1.0);
    expectInputError([&] { makeRbfModel(params, ctx); }, {std::string("contacts.model.") + key, good, "3-D"});
  }
}

}  // namespace
}  // namespace nmdp::test
