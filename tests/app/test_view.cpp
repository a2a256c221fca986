// What `nmdp view` puts into its page, read back from the HTML: the frames and times of the run,
// the link poses, foot points and forces exactly as the file stores them (in float32), the joints,
// the terrain sampled at the grid's nodes, the sand patch's material, the series, and two runs
// overlaid. The page's marker lets a second `nmdp view` replace it. Fallbacks for what a run file
// lacks: test_view_fallbacks.cpp; bad input and --serve: test_view_errors.cpp.
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/hdf5_file.hpp"
#include "run_files.hpp"
#include "simulate_run.hpp"
#include "terrain/terrain_factory.hpp"
#include "test_cli.hpp"
#include "test_support.hpp"
#include "view_page.hpp"

namespace nmdp::test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// A hill under the trot's path, so that the grid's heights and the normals are not those of a plane.
const char* const kHillTerrain =
    R"(terrain={"type": "procedural", "hills": [{"centre": [0.3, 0.1], "height": 0.03, "width": 0.25}]})";

// The values of `dataset`'s first `rows` rows, rounded to float32 as the page stores them.
std::vector<double> storedAsFloat(const h5::File& file, const std::string& dataset, long rows) {
  const h5::File::Array a = file.readArray(dataset);
  size_t width = 1;
  for (size_t k = 1; k < a.shape.size(); ++k) width *= static_cast<size_t>(a.shape[k]);
  std::vector<double> out;
  for (size_t k = 0; k < static_cast<size_t>(rows) * width; ++k) out.push_back(static_cast<float>(a.values[k]));
  return out;
}

struct Page {
  std::string html;
  json payload;
};

Page readPage(const std::string& path) {
  Page p;
  p.html = readText(path);
  p.payload = payloadOf(p.html);
  return p;
}

TEST(ViewCli, PageHoldsTheRunAsItsFileStoresIt) {
  TempDir dir;
  useStandInBundle(dir);
  const std::string run = dir.file("trot.h5");
  runComplete({sceneFile("quadruped_trot_sand3d.json"), "--set", "duration=0.5", "--set", kHillTerrain, "--quiet"}, dir, run);
  const CliResult r = runView({run}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page_path = dir.file("trot.html");  // the default: beside the run
  EXPECT_EQ(r.out, "wrote " + page_path + " (1 run, 11 frames): open it in a browser, e.g. chromium " + page_path + "\n");
  const Page page = readPage(page_path);
  EXPECT_EQ(page.html.rfind("<!doctype html>", 0), 0u);
  EXPECT_NE(page.html.find("<title>nmdp view: loading</title>"), std::string::npos);
  EXPECT_NE(page.html.find("<meta name=\"nmdp-output\" content=\"view\">"), std::string::npos);
  EXPECT_NE(page.html.find("\"<\\/script>\" must not end the element"), std::string::npos) << "the script is inlined, escaped";

  const json& p = page.payload;
  EXPECT_EQ(p["format"], "nmdp-view");
  EXPECT_EQ(p["version"], 1);
  EXPECT_EQ(p["generator"].get<std::string>().rfind("nmdp ", 0), 0u);
  ASSERT_EQ(p["runs"].size(), 1u);
  const json& R = p["runs"][0];
  const h5::File file = h5::File::openRead(run);
  const long N = completeRows(run);
  EXPECT_EQ(R["frames"], N);
  EXPECT_EQ(R["status"], "complete");
  EXPECT_EQ(R["file"], fs::absolute(run).lexically_normal().string());
  EXPECT_NE(R["label"].get<std::string>().find("trot.h5: ne-pgm, dt = 50 ms, rbf"), std::string::npos) << R["label"];

  // Time exactly (float64), the base and joints as float32 of the file's values.
  const PayloadArray time = decodeArray(R["time"]);
  EXPECT_EQ(time.dtype, "float64");
  const Eigen::MatrixXd stored_time = file.readMatrix("/time");
  ASSERT_EQ(time.values.size(), static_cast<size_t>(N));
  for (long i = 0; i < N; ++i) EXPECT_EQ(time.values[i], stored_time(i, 0)) << "row " << i;
  EXPECT_EQ(decodeArray(R["base"]["position"]).values, storedAsFloat(file, "/base/position", N));
  const std::vector<std::string> dofs = file.readStrings("/joint_names");
  EXPECT_EQ(R["joints"]["names"].get<std::vector<std::string>>(), std::vector<std::string>(dofs.begin() + 6, dofs.end()));
  const Eigen::MatrixXd q = file.readMatrix("/q");
  const PayloadArray joints = decodeArray(R["joints"]["q"]);
  ASSERT_EQ(joints.shape, (std::vector<size_t>{static_cast<size_t>(N), 12}));
  for (long i = 0; i < N; ++i)
    for (int j = 0; j < 12; ++j) EXPECT_EQ(joints.values[i * 12 + j], static_cast<float>(q(i, 6 + j)));

  // Forces: wrench[..., 3:6]; normal force: the force along the terrain's normal at the foot point.
  const std::vector<std::string> contacts = file.readStrings("/contacts/names");
  const size_t C = contacts.size();
  EXPECT_EQ(R["contacts"]["names"].get<std::vector<std::string>>(), contacts);
  const h5::File::Array wrench = file.readArray("/contacts/wrench");
  const PayloadArray forces = decodeArray(R["contacts"]["forces"]);
  ASSERT_EQ(forces.shape, (std::vector<size_t>{static_cast<size_t>(N), C, 3}));
  for (size_t k = 0; k < static_cast<size_t>(N) * C; ++k)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(forces.values[3 * k + a], static_cast<float>(wrench.values[6 * k + 3 + a]));

  const json terrain_config = json::parse(R"({"type": "procedural", "hills": [{"centre": [0.3, 0.1], "height": 0.03, "width": 0.25}]})");
  const std::unique_ptr<Terrain> terrain = makeTerrain(terrain_config, ConfigContext{"test", ""});
  // The terrain: heights at the nodes are the hill's (vertical distance: h = −φ(x, y, 0)); the grid
  // covers the trunk's path and the feet with the margin.
  const json& T = p["terrain"];
  ASSERT_TRUE(T.is_object());
  const PayloadArray heights = decodeArray(T["heights"]);
  const double x0 = T["origin"][0], y0 = T["origin"][1], dx = T["spacing"][0], dy = T["spacing"][1];
  const size_t nx = T["size"][0], ny = T["size"][1];
  EXPECT_LE(nx, 256u);
  EXPECT_LE(ny, 256u);
  EXPECT_GE(dx, 0.01 - 1e-12);
  ASSERT_EQ(heights.shape, (std::vector<size_t>{ny, nx}));
  double highest = 0;
  for (size_t j = 0; j < ny; ++j)
    for (size_t i = 0; i < nx; ++i) {
      TerrainQuery tq;
      terrain->query(Vec3(x0 + i * dx, y0 + j * dy, 0.0), tq, false);
      EXPECT_NEAR(heights.values[j * nx + i], -tq.distance, 1e-6) << "node " << i << ", " << j;
      highest = std::max(highest, -tq.distance);
    }
  EXPECT_GT(highest, 0.02) << "the grid missed the hill";
  const Eigen::MatrixXd base = file.readMatrix("/base/position");
  for (long i = 0; i < N; ++i) {
    EXPECT_LE(x0, base(i, 0) - 1.0 + 1e-9);
    EXPECT_GE(x0 + (nx - 1) * dx, base(i, 0) + 1.0 - 1e-9);
    EXPECT_LE(y0, base(i, 1) - 1.0 + 1e-9);
    EXPECT_GE(y0 + (ny - 1) * dy, base(i, 1) + 1.0 - 1e-9);
  }

  // Series: torso height over the hill below the trunk, distance along the initial heading (+x here).
  const PayloadArray height = decodeArray(R["series"]["torso_height"]), forward = decodeArray(R["series"]["forward_distance"]);
  for (long i = 0; i < N; ++i) {
    TerrainQuery tq;
    terrain->query(Vec3(base(i, 0), base(i, 1), 0.0), tq, false);
    EXPECT_NEAR(height.values[i], base(i, 2) + tq.distance, 1e-5) << "row " << i;
    EXPECT_NEAR(forward.values[i], base(i, 0) - base(0, 0), 1e-5) << "row " << i;
  }

  // A second view may replace the page it wrote (the marker), and writes the same page.
  const CliResult again = runView({run, "--quiet"}, dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, "");
  EXPECT_EQ(readText(page_path), page.html);

  // The datasets engineer A's writer adds: foot points and link poses, as stored.
  ASSERT_TRUE(file.exists("/contacts/foot_point")) << "the output file has no /contacts/foot_point (engineer A's part)";
  EXPECT_EQ(decodeArray(R["contacts"]["points"]).values, storedAsFloat(file, "/contacts/foot_point", N));
  const h5::File::Array feet = file.readArray("/contacts/foot_point");
  const PayloadArray normal = decodeArray(R["contacts"]["normal_force"]);
  double largest = 0;
  for (size_t k = 0; k < static_cast<size_t>(N) * C; ++k) {
    TerrainQuery tq;
    terrain->query(Vec3(feet.values[3 * k], feet.values[3 * k + 1], feet.values[3 * k + 2]), tq, false);
    const double expected = tq.normal.dot(Vec3(wrench.values[6 * k + 3], wrench.values[6 * k + 4], wrench.values[6 * k + 5]));
    EXPECT_NEAR(normal.values[k], expected, 1e-6 * std::abs(expected) + 1e-4) << "row " << k / C << " contact " << k % C;
    largest = std::max(largest, std::abs(expected));
  }
  EXPECT_GT(largest, 10.0) << "no foot pressed on the ground: the normal-force check saw nothing";

  // Link poses: every URDF link, position and quaternion as /links/* stores them.
  ASSERT_TRUE(file.exists("/links/position")) << "the output file has no /links poses (engineer A's part)";
  const std::vector<std::string> link_names = file.readStrings("/links/names");
  ASSERT_EQ(R["links"].size(), link_names.size());
  for (size_t l = 0; l < link_names.size(); ++l) EXPECT_EQ(R["links"][l]["name"], link_names[l]);
  const PayloadArray poses = decodeArray(R["link_poses"]);
  const size_t L = link_names.size();
  ASSERT_EQ(poses.shape, (std::vector<size_t>{static_cast<size_t>(N), L, 7}));
  const std::vector<double> position = storedAsFloat(file, "/links/position", N), quaternion = storedAsFloat(file, "/links/quaternion", N);
  for (size_t k = 0; k < static_cast<size_t>(N) * L; ++k) {
    for (int a = 0; a < 3; ++a) EXPECT_EQ(poses.values[7 * k + a], position[3 * k + a]);
    for (int a = 0; a < 4; ++a) EXPECT_EQ(poses.values[7 * k + 3 + a], quaternion[4 * k + a]);
  }
}

TEST(ViewCli, SandPatchIsItsOwnMaterial) {
  TempDir dir;
  useStandInBundle(dir);
  const std::string run = dir.file("pit.h5");
  runComplete({sceneFile("quadruped_trot_sandpit.json"), "--set", "duration=0.1", "--set", "robot.initial.base_position=[0.6, 0]", "--quiet"},
              dir, run);
  const CliResult r = runView({run, "--out", dir.file("pit_page.html"), "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json T = payloadOf(readText(dir.file("pit_page.html")))["terrain"];
  ASSERT_EQ(T["materials"].size(), 2u);
  EXPECT_EQ(T["materials"][0]["name"], "rigid");
  EXPECT_EQ(T["materials"][1]["name"], "sand pit");
  EXPECT_NE(T["materials"][0]["color"], T["materials"][1]["color"]);
  const PayloadArray material = decodeArray(T["material"]);
  EXPECT_EQ(material.dtype, "uint8");
  const double x0 = T["origin"][0], y0 = T["origin"][1], dx = T["spacing"][0], dy = T["spacing"][1];
  const size_t nx = T["size"][0], ny = T["size"][1];
  // The pit is [1, 8] x [-1.5, 1.5] with a 5 cm blending band: sand inside it, rigid outside it.
  int sand = 0, rigid = 0;
  for (size_t j = 0; j < ny; ++j)
    for (size_t i = 0; i < nx; ++i) {
      const double x = x0 + i * dx, y = y0 + j * dy;
      const bool inside = x > 1.03 && x < 7.97 && y > -1.47 && y < 1.47;
      const bool outside = x < 0.97 || x > 8.03 || y < -1.53 || y > 1.53;
      const double m = material.values[j * nx + i];
      if (inside) {
        EXPECT_EQ(m, 1) << "(" << x << ", " << y << ") is in the pit";
      }
      if (outside) {
        EXPECT_EQ(m, 0) << "(" << x << ", " << y << ") is outside the pit";
      }
      sand += inside;
      rigid += outside;
    }
  EXPECT_GT(sand, 100) << "the grid (1 m around the path) reaches into the pit";
  EXPECT_GT(rigid, 100);
}

TEST(ViewCli, TwoRunsOverlaidInOnePage) {
  TempDir dir;
  useStandInBundle(dir);
  const std::string fine = dir.file("fine.h5"), coarse = dir.file("coarse.h5");
  runComplete({trotScene(), "--set", "duration=0.2", "--set", "integrator.dt=0.01", "--quiet"}, dir, fine);
  runComplete({trotScene(), "--set", "duration=0.2", "--set", "integrator.dt=0.05", "--quiet"}, dir, coarse);
  const std::string page = dir.file("both.html");
  const CliResult r = runView({fine, coarse, "--out", page}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "wrote " + page + " (2 runs, 21 frames): open it in a browser, e.g. chromium " + page + "\n");
  const json p = payloadOf(readText(page));
  ASSERT_EQ(p["runs"].size(), 2u);
  EXPECT_EQ(p["runs"][0]["frames"], 21);
  EXPECT_EQ(p["runs"][1]["frames"], 5);
  EXPECT_NE(p["runs"][0]["label"].get<std::string>().find("dt = 10 ms"), std::string::npos) << p["runs"][0]["label"];
  EXPECT_NE(p["runs"][1]["label"].get<std::string>().find("dt = 50 ms"), std::string::npos) << p["runs"][1]["label"];
  EXPECT_EQ(decodeArray(p["runs"][1]["time"]).values.back(), 0.2);
}

}  // namespace
}  // namespace nmdp::test
