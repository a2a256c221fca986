#include "app/view_run.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/json_text.hpp"
#include "io/hdf5_file.hpp"
#include "sim/trajectory_writer.hpp"

namespace nmdp::app {

namespace {
namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw InputError(displayPath(path) + ": " + what); }

// The first `rows` rows of a numeric dataset whose trailing dimensions are `trailing` (e.g. {C, 6}),
// refused when its shape differs or a value is not finite.
Rows readRows(const h5::File& file, const std::string& dataset, long rows, const std::vector<std::int64_t>& trailing) {
  std::int64_t width = 1;
  for (std::int64_t n : trailing) width *= n;
  const h5::File::Array a = file.readArray(dataset);
  std::vector<std::int64_t> expected = {rows};
  expected.insert(expected.end(), trailing.begin(), trailing.end());
  bool fits = a.shape.size() == expected.size() && a.shape[0] >= rows;
  for (size_t k = 1; fits && k < expected.size(); ++k) fits = a.shape[k] == expected[k];
  if (!fits) {
    auto text = [](const std::vector<std::int64_t>& shape) {
      std::string out = "(";
      for (size_t k = 0; k < shape.size(); ++k) out += (k ? " x " : "") + std::to_string(shape[k]);
      return out + ")";
    };
    fail(file.path(), "dataset '" + dataset + "' has shape " + text(a.shape) + ", expected " + text(expected) +
                          " (at least " + std::to_string(rows) + " rows)");
  }
  Rows out = Eigen::Map<const Rows>(a.values.data(), rows, width);
  for (long i = 0; i < rows; ++i)
    if (!out.row(i).allFinite())
      fail(file.path(), "dataset '" + dataset + "' has a value that is not finite (NaN or infinite) in row " + std::to_string(i) +
                            " of the " + std::to_string(rows) + " committed rows");
  return out;
}

std::vector<std::string> readNames(const h5::File& file, const std::string& dataset, size_t count) {
  std::vector<std::string> names = file.readStrings(dataset);
  if (count != static_cast<size_t>(-1) && names.size() != count)
    fail(file.path(), "dataset '" + dataset + "' has " + std::to_string(names.size()) + " names, expected " + std::to_string(count));
  return names;
}

// The number of committed rows: /rows, else /steps, else len(/time).
long committedRows(const h5::File& file) {
  for (const char* dataset : {"/rows", "/steps"}) {
    if (!file.exists(dataset)) continue;
    const h5::File::Array a = file.readArray(dataset, 1);
    if (a.values.size() != 1 || !(a.values[0] >= 0) || a.values[0] > 1e15 || a.values[0] != std::floor(a.values[0]))
      fail(file.path(), std::string("dataset '") + dataset + "' is not a count of rows");
    return static_cast<long>(a.values[0]);
  }
  if (!file.exists("/time")) fail(file.path(), "dataset '/time' is missing (this is not a run nmdp simulate wrote)");
  const h5::File::Array t = file.readArray("/time");
  return t.shape.empty() ? 0 : static_cast<long>(t.shape[0]);
}

// The world orientation of the trunk from /base/rpy: R = Rz(yaw) Ry(pitch) Rx(roll).
Rows quaternionsFromRpy(const Rows& rpy) {
  Rows q(rpy.rows(), 4);
  for (Eigen::Index i = 0; i < rpy.rows(); ++i) {
    const Eigen::Quaterniond r = Eigen::AngleAxisd(rpy(i, 2), Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(rpy(i, 1), Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(rpy(i, 0), Eigen::Vector3d::UnitX());
    q.row(i) << r.x(), r.y(), r.z(), r.w();
  }
  return q;
}

// Base coordinates at the start of q: 6 for a floating base, 3 planar, 0 fixed.
int baseCoordinates(const nlohmann::json& config) {
  const nlohmann::json* robot = config.contains("robot") ? &config["robot"] : nullptr;
  const std::string base = robot && robot->contains("base") && (*robot)["base"].is_string() ? (*robot)["base"].get<std::string>() : "floating";
  return base == "fixed" ? 0 : base == "planar" ? 3 : 6;
}

void readRobot(const h5::File& file, RunFile& run) {
  if (file.exists("/model/urdf")) {
    run.urdf_text = file.readString("/model/urdf");
    if (file.exists("/model/urdf_path")) run.urdf_path = file.readString("/model/urdf_path");
    if (file.exists("/model/mesh_files") && file.exists("/model/mesh_paths")) {
      const std::vector<std::string> files = file.readStrings("/model/mesh_files");
      const std::vector<std::string> paths = readNames(file, "/model/mesh_paths", files.size());
      for (size_t k = 0; k < files.size(); ++k) run.mesh_paths.emplace_back(files[k], paths[k]);
    }
    return;
  }
  const nlohmann::json& robot = run.config.contains("robot") ? run.config["robot"] : nlohmann::json();
  const std::string urdf = robot.is_object() && robot.contains("urdf") && robot["urdf"].is_string() ? robot["urdf"].get<std::string>() : "";
  if (!urdf.empty() && pathExists(urdf)) {
    try {
      run.urdf_text = readInputFile(urdf, "URDF file");
      run.urdf_path = urdf;
      run.warnings.push_back(run.name + " has no /model/urdf: the robot is drawn from " + urdf + " as it is now");
      return;
    } catch (const InputError& e) {
      run.warnings.push_back(run.name + " has no /model/urdf and its URDF cannot be read (" + e.what() + "): the trunk is drawn as a box");
      return;
    }
  }
  run.warnings.push_back(run.name + " has no /model/urdf and its URDF " + (urdf.empty() ? std::string("is not named in its config") : urdf + " is not found") +
                         ": the trunk is drawn as a box");
}

void readTerrain(const h5::File& file, RunFile& run) {
  if (file.exists("/terrain/description")) {
    run.terrain = parseJson(file.readString("/terrain/description"), run.path + ": /terrain/description");
    return;
  }
  if (run.config.contains("terrain")) {
    run.terrain = run.config["terrain"];
    run.warnings.push_back(run.name + " has no /terrain/description: the terrain is rebuilt from its config");
  }
}

}  // namespace

RunFile readRunFile(const std::string& given) {
  RunFile run;
  run.path = fs::absolute(given).lexically_normal().string();
  run.name = fs::path(given).filename().string();
  const h5::File file = h5::File::openRead(given);
  if (!file.hasAttribute("/", "nmdp_output"))
    fail(given, "this HDF5 file was not written by nmdp (no root attribute 'nmdp_output'); nmdp view reads the runs of nmdp simulate");
  const std::string kind = file.readStringAttribute("/", "nmdp_output");
  if (kind != "trajectory")
    fail(given, "root attribute 'nmdp_output' is '" + kind + "', not 'trajectory': nmdp view reads the runs of nmdp simulate");
  if (file.hasAttribute("/", "config")) {
    run.config = parseJson(file.readStringAttribute("/", "config"), run.path + ": attribute 'config'");
    if (!run.config.is_object()) fail(given, "root attribute 'config' is not a JSON object");
  }
  run.status = file.exists("/status") ? TrajectoryWriter::readStatus(given) : "unknown";
  if (file.hasAttribute("/", "method")) run.method = file.readStringAttribute("/", "method");
  if (file.hasAttribute("/", "contact_model")) run.contact_model = file.readStringAttribute("/", "contact_model");
  if (file.hasAttribute("/", "dt")) run.dt = file.readDoubleAttribute("/", "dt");

  const long rows = run.rows = committedRows(file);
  if (rows <= 0) fail(given, "the run has no rows (/steps is 0): nothing to show");
  const Rows time = readRows(file, "/time", rows, {});
  run.time.assign(time.data(), time.data() + rows);
  for (long i = 1; i < rows; ++i)
    if (run.time[i] < run.time[i - 1]) fail(given, "dataset '/time' decreases at row " + std::to_string(i));

  if (file.hasAttribute("/", "duration") && run.dt > 0) {
    int every = 1;
    if (run.config.contains("output") && run.config["output"].contains("every") && run.config["output"]["every"].is_number_integer())
      every = std::max(1, run.config["output"]["every"].get<int>());
    const double steps = std::ceil(file.readDoubleAttribute("/", "duration") / run.dt - 1e-9);
    if (std::isfinite(steps) && steps >= 0 && steps < 1e15) run.scheduled = static_cast<long>(std::ceil(steps / every)) + 1;
  }
  if (run.status == "running")
    run.warnings.push_back(run.name + " was cut short (status 'running'): " + std::to_string(rows) + " committed rows" +
                           (run.scheduled > 0 ? " of " + std::to_string(run.scheduled) + " scheduled" : ""));

  run.base_position = readRows(file, "/base/position", rows, {3});
  if (file.exists("/base/quaternion")) {
    run.base_quaternion = readRows(file, "/base/quaternion", rows, {4});
  } else {
    run.base_quaternion = quaternionsFromRpy(readRows(file, "/base/rpy", rows, {3}));
  }

  const std::vector<std::string> dofs = file.readStrings("/joint_names");
  const Rows q = readRows(file, "/q", rows, {static_cast<std::int64_t>(dofs.size())});
  const int base = std::min<int>(baseCoordinates(run.config), static_cast<int>(dofs.size()));
  run.joint_names.assign(dofs.begin() + base, dofs.end());
  run.joint_q = q.rightCols(static_cast<Eigen::Index>(dofs.size()) - base);

  run.contact_names = file.readStrings("/contacts/names");
  const auto contacts = static_cast<std::int64_t>(run.contact_names.size());
  const Rows wrench = readRows(file, "/contacts/wrench", rows, {contacts, 6});
  run.contact_forces.resize(rows, 3 * contacts);
  for (std::int64_t c = 0; c < contacts; ++c) run.contact_forces.middleCols(3 * c, 3) = wrench.middleCols(6 * c + 3, 3);
  if (file.exists("/contacts/foot_point"))
    run.foot_points = readRows(file, "/contacts/foot_point", rows, {contacts, 3});
  else if (contacts > 0)
    run.warnings.push_back(run.name + " has no /contacts/foot_point: contact points and force arrows are not drawn");

  if (file.exists("/links/names") && file.exists("/links/position") && file.exists("/links/quaternion")) {
    run.link_names = file.readStrings("/links/names");
    const auto links = static_cast<std::int64_t>(run.link_names.size());
    run.link_position = readRows(file, "/links/position", rows, {links, 3});
    run.link_quaternion = readRows(file, "/links/quaternion", rows, {links, 4});
  } else {
    run.warnings.push_back(run.name + " has no /links poses: only the trunk is drawn, from /base");
  }
  readRobot(file, run);
  readTerrain(file, run);
  return run;
}

}  // namespace nmdp::app
