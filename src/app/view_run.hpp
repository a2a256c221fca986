// One run file as nmdp view reads it: every dataset the page draws from, the first /steps rows only,
// checked for shape and NaN, with a warning for each part the file lacks (the page draws a
// fallback instead). Bad input (not an nmdp HDF5 file, no rows, mismatched shapes, NaN in /time) is
// one InputError naming the file and the dataset.
#pragma once
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace nmdp::app {

// Row-major N × k table of one dataset's first N rows (k the product of the other dimensions).
using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct RunFile {
  std::string path;      // absolute
  std::string name;      // the file name, for labels and warnings
  std::string status;    // /status: complete, running (killed), failed: ..., interrupted ...
  long rows = 0;         // N
  long scheduled = 0;    // rows the scene scheduled (duration / dt + 1), 0 when unknown
  nlohmann::json config; // the resolved scene (root attribute `config`), {} when absent
  std::string method, contact_model;
  double dt = 0.0;

  std::vector<double> time;      // N, s
  Rows base_position;            // N × 3, world
  Rows base_quaternion;          // N × 4, xyzw, world
  std::vector<std::string> joint_names;  // actuated joints (the base coordinates dropped)
  Rows joint_q;                  // N × J

  std::vector<std::string> contact_names;
  std::optional<Rows> foot_points;  // N × 3C, world
  Rows contact_forces;              // N × 3C, world force on the robot (wrench[3:6])

  std::vector<std::string> link_names;
  std::optional<Rows> link_position, link_quaternion;  // N × 3L, N × 4L

  // The robot's URDF: its text and where it was read from ("" when unknown), and its meshes as
  // the run resolved them (filename as written → absolute path or "").
  std::optional<std::string> urdf_text;
  std::string urdf_path;
  std::vector<std::pair<std::string, std::string>> mesh_paths;

  std::optional<nlohmann::json> terrain;  // /terrain/description, else the config's "terrain"
  std::string terrain_base_dir;           // where the config's relative terrain files are

  std::vector<std::string> warnings;
};

RunFile readRunFile(const std::string& path);

}  // namespace nmdp::app
