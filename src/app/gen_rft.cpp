#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/json_argument.hpp"
#include "common/input_error.hpp"
#include "io/output_path.hpp"
#include "training/force_dataset.hpp"
#include "training/rft.hpp"
#include "training/rft3d_config.hpp"
#include "training/rft_config.hpp"
#include "training/sand_samples_csv.hpp"

namespace nmdp::app {

const char* const kGenRftHelp =
    "usage: nmdp gen-rft [--config RFT.json] --out FOLDER_OR_FILE.h5\n\n"
    "Generates wrench samples from resistive force theory (Li, Zhang, Goldman, Science 2013; the generic\n"
    "9-coefficient form times the medium's scale zeta) integrated over a foot shape: at every (depth,\n"
    "angle) of the grid, the wrench (F_x, F_z, tau_y) resisting each motion direction. These samples\n"
    "are the vertices of the wrench space there, ready for nmdp fit.\n\n"
    "  --config RFT.json  medium (zeta in N/cm^3, coefficients), foot (disc, plate or blade; sizes in m;\n"
    "                     torque_centre; elements) and grid (depths in m, angles in rad, directions);\n"
    "                     a file or an inline JSON object; every key is optional (all of them: --schema).\n"
    "                     Without it: a disc of radius 0.02 m, zeta 1 N/cm^3, the sand samples' points,\n"
    "                     26 directions.\n"
    "  --out PATH         a folder: the CSV layout of granular/sand_samples (features.csv,\n"
    "                     wrench_samples.csv, scalars.txt) and rft_config.json, the complete\n"
    "                     configuration (pass it to --config to regenerate); a path ending in .h5: a\n"
    "                     force dataset (training/force_dataset.hpp)\n"
    "  --schema           print every RFT.json key with its type, default, range, unit and use (the\n"
    "                     planar keys, then the 3-D ones), and stop\n\n"
    "A configuration with \"dimension\": 3 asks for three-dimensional RFT (training/rft3d_law.hpp: the\n"
    "planar law applied in each surface element's vertical plane of motion) on a 3-D foot (sphere, plate\n"
    "or blade) over depths x betas x gammas (the leg's sagittal and lateral leans) and translation\n"
    "directions (default the 26 cube directions): \"output\": \"spatial\" (default) writes the 6-D\n"
    "wrenches (tau_x, tau_y, tau_z, F_x, F_y, F_z) about the foot point to an .h5 file; \"output\":\n"
    "\"planar\" the planar samples (F_x, F_z, tau_y) of the same foot and medium at gamma 0.\n";

namespace {
bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

int runGenRft(const Args& args) {
  if (args.size() == 1 && args[0] == "--schema") {
    nlohmann::ordered_json both = rftConfigSchema();
    for (const auto& [section, rows] : rft3dConfigSchema().items()) both["3d: " + section] = rows;
    return std::cout << schemaText(both), 0;
  }
  nlohmann::json config = nlohmann::json::object();
  std::string where = "defaults", out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto next = [&]() -> const std::string& { return optionValue(args, i, "gen-rft"); };
    if (a == "--config") {
      ConfigContext ctx;
      config = readJsonArgument("--config", next(), ctx);
      where = ctx.where;
    } else if (a == "--out") {
      out = next();
    } else {
      throw InputError("unknown argument '" + a + "' (see nmdp gen-rft --help)");
    }
  }
  if (out.empty()) throw InputError("--out is required: a folder, or a file ending in .h5 (see nmdp gen-rft --help)");

  // The output replaces no input and nothing nmdp did not write (io/output_path.hpp).
  const std::vector<RunInput> inputs = {{where == "defaults" || where == "--config" ? "" : where, "the --config file"}};
  const std::vector<std::string> folder_files = {"features.csv", "wrench_samples.csv", "scalars.txt", "rft_config.json"};
  if (endsWith(out, ".h5"))
    checkOutputFile(out, inputs, "--out");
  else
    checkOutputFolder(out, folder_files, inputs, "--out");

  const bool spatial_config = isRft3dConfig(config, where);
  std::string resolved;
  ForceDataset data;
  size_t direction_count = 0;
  double torque_centre = 0.0;
  bool spatial_output = false;
  if (spatial_config) {
    const Rft3dConfig c = readRft3dConfig(config, where);
    spatial_output = c.output == Rft3dOutput::Spatial;
    if (spatial_output && !endsWith(out, ".h5"))
      throw InputError("--out: the spatial (3-D) samples are written to a file ending in .h5 (the CSV folder is planar)");
    data = rft3dConfigSamples(c);
    resolved = c.resolved.dump(2);
    direction_count = c.grid.directions.size();
    torque_centre = c.torque_centre;
    data.source += "; nmdp gen-rft configuration: " + c.resolved.dump();
  } else {
    nlohmann::json planar = config;
    if (planar.is_object()) planar.erase("dimension");  // "dimension": 2 (checked above) is the planar default
    const RftConfig c = readRftConfig(planar, where);
    data = rftSamples(c.medium, c.foot, c.grid);
    resolved = c.resolved.dump(2);
    direction_count = c.grid.directions.size();
    torque_centre = c.foot.torque_centre;
    data.source += "; nmdp gen-rft configuration: " + c.resolved.dump();
  }
  std::vector<std::string> written;
  if (endsWith(out, ".h5")) {
    writeForceDataset(out, data);
    written.push_back(out);
  } else {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (!std::filesystem::is_directory(out, ec)) throw InputError(out + ": cannot create the folder");
    writeFolderMarker(out, "gen-rft", folder_files);  // first: a folder left half-written is still ours
    writeSandSamplesCsv(out, data);
    writeFileAtomically((std::filesystem::path(out) / "rft_config.json").string(), resolved + "\n");
    written = folder_files;
  }

  const Eigen::Index K = static_cast<Eigen::Index>(direction_count);
  const Eigen::Index N = data.wrench.rows();
  std::cout << "wrote " << N << " wrench samples (" << N / K << " points x " << K << " directions) to " << out;
  if (written.size() > 1) {
    std::cout << ":";
    for (const std::string& w : written) std::cout << " " << w;
  }
  if (spatial_output) {
    const Eigen::MatrixXd& w = data.wrench;
    std::cout << "\nlargest |F| " << w.rightCols(3).rowwise().norm().maxCoeff() << " N, largest |tau| "
              << w.leftCols(3).rowwise().norm().maxCoeff() << " N m (about the foot point)\n";
  } else {
    std::cout << "\nlargest |F_x| " << data.wrench.col(0).cwiseAbs().maxCoeff() << " N, largest |F_z| "
              << data.wrench.col(1).cwiseAbs().maxCoeff() << " N, largest |tau_y| "
              << data.wrench.col(2).cwiseAbs().maxCoeff() << " N m (about the torque centre, " << torque_centre
              << " m up the leg)\n";
  }
  return 0;
}

}  // namespace nmdp::app
