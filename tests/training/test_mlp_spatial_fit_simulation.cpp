// A spatial MLP fitted by `nmdp fit --model mlp` on 3-D data (test_mlp_spatial_fit.cpp's synthetic
// wrenches) drives a short simulation: the foot dropped onto the sand with the first-order (ne-pgm)
// and the zeroth-order (ne-zopgm) PGM converges every step and is stopped in the sand.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "contact_models/registry.hpp"
#include "scene_simulation.hpp"
#include "test_temp_dir.hpp"
#include "training/mlp/contact_model_fit.hpp"
#include "training/mlp/mlp_fit.hpp"
#include "training/mlp/mlp_points.hpp"

namespace nmdp::test {
namespace {

// Resistance to the 26 default directions growing with depth (2e4 N/m per unit of projected
// resistance), with a torque of the force 2 cm up the leg: smooth in (φ, β, γ).
ForceDataset sandDataset() {
  std::vector<Eigen::Vector3d> dirs;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (i || j || k) dirs.push_back(Eigen::Vector3d(i, j, k).normalized());
  ForceDataset data;
  std::vector<Eigen::Matrix<double, 1, 10>> rows;  // phi, beta, gamma, vertex, wrench
  for (double phi : {-0.04, -0.03, -0.02, -0.01, -0.005})
    for (double beta : {-0.6, 0.0, 0.6})
      for (double gamma : {-0.4, 0.0, 0.4})
        for (size_t j = 0; j < dirs.size(); ++j) {
          const Eigen::Vector3d a(std::cos(gamma) * std::sin(beta), std::sin(gamma), std::cos(gamma) * std::cos(beta));
          const Eigen::Vector3d F = 2e4 * phi * Eigen::Vector3d(1.0, 1.0, 2.0).cwiseProduct(dirs[j]);
          const Eigen::Vector3d tau = (0.02 * a).cross(F);
          Eigen::Matrix<double, 1, 10> r;
          r << phi, beta, gamma, static_cast<double>(j), tau.transpose(), F.transpose();
          rows.push_back(r);
        }
  const Eigen::Index N = static_cast<Eigen::Index>(rows.size());
  data.features.resize(N, 3);
  data.vertex.resize(N);
  data.wrench.resize(N, 6);
  for (Eigen::Index i = 0; i < N; ++i) {
    data.features.row(i) = rows[i].head<3>();
    data.vertex[i] = static_cast<int>(rows[i][3]);
    data.wrench.row(i) = rows[i].tail<6>();
  }
  data.feature_names = {"phi", "beta", "gamma"};
  data.feature_units = {"m", "rad", "rad"};
  data.wrench_names = {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"};
  data.wrench_units = {"N m", "N m", "N m", "N", "N", "N"};
  return data;
}

TEST(MlpSpatialFitSimulation, FootDropConvergesWithBothPgmOrders) {
  FitConfig c;
  c.mlp.hidden_layers = 1;
  c.mlp.width = 16;
  c.mlp.max_epochs = 400;
  c.mlp.final_learning_rate = 1e-3;
  c.mlp.validation_fraction = 0.0;
  c.mlp.output_envelope = MlpOutputEnvelope::Depth;
  const ContactModelFit fit = fitContactModel(sandDataset(), "mlp", c, "synthetic 3-D sand");
  ASSERT_TRUE(fit.mlp && fit.mlp->spatial());
  const TempDir dir;
  const std::string path = dir.file("sand3d_mlp.h5");
  saveContactModelFit(path, fit);
  EXPECT_NE(fittedContactModel(fit)->describe().find("spatial"), std::string::npos) << fittedContactModel(fit)->describe();
  for (const std::string method : {"ne-pgm", "ne-zopgm"}) {
    const SceneConfig scene = repositoryScene(
        "quadruped_foot_drop_sand.json",
        {"contacts.model=" + nlohmann::json{{"type", "mlp"}, {"file", path}}.dump(), "integrator.method=\"" + method + "\"",
         "duration=0.5"});
    Simulation sim = buildSimulation(scene, ContactModelRegistry::withBuiltins());
    int steps = 0;
    while (sim.state().time < 0.5 - 1e-9) {
      ASSERT_TRUE(sim.step().converged) << method << " step " << steps;
      ++steps;
    }
    EXPECT_EQ(steps, 10) << method;
    const Eigen::VectorXd& q = sim.state().q;
    ASSERT_TRUE(q.allFinite()) << method;
    // Dropped at 1 m/s from 3 cm: the sand stops it within a few cm of the surface.
    const Eigen::VectorXd& qd = sim.state().qd;
    EXPECT_LT(qd.cwiseAbs().maxCoeff(), 0.2) << method << ": still moving, qd " << qd.transpose();
  }
}

}  // namespace
}  // namespace nmdp::test
