// The spatial MLP as a contact model: SpatialWrenchModel's dV/dξ (six ξ directions per contact)
// against central differences of V for every Jacobian scheme, and the "mlp" factory loading a spatial
// file (and refusing the planar-only torque_centre).
#include <gtest/gtest.h>

#include <iostream>

#include "common/input_error.hpp"
#include "contact_derivative_check.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "contact_models/registry.hpp"
#include "contact_models/spatial_wrench_model.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

const SpatialGeometry kGeometry{0.01, 0.008};  // cut-off 1 cm above the surface, 8 mm band

// A random 2×32 network with depths and leans of the sand's range as its normalization, forces of
// hundreds of N, and the soft depth envelope with one zero anchor.
MlpParameters spatialParameters(MlpActivation activation) {
  MlpParameters p = randomMlpParameters(2, 32, 26, activation, 5, MlpWrench::Spatial);
  p.input_mean = Eigen::Vector3d(-0.02, 0.0, 0.0);
  p.input_std = Eigen::Vector3d(0.02, 0.4, 0.4);
  p.output_scale.setConstant(200.0);
  p.output_envelope = MlpOutputEnvelope::SoftDepth;
  p.envelope_width = 0.005;
  p.anchors = Eigen::RowVector3d(0.0, 0.2, -0.2);
  p.anchor_radius = 0.5;
  return p;
}

// Four contacts leaning in β and γ, deep, shallow, in the cut-off band and just below it.
std::vector<ContactFrame> fourContacts(const PlaneTerrain& terrain, double radius) {
  const double depths[4] = {-0.04, -0.012, 0.006, 0.0025};
  const double betas[4] = {0.3, -0.5, 0.2, -0.1};
  const double gammas[4] = {-0.25, 0.35, 0.45, -0.6};
  const Vec3 laterals[4] = {Vec3(0.1, 1.0, 0.05), Vec3(-0.2, 1.0, 0.3), Vec3(1.0, 0.2, 0.0), Vec3(0.3, 0.9, -0.2)};
  const Vec3 n = terrain.normal();
  std::vector<ContactFrame> out;
  for (int c = 0; c < 4; ++c) {
    ContactFrame f;
    f.radius = radius;
    const Vec3 surface = Vec3(0.1 * c, -0.05 * c, 0.0);
    TerrainQuery q;
    terrain.query(surface, q, false);
    f.position = surface + (depths[c] + radius - q.distance) * n;
    f.lateral = laterals[c].normalized();
    const Vec3 y = (f.lateral - f.lateral.dot(n) * n).normalized(), x = y.cross(n);
    f.leg_axis = std::cos(gammas[c]) * std::sin(betas[c]) * x + std::sin(gammas[c]) * y +
                 std::cos(gammas[c]) * std::cos(betas[c]) * n;
    out.push_back(f);
  }
  return out;
}

class MlpSpatialModelDerivatives : public ::testing::TestWithParam<MlpJacobian> {};

TEST_P(MlpSpatialModelDerivatives, MatchCentralDifferencesOfV) {
  for (MlpActivation activation : {MlpActivation::Tanh, MlpActivation::Silu}) {
    auto function = std::make_shared<const MlpFunction>(spatialParameters(activation), GetParam());
    const SpatialWrenchModel model(function, kGeometry, "mlp");
    EXPECT_EQ(model.derivative(), function->derivative());
    VertexDerivativeCheck check;
    check.rotation_step = check.translation_step = 2e-7;  // as for the 3-D RBF (cut-off band truncation)
    check.tolerance = 1e-6;
    const PlaneTerrain flat, tilted(Vec3(0.2, -0.15, 1.0), 0.05);
    for (const PlaneTerrain* terrain_ptr : {&flat, &tilted})
      for (double radius : {0.0, 0.02}) {
        const PlaneTerrain& terrain = *terrain_ptr;
        const std::string label = std::string(mlpActivationName(activation)) + ", radius " + std::to_string(radius);
        const VertexDerivativeResult r = checkVertexDerivative(model, fourContacts(terrain, radius), terrain, check, label);
        std::cout << "[ info ] dV/dxi vs central differences, " << mlpJacobianName(GetParam()) << ", " << label << ": "
                  << r.worst << "\n";
        for (const ContactWrenches& w : r.analytic) EXPECT_GT(w.V.cwiseAbs().maxCoeff(), 0.0) << label;
      }
  }
}

INSTANTIATE_TEST_SUITE_P(AllSchemes, MlpSpatialModelDerivatives,
                         ::testing::Values(MlpJacobian::ForwardMode, MlpJacobian::DoubleBackward, MlpJacobian::Tangents),
                         [](const ::testing::TestParamInfo<MlpJacobian>& info) {
                           std::string s = mlpJacobianName(info.param);
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(MlpSpatialModel, FeaturesAreTheNetworksInput) {
  // On flat ground with lateral axis y (R = I) the force rows of V are σ (F_x, F_y, F_z) of the
  // network at the reported (φ, β, γ).
  const auto function = std::make_shared<const MlpFunction>(spatialParameters(MlpActivation::Tanh), MlpJacobian::Tangents);
  const SpatialWrenchModel model(function, kGeometry, "mlp");
  ASSERT_EQ(model.featureInfo().size(), 3u);
  EXPECT_EQ(model.featureInfo()[2].name, "gamma");
  const PlaneTerrain flat;
  const double depths[2] = {-0.02, -0.008}, betas[2] = {0.2, -0.3}, gammas[2] = {0.1, -0.25};
  std::vector<ContactFrame> frames(2);
  for (int c = 0; c < 2; ++c) {
    frames[c].radius = 0.02;
    frames[c].position = Vec3(0.1 * c, 0.0, 0.02 + depths[c]);
    frames[c].leg_axis = Vec3(std::cos(gammas[c]) * std::sin(betas[c]), std::sin(gammas[c]),
                              std::cos(gammas[c]) * std::cos(betas[c]));
    frames[c].lateral = Vec3::UnitY();
  }
  Eigen::MatrixXd f(2, 3);
  model.features(frames, flat, f);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(f(c, 0), depths[c], 1e-15);
    EXPECT_NEAR(f(c, 1), betas[c], 1e-15);
    EXPECT_NEAR(f(c, 2), gammas[c], 1e-15);
  }
  std::vector<ContactWrenches> out(2);
  for (ContactWrenches& w : out) w.resize(model.vertexCount());
  model.evaluate(frames, flat, out, false);
  Eigen::MatrixXd W;
  function->evaluate(Eigen::MatrixX3d(f), W, nullptr);
  for (int c = 0; c < 2; ++c) {
    const double sigma = cutoffStep(planarGeometryOf(kGeometry), f(c, 0), nullptr);
    Eigen::MatrixXd expected(3, model.vertexCount());
    for (int k = 0; k < model.vertexCount(); ++k) expected.col(k) = sigma * W.row(c).segment<3>(6 * k + 3).transpose();
    const Eigen::MatrixXd forces = out[c].V.bottomRows<3>();
    EXPECT_GT(forces.cwiseAbs().maxCoeff(), 0.1) << c;  // N: the network pushes back (0.9 N at 8 mm)
    EXPECT_LE(ulpsOfLargest(forces, expected), 64.0) << c << "\n" << forces << "\n" << expected;
  }
}

TEST(MlpSpatialModel, RegistryLoadsASpatialFile) {
  const TempDir dir;
  const std::string path = dir.file("sand3d_mlp.h5");
  const MlpParameters p = spatialParameters(MlpActivation::Tanh);
  saveMlpModel(path, p, kGeometry);
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  const ConfigContext ctx{"scene.json: contacts.model", dir.path().string()};
  const auto model = registry.build({{"type", "mlp"}, {"file", path}, {"jacobian", "tangents"}, {"cutoff_width", 0.006}}, ctx);
  const auto* spatial = dynamic_cast<const SpatialWrenchModel*>(model.get());
  ASSERT_NE(spatial, nullptr) << model->describe();
  EXPECT_EQ(spatial->vertexCount(), 26);
  EXPECT_EQ(spatial->geometry().cutoff, kGeometry.cutoff);
  EXPECT_EQ(spatial->geometry().cutoff_width, 0.006);
  EXPECT_EQ(model->configuration().at("type"), "mlp");
  EXPECT_EQ(model->configuration().at("jacobian"), "tangents");
  // The loaded model evaluates as the one built in code.
  const SpatialWrenchModel in_code(std::make_shared<const MlpFunction>(p, MlpJacobian::Tangents),
                                   SpatialGeometry{kGeometry.cutoff, 0.006}, "mlp");
  const PlaneTerrain ground;
  const auto frames = fourContacts(ground, 0.02);
  std::vector<ContactWrenches> a(4), b(4);
  for (int c = 0; c < 4; ++c) a[c].resize(26), b[c].resize(26);
  model->evaluate(frames, ground, a, true);
  in_code.evaluate(frames, ground, b, true);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(a[c].V, b[c].V) << c;
    EXPECT_GT(a[c].V.cwiseAbs().maxCoeff(), 0.0) << c;
  }
  // torque_centre belongs to planar models.
  try {
    registry.build({{"type", "mlp"}, {"file", path}, {"torque_centre", 0.1}}, ctx);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("torque_centre"), std::string::npos) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace nmdp::test
