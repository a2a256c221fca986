// What the output file stores per row, checked against the simulation that wrote it: every dataset
// describes itself (units, description); the torques are the PD law of the stored state, targets and
// the config's gains; foot points, links and the base quaternion are the forward kinematics of the
// stored q and chart; the energies match closed forms for a falling and a resting box; /rows and
// /steps count rows and time steps; /terrain/description rebuilds the terrain without its file.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>

#include "io/hdf5_file.hpp"
#include "multibody/kinematics.hpp"
#include "run_files.hpp"
#include "scene_simulation.hpp"
#include "sim/trajectory_layout.hpp"
#include "sim/trajectory_recorder.hpp"
#include "solver/contact_kinematics.hpp"
#include "terrain/terrain_factory.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

// Runs the simulation for its scheduled steps into `path` as `nmdp simulate` does.
void record(Simulation& sim, const std::string& path) {
  TrajectoryWriter writer(path, trajectoryLayout(sim));
  TrajectoryRecorder recorder(writer, sim);
  sim.addObserver([&](const Simulation& s, const StepStats& stats) { recorder.observe(s, stats); });
  recorder.start();
  for (long i = 0; i < sim.scheduledSteps(); ++i) ASSERT_TRUE(sim.step().converged) << "step " << i;
  recorder.finish();
  writer.finish();
}

// Row i of a 3-D dataset (N × a × b) as an a × b matrix.
Eigen::MatrixXd slab(const Dataset& d, long i) {
  const long a = static_cast<long>(d.dims[1]), b = static_cast<long>(d.dims[2]);
  Eigen::MatrixXd m(a, b);
  for (long r = 0; r < a; ++r)
    for (long c = 0; c < b; ++c) m(r, c) = d.values[static_cast<size_t>((i * a + r) * b + c)];
  return m;
}

Mat3 rotationOf(const Eigen::RowVectorXd& xyzw) {
  return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized().toRotationMatrix();
}

TEST(TrajectoryContents, EveryDatasetHasUnitsAndADescription) {
  TempDir dir;
  const std::string path = dir.file("trot.h5");
  Simulation sim = repositorySimulation("quadruped_trot_flat.json", {"duration=0.2"});
  record(sim, path);
  const h5::File file = h5::File::openRead(path);
  const std::set<std::string> names = datasetNames(path);
  EXPECT_GT(names.size(), 30u);
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(file.hasAttribute(name, "units"));
    ASSERT_TRUE(file.hasAttribute(name, "description"));
    EXPECT_FALSE(file.readStringAttribute(name, "units").empty());
    EXPECT_GT(file.readStringAttribute(name, "description").size(), 10u);
  }
  EXPECT_EQ(file.readStringAttribute("/base/position", "frame"), "world");
  EXPECT_EQ(file.readStringAttribute("/contacts/wrench", "units"), "N m, N m, N m, N, N, N");
  const std::vector<std::string> q_units = file.readStrings("/joint_names");
  EXPECT_EQ(q_units[3], "base_chart_x") << "a floating base's angles are chart angles, named so";
  EXPECT_EQ(file.readStringAttribute("/q", "units").substr(0, 15), "m, m, m, rad, r");
}

// The trot of the quadruped: the stored torques are the PD law of the stored q, q̇, targets and gains.
TEST(TrajectoryContents, TorquesAreThePdLawOfTheStoredStateTargetsAndGains) {
  TempDir dir;
  const std::string path = dir.file("trot.h5");
  Simulation sim = repositorySimulation("quadruped_trot_flat.json", {"duration=0.5"});
  const PdGains gains = sim.system().gains;
  record(sim, path);
  const h5::File file = h5::File::openRead(path);
  const Eigen::MatrixXd q = file.readMatrix("/q"), qd = file.readMatrix("/qdot");
  const Eigen::MatrixXd q_target = file.readMatrix("/joints/q_target"), qd_target = file.readMatrix("/joints/qdot_target");
  const Eigen::MatrixXd torque = file.readMatrix("/joints/torque"), pd = file.readMatrix("/joints/torque_pd");
  const Eigen::MatrixXd ff = file.readMatrix("/joints/torque_feedforward");
  ASSERT_EQ(q.rows(), 11);
  double largest = 0.0;
  for (long i = 0; i < q.rows(); ++i)
    for (long j = 0; j < q.cols(); ++j) {
      if (sim.model().bodies[static_cast<size_t>(j)].is_base) {
        EXPECT_TRUE(std::isnan(q_target(i, j)) && std::isnan(qd_target(i, j))) << "row " << i << " coordinate " << j;
        EXPECT_EQ(torque(i, j), 0.0);
        continue;
      }
      const double law = -gains.kp[j] * (q(i, j) - q_target(i, j)) - gains.kd[j] * (qd(i, j) - qd_target(i, j));
      // The same expression in the same order: equal up to the rounding of the reader's copy (none).
      EXPECT_NEAR(pd(i, j), law, 1e-12 * (1.0 + std::abs(law))) << "row " << i << " coordinate " << j;
      EXPECT_EQ(ff(i, j), gains.tau_ff[j]);
      EXPECT_NEAR(torque(i, j), pd(i, j) + ff(i, j), 1e-12 * (1.0 + std::abs(torque(i, j))));
      largest = std::max(largest, std::abs(torque(i, j)));
    }
  EXPECT_GT(largest, 1.0) << "a trot applies torques of newton metres";
  // The gains the law used are the ones the resolved config records.
  const nlohmann::json config = configOf(path);
  ASSERT_TRUE(config["controller"].contains("kp")) << config["controller"].dump();
}

// Foot points, link poses and the base quaternion: forward kinematics of the stored q and chart.
TEST(TrajectoryContents, PosesAreTheKinematicsOfTheStoredCoordinatesAndChart) {
  TempDir dir;
  const std::string path = dir.file("trot.h5");
  Simulation sim = repositorySimulation("quadruped_trot_flat.json", {"duration=0.5"});
  record(sim, path);
  const h5::File file = h5::File::openRead(path);
  const Eigen::MatrixXd q = file.readMatrix("/q"), chart = file.readMatrix("/base/chart");
  const Eigen::MatrixXd base_quaternion = file.readMatrix("/base/quaternion"), rpy = file.readMatrix("/base/rpy");
  const Dataset foot = readDataset(path, "/contacts/foot_point"), link_position = readDataset(path, "/links/position");
  const Dataset link_quaternion = readDataset(path, "/links/quaternion");
  const std::vector<std::string> link_names = file.readStrings("/links/names");
  const Model& model = sim.model();
  ASSERT_EQ(link_names.size(), model.links.size());
  Data data(model);
  for (long i = 0; i < q.rows(); ++i) {
    data.base_chart = rotationOf(chart.row(i));
    forwardKinematics(model, data, Eigen::VectorXd(q.row(i).transpose()));
    const Eigen::MatrixXd feet = slab(foot, i);
    for (size_t c = 0; c < sim.system().contacts.size(); ++c) {
      ContactFrame frame;
      contactFrame(model, data, sim.system().contacts[c], frame);
      const Vec3 stored = feet.row(static_cast<long>(c)).transpose();
      EXPECT_LE((stored - frame.position).norm(), 1e-12 * frame.position.norm()) << "row " << i << " contact " << c;
    }
    const Eigen::MatrixXd positions = slab(link_position, i), quaternions = slab(link_quaternion, i);
    for (int l : {0, model.linkIndex("FL_calf"), static_cast<int>(model.links.size()) - 1}) {
      ASSERT_GE(l, 0);
      Mat3 R;
      Vec3 p;
      linkPose(model, data, l, R, p);
      EXPECT_LE((Vec3(positions.row(l).transpose()) - p).norm(), 1e-12 * (1.0 + p.norm())) << link_names[l];
      EXPECT_LE((rotationOf(quaternions.row(l)) - R).norm(), 1e-12) << link_names[l];
    }
    // /base/quaternion is the rotation /base/rpy describes (ZYX).
    const Mat3 from_rpy = (Eigen::AngleAxisd(rpy(i, 2), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy(i, 1), Vec3::UnitY()) *
                           Eigen::AngleAxisd(rpy(i, 0), Vec3::UnitX()))
                              .toRotationMatrix();
    EXPECT_LE((rotationOf(base_quaternion.row(i)) - from_rpy).norm(), 1e-12) << "row " << i;
  }
}

// A scene of the 1 kg box (tests/data/box.urdf) with its four bottom corners as contacts, or none.
std::string boxScene(const TempDir& dir, double height, double duration, bool contacts = true) {
  nlohmann::json points = nlohmann::json::array();
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      if (contacts) points.push_back({{"link", "box"}, {"offset", {0.1 * sx, 0.1 * sy, -0.05}}, {"radius", 0.0}});
  const nlohmann::json scene = {
      {"robot", {{"urdf", sourcePath("tests/data/box.urdf")}, {"initial", {{"base_position", {0.0, 0.0, height}}}}}},
      {"contacts", {{"points", points}}},
      {"integrator", {{"dt", 0.001}}},
      {"duration", duration}};
  return dir.write("box.json", scene.dump());
}

// Free fall from 10 m without contacts: kinetic = ½ m g² t², and kinetic + potential constant up to
// backward Euler's known drift.
TEST(TrajectoryContents, EnergiesOfAFallingBoxMatchTheClosedForm) {
  TempDir dir;
  const std::string scene_path = boxScene(dir, 10.0, 0.3, false);
  Simulation sim = buildSimulation(parseScene(loadSceneJson(scene_path), scene_path), coulombAndRbf());
  record(sim, dir.file("fall.h5"));
  const h5::File file = h5::File::openRead(dir.file("fall.h5"));
  const Eigen::MatrixXd t = file.readMatrix("/time"), kinetic = file.readMatrix("/energy/kinetic");
  const Eigen::MatrixXd potential = file.readMatrix("/energy/potential"), position = file.readMatrix("/base/position");
  const double m = 1.0, g = 9.81;
  ASSERT_EQ(t.rows(), 301);
  const double total0 = kinetic(0, 0) + potential(0, 0);
  EXPECT_NEAR(potential(0, 0), m * g * 10.0, 1e-9) << "zero with the centre of mass at z = 0";
  const double h = 0.001;
  for (long i = 0; i < t.rows(); ++i) {
    // Backward Euler (order 1): v_n = −g t_n exactly, so K is exact; z_n = z_0 − g h² n (n + 1)/2, so
    // K + P drifts by exactly −½ m g² h t_n (0.0144 J at 0.3 s). Tolerances: rounding only.
    EXPECT_NEAR(kinetic(i, 0), 0.5 * m * g * g * t(i, 0) * t(i, 0), 1e-9 * (1.0 + kinetic(i, 0))) << "row " << i;
    EXPECT_NEAR(kinetic(i, 0) + potential(i, 0) - total0, -0.5 * m * g * g * h * t(i, 0), 1e-9 * total0) << "row " << i;
    EXPECT_NEAR(potential(i, 0), m * g * position(i, 2), 1e-9) << "row " << i;
  }
}

// At rest on the ground: kinetic ≈ 0 and potential = m g z of the centre of mass.
TEST(TrajectoryContents, EnergiesOfARestingBox) {
  TempDir dir;
  const std::string scene_path = boxScene(dir, 0.05, 1.0);
  Simulation sim = buildSimulation(parseScene(loadSceneJson(scene_path), scene_path), coulombAndRbf());
  record(sim, dir.file("rest.h5"));
  const h5::File file = h5::File::openRead(dir.file("rest.h5"));
  const Eigen::MatrixXd kinetic = file.readMatrix("/energy/kinetic"), potential = file.readMatrix("/energy/potential");
  const Eigen::MatrixXd position = file.readMatrix("/base/position");
  const long last = kinetic.rows() - 1;
  EXPECT_LT(kinetic(last, 0), 1e-6) << "J: settled";
  EXPECT_NEAR(potential(last, 0), 9.81 * position(last, 2), 1e-9);
  EXPECT_NEAR(position(last, 2), 0.05, 5e-3) << "resting on its bottom face";
}

// /rows counts rows (the t = 0 row included), /steps the time steps they cover.
TEST(TrajectoryContents, RowsCountRowsAndStepsCountTimeSteps) {
  TempDir dir;
  const std::string scene_path = boxScene(dir, 10.0, 1.0);
  for (int every : {1, 7}) {
    SCOPED_TRACE(every);
    nlohmann::json scene = loadSceneJson(scene_path);
    scene["output"] = {{"every", every}};
    Simulation sim = buildSimulation(parseScene(scene, scene_path), coulombAndRbf());
    ASSERT_EQ(sim.scheduledSteps(), 1000);
    const std::string path = dir.file("rows" + std::to_string(every) + ".h5");
    record(sim, path);
    const long rows = every == 1 ? 1001 : 1 + 1000 / 7 + 1;  // t = 0, every 7th step, the last step
    EXPECT_EQ(TrajectoryWriter::readRows(path), rows);
    EXPECT_EQ(TrajectoryWriter::readSteps(path), 1000);
    EXPECT_EQ(h5::File::openRead(path).readMatrix("/time").rows(), rows);
  }
}

// /terrain/description builds the same terrain as the scene's, without the heightfield's file.
TEST(TrajectoryContents, TerrainDescriptionRebuildsTheTerrainWithoutItsFile) {
  TempDir dir;
  const std::string csv = dir.write("hills.csv", "0, 0.1, 0.2\n0.05, 0.3, -0.1\n0.2, 0.0, 0.1\n0.1, 0.1, 0.1\n");
  const std::string scene_path = boxScene(dir, 2.0, 0.01);
  nlohmann::json scene = loadSceneJson(scene_path);
  scene["terrain"] = {{"type", "heightfield"}, {"file", "hills.csv"}, {"spacing", 0.5}, {"origin", {-0.5, -0.75}}, {"offset", 0.02}};
  Simulation sim = buildSimulation(parseScene(scene, scene_path), coulombAndRbf());
  record(sim, dir.file("hills.h5"));
  std::filesystem::remove(csv);
  const nlohmann::json description = nlohmann::json::parse(h5::File::openRead(dir.file("hills.h5")).readString("/terrain/description"));
  EXPECT_FALSE(description.contains("file"));
  const std::unique_ptr<Terrain> rebuilt = makeTerrain(description, {"description", dir.path().string()});
  TerrainQuery a, b;
  for (double x = -1.0; x <= 1.5; x += 0.13)
    for (double y = -1.0; y <= 1.5; y += 0.17) {
      sim.terrain().query(Vec3(x, y, 0.3), a, false);
      rebuilt->query(Vec3(x, y, 0.3), b, false);
      EXPECT_EQ(a.distance, b.distance) << x << ", " << y;
    }
}

}  // namespace
}  // namespace nmdp::test
