// The 3-D configuration of `nmdp gen-rft` (training/rft3d_config.*) and its samples
// (training/rft3d_samples.*): direction sets, the spatial dataset's layout and order, the planar
// dataset of the same foot equal to the planar RFT of the same plate (torque about the torque
// centre included), the shipped quadruped configuration, the CLI, and bad configurations giving
// one message that names the file and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/input_error.hpp"
#include "common/json_text.hpp"
#include "test_cli.hpp"
#include "training/force_dataset.hpp"
#include "training/rft.hpp"
#include "training/rft3d_config.hpp"
#include "training/rft3d_samples.hpp"

namespace nmdp::test {
namespace {
using json = nlohmann::json;
using Eigen::Vector3d;

TEST(Rft3dSamples, DirectionSets) {
  const std::vector<Vector3d> cube = rft3dCubeDirections();
  ASSERT_EQ(cube.size(), 26u);
  EXPECT_LT((cube[0] - Vector3d(-1, -1, -1).normalized()).norm(), 1e-15);
  EXPECT_LT((cube[1] - Vector3d(-1, -1, 0).normalized()).norm(), 1e-15);  // i slowest, k fastest
  EXPECT_LT((cube[25] - Vector3d(1, 1, 1).normalized()).norm(), 1e-15);
  const std::vector<Vector3d> fib = rft3dFibonacciDirections(40);
  ASSERT_EQ(fib.size(), 40u);
  Vector3d mean = Vector3d::Zero();
  for (const Vector3d& v : fib) {
    EXPECT_NEAR(v.norm(), 1.0, 1e-12);
    mean += v / 40.0;
  }
  EXPECT_LT(mean.norm(), 0.05);  // spread over the sphere
  const std::vector<Vector3d> circle = rft3dCircleDirections(12);
  for (const Vector3d& v : circle) EXPECT_EQ(v.y(), 0.0);
  EXPECT_LT((circle[0] - Vector3d(0, 0, -1)).norm(), 1e-15);
}

TEST(Rft3dSamples, SpatialLayoutAndOrder) {
  RftMedium m;
  m.zeta = 2.71;
  Rft3dFoot foot;  // sphere 0.02
  foot.elements = 24;
  Rft3dGrid grid{{-0.01, -0.03}, {0.0, 0.5}, {-0.4, 0.0, 0.4}, rft3dCubeDirections()};
  const ForceDataset d = rft3dSamples(m, foot, grid);
  validateForceDataset(d, "rft3d");
  ASSERT_EQ(d.features.rows(), 2 * 2 * 3 * 26);
  EXPECT_EQ(d.wrench.cols(), 6);
  EXPECT_EQ(d.feature_names, (std::vector<std::string>{"phi", "beta", "gamma"}));
  EXPECT_EQ(d.wrench_names, (std::vector<std::string>{"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"}));
  EXPECT_EQ(d.wrench_units, (std::vector<std::string>{"N m", "N m", "N m", "N", "N", "N"}));
  // Row (depth 1, beta 0, gamma 2, direction 7): depths outer, then betas, gammas, directions.
  const Eigen::Index row = ((1 * 2 + 0) * 3 + 2) * 26 + 7;
  EXPECT_EQ(d.features.row(row), Eigen::RowVector3d(-0.03, 0.0, 0.4));
  EXPECT_EQ(d.vertex[row], 7);
  const Wrench6 w = rft3dWrench(m, foot, -0.03, 0.0, 0.4, grid.directions[7]);
  EXPECT_EQ(d.wrench(row, 3), w.force.x());
  EXPECT_EQ(d.wrench(row, 1), w.torque.y());
  // Every sample resists its motion (dissipation); only a foot lifted clear of the sand (a sphere
  // pulled up from 1 cm, whose leading upper half is above the surface) meets nothing.
  int loaded = 0;
  for (Eigen::Index r = 0; r < d.features.rows(); ++r) {
    const double power = d.wrench.row(r).tail(3).dot(grid.directions[d.vertex[r]].transpose());
    if (d.wrench.row(r).tail(3).norm() == 0.0) {
      EXPECT_GT(grid.directions[d.vertex[r]].z(), 0.0) << r;
    } else {
      EXPECT_LT(power, 0.0) << r;
      ++loaded;
    }
  }
  EXPECT_GT(loaded, 9 * d.features.rows() / 10);
}

TEST(Rft3dSamples, PlanarOutputEqualsThePlanarRftOfTheSamePlate) {
  // The planar dataset of a 3-D plate of width w at γ = 0 is the planar RFT of the plate of that
  // width: forces and the torque about the torque centre up the leg. Wholly submerged plates, where
  // both integrals are exact, so the two agree to rounding.
  RftMedium m;
  m.zeta = 2.71;
  for (Rft3dShape shape : {Rft3dShape::Plate, Rft3dShape::Blade}) {
    Rft3dFoot foot;
    foot.shape = shape;
    foot.length = 0.05;
    foot.width = 0.03;
    foot.elements = 40;
    RftFoot planar;
    planar.shape = shape == Rft3dShape::Plate ? RftShape::Plate : RftShape::Blade;
    planar.length = 0.05;
    planar.width = 0.03;
    planar.elements = 40;
    planar.torque_centre = 0.04;
    const Rft3dGrid grid{{-0.06, -0.1}, {-0.5, 0.0, 0.6}, {0.0}, rft3dCircleDirections(12)};  // submerged: exact
    const ForceDataset d3 = rft3dPlanarSamples(m, foot, grid, 0.04);
    const ForceDataset d2 = rftSamples(m, planar, {grid.depths, grid.betas, rftCircleDirections(12)});
    validateForceDataset(d3, "planar");
    ASSERT_EQ(d3.wrench.rows(), d2.wrench.rows());
    EXPECT_EQ(d3.features, d2.features);
    EXPECT_EQ(d3.vertex, d2.vertex);
    EXPECT_EQ(d3.wrench_names, d2.wrench_names);
    EXPECT_EQ(d3.torque_centre, d2.torque_centre);
    const double scale = d2.wrench.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 1.0);
    EXPECT_LT((d3.wrench - d2.wrench).cwiseAbs().maxCoeff(), 1e-9 * scale) << rft3dShapeName(shape);
    ASSERT_GT(d2.wrench.col(2).cwiseAbs().maxCoeff(), 0.01);  // the torque is compared, not zeros
  }
  Rft3dFoot sphere;
  EXPECT_THROW(rft3dPlanarSamples(m, sphere, {{-0.01}, {0.0}, {0.0}, {Vector3d(0, 1, 0)}}, 0.0), std::invalid_argument);
}

void expectConfigError(const json& config, const std::vector<std::string>& expect) {
  try {
    readRft3dConfig(config, "rft3d.json");
    ADD_FAILURE() << "accepted: " << config.dump();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("rft3d.json: ", 0), 0u) << what;
    for (const std::string& s : expect) EXPECT_NE(what.find(s), std::string::npos) << "missing '" << s << "' in: " << what;
  }
}

TEST(Rft3dConfig, DefaultsAndBadKeys) {
  const Rft3dConfig c = readRft3dConfig({{"dimension", 3}}, "defaults");
  EXPECT_EQ(c.foot.shape, Rft3dShape::Sphere);
  EXPECT_EQ(c.foot.radius, 0.02);
  EXPECT_EQ(c.output, Rft3dOutput::Spatial);
  EXPECT_EQ(c.grid.directions.size(), 26u);
  EXPECT_EQ(c.grid.gammas.size(), 3u);
  EXPECT_EQ(c.resolved["grid"]["directions"]["type"], "cube");
  const Rft3dConfig p = readRft3dConfig({{"dimension", 3}, {"output", "planar"}}, "defaults");
  EXPECT_EQ(p.grid.gammas, std::vector<double>{0.0});
  EXPECT_EQ(p.resolved["grid"]["directions"]["type"], "circle");

  EXPECT_FALSE(isRft3dConfig(json::object(), "x"));
  EXPECT_FALSE(isRft3dConfig({{"dimension", 2}}, "x"));
  EXPECT_TRUE(isRft3dConfig({{"dimension", 3}}, "x"));
  EXPECT_THROW(isRft3dConfig({{"dimension", "3"}}, "x"), InputError);

  const json d3 = {{"dimension", 3}};
  auto with = [&](const json& extra) {
    json c = d3;
    c.update(extra);
    return c;
  };
  expectConfigError({{"dimension", 4}}, {"dimension", "2 (planar) or 3"});
  expectConfigError(with({{"outptu", "planar"}}), {"outptu", "did you mean 'output'"});
  expectConfigError(with({{"output", "plane"}}), {"output", "did you mean 'planar'"});
  expectConfigError(with({{"foot", {{"shape", "sphre"}}}}), {"foot.shape", "did you mean 'sphere'"});
  expectConfigError(with({{"foot", {{"shape", "plate"}, {"length", 0.05}}}}), {"foot.width", "required"});
  expectConfigError(with({{"foot", {{"shape", "sphere"}, {"length", 0.05}}}}), {"foot.length", "radius"});
  expectConfigError(with({{"foot", {{"radius", 0}}}}), {"foot.radius"});
  expectConfigError(with({{"foot", {{"elements", 0}}}}), {"foot.elements"});
  expectConfigError(with({{"foot", {{"torque_centre", 0.02}}}}), {"foot.torque_centre", "planar output only"});
  expectConfigError(with({{"medium", {{"zeta", -1}}}}), {"medium.zeta"});
  expectConfigError(with({{"grid", {{"gammas", {0.1, 0.1}}}}}), {"grid.gammas", "twice"});
  expectConfigError(with({{"grid", {{"betas", {2.0}}}}}), {"grid.betas", "2.0"});
  expectConfigError(with({{"grid", {{"depths", {0.01}}}}}), {"grid.depths"});
  expectConfigError(with({{"grid", {{"directions", {{"type", "cub"}}}}}}), {"grid.directions.type", "did you mean 'cube'"});
  expectConfigError(with({{"grid", {{"directions", {{"type", "fibonacci"}}}}}}), {"grid.directions.count", "required"});
  expectConfigError(with({{"grid", {{"directions", {{"type", "cube"}, {"count", 3}}}}}}), {"grid.directions.count"});
  expectConfigError(with({{"grid", {{"directions", {{"type", "list"}, {"vectors", {{1, 0}}}}}}}}),
                    {"grid.directions.vectors[0]", "[x, y, z]"});
  expectConfigError(with({{"grid", {{"directions", {{"type", "list"}, {"vectors", {{0, 0, 0}}}}}}}}),
                    {"grid.directions.vectors[0]", "zero"});
  expectConfigError(with({{"output", "planar"}, {"grid", {{"gammas", {0.0}}}}}), {"grid.gammas", "planar"});
  expectConfigError(with({{"output", "planar"}, {"grid", {{"directions", {{"type", "cube"}}}}}}),
                    {"grid.directions.type", "x-z plane"});
  expectConfigError(with({{"output", "planar"}, {"grid", {{"directions", {{"type", "list"}, {"vectors", {{1, 0.5, 0}}}}}}}}),
                    {"grid.directions.vectors[0]", "y = 0"});
  expectConfigError(with({{"foot", {{"elements", 10000}}}}), {"grid", "more work"});
}

TEST(Rft3dConfig, TheShippedQuadrupedConfigurationReads) {
  const std::string path = std::string(NMDP_SOURCE_DIR) + "/data/granular/rft3d_quadruped_foot.json";
  const Rft3dConfig c = readRft3dConfig(loadJsonFile(path, "the 3-D RFT configuration"), path);
  EXPECT_EQ(c.foot.shape, Rft3dShape::Sphere);
  EXPECT_EQ(c.foot.radius, 0.02);
  EXPECT_EQ(c.medium.zeta, 2.71);
  EXPECT_EQ(c.grid.depths.size(), 9u);
  EXPECT_EQ(c.grid.betas, (std::vector<double>{-0.6, 0.0, 0.6}));
  EXPECT_EQ(c.grid.gammas, (std::vector<double>{-0.6, 0.0, 0.6}));
  EXPECT_EQ(c.grid.directions.size(), 26u);
}

TEST(GenRftCli, WritesSpatialAndPlanarDatasetsFromA3dConfiguration) {
  const TempDir dir;
  const json config = {{"dimension", 3},
                       {"medium", {{"zeta", 2.71}}},
                       {"foot", {{"shape", "sphere"}, {"radius", 0.02}, {"elements", 16}}},
                       {"grid", {{"depths", {-0.01, -0.02}}, {"betas", {0.0, 0.3}}, {"gammas", {0.0, 0.2}}}}};
  const std::string path = dir.write("rft3d.json", config.dump(2)), out = dir.file("spatial.h5");
  const CliResult r = runNmdp({"gen-rft", "--config", path, "--out", out}, dir);
  ASSERT_TRUE(r.exited);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("208 wrench samples (8 points x 26 directions)"), std::string::npos) << r.out;
  const ForceDataset d = readForceDataset(out);
  EXPECT_EQ(d.wrench.cols(), 6);
  EXPECT_EQ(d.feature_names, (std::vector<std::string>{"phi", "beta", "gamma"}));
  const ForceDataset direct = rft3dConfigSamples(readRft3dConfig(config, "x"));
  EXPECT_EQ(d.wrench, direct.wrench);
  EXPECT_NE(d.source.find("\"dimension\":3"), std::string::npos) << d.source;

  json planar = config;
  planar["output"] = "planar";
  planar["grid"].erase("gammas");
  planar["foot"]["torque_centre"] = 0.02;
  const std::string folder = dir.file("planar");
  const CliResult r2 = runNmdp({"gen-rft", "--config", planar.dump(), "--out", folder}, dir);
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const ForceDataset imported = importSandSamplesCsv(folder);
  EXPECT_EQ(imported.wrench.cols(), 3);
  EXPECT_EQ(imported.features.rows(), 2 * 2 * 26);
  ASSERT_TRUE(imported.torque_centre.has_value());
  EXPECT_EQ(*imported.torque_centre, 0.02);

  // A spatial dataset goes to .h5 only; a bad key is one line naming the file and key.
  const CliResult bad = runNmdp({"gen-rft", "--config", path, "--out", dir.file("folder")}, dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find(".h5"), std::string::npos) << bad.err;
  const std::string typo = dir.write("typo.json", R"({"dimension": 3, "grid": {"gamas": [0]}})");
  const CliResult bad2 = runNmdp({"gen-rft", "--config", typo, "--out", dir.file("t.h5")}, dir);
  EXPECT_EQ(bad2.exit_code, 1);
  ASSERT_NO_FATAL_FAILURE(expectOneLine(bad2.err, "stderr"));
  EXPECT_NE(bad2.err.find(typo), std::string::npos) << bad2.err;
  EXPECT_NE(bad2.err.find("grid.gamas"), std::string::npos) << bad2.err;
  EXPECT_NE(bad2.err.find("did you mean 'gammas'"), std::string::npos) << bad2.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("t.h5")));
}

}  // namespace
}  // namespace nmdp::test
