// Scenes with material patches: the floating-base quadruped trots from rigid ground (the default
// Coulomb model) into a sand pit (the planar RFT model) with the default integrator, and its feet
// sink in the pit only; every bad patch configuration gives one InputError naming the file and key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/input_error.hpp"
#include "contact_models/patched_model.hpp"
#include "multibody/kinematics.hpp"
#include "scene_simulation.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp {
namespace {

using json = nlohmann::json;
using test::inputErrorMessage;
using test::repositoryScene;
using test::sourcePath;

// What a run did: distance, heading, and how deep the feet went on each material.
struct PitRun {
  double forward = 0, lateral = 0, max_yaw = 0;
  double rigid_depth = 0, pit_depth = 0;  // deepest foot point below the surface (m), feet down
  double pit_mean_depth = 0, rigid_mean_depth = 0;  // mean over the loaded foot samples
  int pit_samples = 0, rigid_samples = 0;
  bool converged = true;
};

PitRun runPit(const std::string& scene, const std::vector<std::string>& overrides = {}, bool patched = true) {
  Simulation sim = buildSimulation(repositoryScene(scene, overrides), test::coulombAndRbf());
  EXPECT_EQ(dynamic_cast<const PatchedModel*>(&sim.contactModel()) != nullptr, patched);
  const double pit_start = 1.0, band = 0.05;
  Vec3 p0, rpy;
  sim.basePose(p0, rpy);
  Data data(sim.model());
  PitRun r;
  double pit_sum = 0, rigid_sum = 0;
  for (long i = 0; i < sim.scheduledSteps(); ++i) {
    if (!sim.step().converged) {
      r.converged = false;
      break;
    }
    Vec3 p;
    sim.basePose(p, rpy);
    r.max_yaw = std::max(r.max_yaw, std::abs(rpy.z()));
    data.base_chart = sim.state().base_chart;
    forwardKinematics(sim.model(), data, sim.state().q);
    const std::vector<Vec6>& wrenches = sim.contactWrenches();
    for (size_t c = 0; c < sim.system().contacts.size(); ++c) {
      const ContactPoint& cp = sim.system().contacts[c];
      const Vec3 centre = linkPoint(sim.model(), data, cp.link, cp.offset);
      const double depth = cp.radius - centre.z();  // below the plane z = 0
      const bool loaded = wrenches[c].tail<3>().z() > 1.0;  // N
      if (!loaded) continue;
      if (centre.x() < pit_start - band) {
        r.rigid_depth = std::max(r.rigid_depth, depth);
        rigid_sum += depth;
        ++r.rigid_samples;
      } else if (centre.x() > pit_start + band) {
        r.pit_depth = std::max(r.pit_depth, depth);
        pit_sum += depth;
        ++r.pit_samples;
      }
    }
  }
  Vec3 p;
  sim.basePose(p, rpy);
  r.forward = p.x() - p0.x();
  r.lateral = p.y() - p0.y();
  r.pit_mean_depth = r.pit_samples ? pit_sum / r.pit_samples : 0;
  r.rigid_mean_depth = r.rigid_samples ? rigid_sum / r.rigid_samples : 0;
  std::printf("%s: forward %.3f m, lateral %.3f m, max |yaw| %.3f rad, loaded feet on rigid ground: deepest %.4f m, mean %.4f m (%d samples); "
              "in the pit: deepest %.4f m, mean %.4f m (%d samples)\n",
              scene.c_str(), r.forward, r.lateral, r.max_yaw, r.rigid_depth, r.rigid_mean_depth, r.rigid_samples, r.pit_depth,
              r.pit_mean_depth, r.pit_samples);
  return r;
}

TEST(ScenePatches, QuadrupedTrotsFromRigidGroundIntoTheSandPitAndSinksThereOnly) {
  const PitRun r = runPit("quadruped_trot_sandpit.json");
  ASSERT_TRUE(r.converged);
  EXPECT_GT(r.rigid_samples, 20);
  EXPECT_GT(r.pit_samples, 20);
  // Rigid floor (Coulomb, k = 1e9 N/m³): a foot 1 cm deep would push with k d³ = 1000 N, six times
  // the robot's weight (171 N); a standing foot is 3.5 mm deep (coulomb_model.hpp). The sand
  // yields: its feet go centimetres deep, several times the rigid floor's.
  EXPECT_LT(r.rigid_depth, 0.01);
  EXPECT_GT(r.pit_mean_depth, 3 * r.rigid_mean_depth);
  EXPECT_GT(r.pit_mean_depth, 0.01);
  // The same scene without the pit: every loaded foot stays as shallow as on the rigid part above.
  const PitRun rigid = runPit("quadruped_trot_sandpit.json", {"terrain.patches=[]"}, false);
  ASSERT_TRUE(rigid.converged);
  EXPECT_GT(rigid.pit_samples, 20);
  EXPECT_LT(rigid.pit_depth, 0.01);
}


TEST(ScenePatches, A1TrotsIntoTheSandPitAndSinksThereOnly) {
  if (!std::filesystem::exists(test::sharedPath("robots/a1/urdf/a1.urdf"))) GTEST_SKIP() << "../shared/robots/a1 is absent";
  const PitRun r = runPit("a1_trot_sandpit.json");
  ASSERT_TRUE(r.converged);
  EXPECT_GT(r.pit_samples, 20);
  EXPECT_LT(r.rigid_depth, 0.01);
  EXPECT_GT(r.pit_mean_depth, 3 * r.rigid_mean_depth);
}

// ---- bad input: one InputError naming the scene file and the key ---------------------------------

const char* kSand = "../../data/granular/rft_quadruped_rbf.h5";

json patch(const std::string& name, const json& region, const std::string& file = kSand) {
  return {{"name", name}, {"region", region}, {"model", {{"type", "rbf"}, {"file", file}}}};
}
json rectangle(double x0, double y0, double x1, double y1) {
  return {{"type", "rectangle"}, {"min", {x0, y0}}, {"max", {x1, y1}}};
}
json polygon(const json& points) { return {{"type", "polygon"}, {"points", points}}; }

// The error of building the sandpit scene with terrain.patches replaced (and more overrides).
std::string patchError(const json& patches, std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), "terrain.patches=" + patches.dump());
  return inputErrorMessage([&] { buildSimulation(repositoryScene("quadruped_trot_sandpit.json", overrides), test::coulombAndRbf()); });
}

void expectNames(const std::string& message, const std::string& key, const std::string& what) {
  EXPECT_NE(message.find("quadruped_trot_sandpit.json"), std::string::npos) << message;
  EXPECT_NE(message.find(key), std::string::npos) << message;
  EXPECT_NE(message.find(what), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(ScenePatches, OverlappingPatchesAreRefused) {
  expectNames(patchError(json::array({patch("a", rectangle(1, -1, 3, 1)), patch("b", rectangle(2, 0, 4, 2))})), "terrain.patches[1]",
              "overlaps patch 'a'");
  // One inside the other.
  expectNames(patchError(json::array({patch("a", rectangle(1, -1, 3, 1)), patch("b", {{"type", "circle"}, {"centre", {2, 0}}, {"radius", 0.2}})})),
              "terrain.patches[1]", "overlaps");
  // Apart, but closer than their bands reach (2 · 0.05/√2 = 0.0707 m beyond two rectangles' corners).
  expectNames(patchError(json::array({patch("a", rectangle(1, -1, 3, 1)), patch("b", rectangle(3.05, -1, 4, 1))})), "terrain.patches[1]",
              "closer than the 0.0707");
  // Far enough apart: accepted.
  EXPECT_NO_THROW(buildSimulation(repositoryScene("quadruped_trot_sandpit.json",
                                                  {"terrain.patches=" + json::array({patch("a", rectangle(1, -1, 3, 1)),
                                                                                      patch("b", rectangle(3.08, -1, 4, 1))}).dump()}),
                                  test::coulombAndRbf()));
}

TEST(ScenePatches, BadPolygonsAreRefused) {
  expectNames(patchError(json::array({patch("line", polygon({{1, 0}, {2, 0}, {3, 0}}))})), "terrain.patches[0].region.points", "fold back");
  expectNames(patchError(json::array({patch("bow tie", polygon({{1, 0}, {2, 1}, {2, 0}, {1, 1}}))})), "terrain.patches[0].region.points",
              "intersects itself");
  expectNames(patchError(json::array({patch("two", polygon({{1, 0}, {2, 1}}))})), "terrain.patches[0].region.points", "at least 3 points");
  expectNames(patchError(json::array({patch("x", {{"type", "hexagon"}})})), "terrain.patches[0].region.type", "unknown region type");
  expectNames(patchError(json::array({patch("thin", rectangle(1, 0, 1.02, 1))})), "terrain.patches[0].region.max", "blend_width");
}

TEST(ScenePatches, BadBlendWidthsAndNumbersAreRefused) {
  const json pit = json::array({patch("pit", rectangle(1, -1, 3, 1))});
  expectNames(patchError(pit, {"terrain.blend_width=0"}), "terrain.blend_width", "positive");
  expectNames(patchError(pit, {"terrain.blend_width=-0.1"}), "terrain.blend_width", "positive");
  expectNames(patchError(pit, {"terrain.blend_width=nan"}), "terrain.blend_width", "number");
  expectNames(patchError(json::array({patch("pit", {{"type", "rectangle"}, {"min", {"nan", 0}}, {"max", {3, 1}}})})), "terrain.patches[0].region.min",
              "two numbers");
  expectNames(patchError(json::array({patch("pit", {{"type", "circle"}, {"centre", {2, 0}}, {"radius", "NaN"}})})), "terrain.patches[0].region.radius",
              "number");
}

TEST(ScenePatches, AMissingModelFileIsRefusedWhenTheSceneIsRead) {
  const std::string message = inputErrorMessage([] {
    repositoryScene("quadruped_trot_sandpit.json", {"terrain.patches.0.model.file=no_such_sand.h5"});
  });
  expectNames(message, "terrain.patches[0].model.file", "no_such_sand.h5");
  expectNames(message, "", "not found");
  expectNames(patchError(json::array({{{"name", "pit"}, {"region", rectangle(1, -1, 3, 1)}}})), "terrain.patches[0].model", "missing");
  expectNames(patchError(json::array({patch("pit", rectangle(1, -1, 3, 1), "../quadruped/quadruped.urdf")})), "terrain.patches[0].model", "");
}

// A heightfield of 6 × 4 nodes and its material map.
struct MapFixture {
  test::TempDir dir;
  std::string scene;
  MapFixture(const std::string& map, const json& models) {
    dir.write("heights.csv", "0,0,0,0,0,0\n0,0,0,0,0,0\n0,0,0,0,0,0\n0,0,0,0,0,0\n");
    dir.write("materials.csv", map);
    json s = loadSceneJson(sourcePath("models/scenes/quadruped_trot_sandpit.json"));
    s["robot"]["urdf"] = sourcePath("models/quadruped/quadruped.urdf");
    s["terrain"] = {{"type", "heightfield"}, {"file", "heights.csv"}, {"spacing", 1.0}, {"origin", {-1.5, -1.5}},
                    {"material_map", {{"file", "materials.csv"}, {"models", models}}}};
    s["duration"] = 0.5;
    scene = dir.write("scene.json", s.dump());
  }
  Simulation build() const { return buildSimulation(parseScene(loadSceneJson(scene), scene), test::coulombAndRbf()); }
  std::string error() const { return inputErrorMessage([&] { build(); }); }
};

const json kSandModels = json::array({{{"type", "rbf"}, {"file", sourcePath("data/granular/rft_quadruped_rbf.h5")}}});

TEST(ScenePatches, AMaterialMapOnAHeightfieldRuns) {
  const MapFixture f("0,0,1,1,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n", kSandModels);
  Simulation sim = f.build();
  const auto* patched = dynamic_cast<const PatchedModel*>(&sim.contactModel());
  ASSERT_NE(patched, nullptr);
  EXPECT_EQ(patched->layout().materialCount(), 2);
  for (long i = 0; i < sim.scheduledSteps(); ++i) ASSERT_TRUE(sim.step().converged);
}

TEST(ScenePatches, BadMaterialMapsAreRefused) {
  auto expectMap = [](const MapFixture& f, const std::string& what) {
    const std::string m = f.error();
    EXPECT_NE(m.find("scene.json"), std::string::npos) << m;
    EXPECT_NE(m.find("terrain.material_map"), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  };
  expectMap(MapFixture("0,0,1,1,1,1\n0,0,1,-1,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n", kSandModels), "no material");
  expectMap(MapFixture("0,0,1,1,1,1\n0,0,1,,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n", kSandModels), "materials.csv");
  expectMap(MapFixture("0,0,1,1,1,1\n0,0,1,2,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n", kSandModels), "has no model");
  expectMap(MapFixture("0,0,1,1,1\n0,0,1,1,1\n0,0,1,1,1\n0,0,1,1,1\n", kSandModels), "one material per node");
  expectMap(MapFixture("0,0,1,1,1,1\n0,0,1,1.5,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n", kSandModels), "not an integer");
  expectMap(MapFixture("0,0,1,1,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n0,0,1,1,1,1\n",
                       json::array({{{"type", "rbf"}, {"file", "missing.h5"}}})),
            "models[0].file");
}

}  // namespace
}  // namespace nmdp
