// The "rbf" contact model: an RbfFunction (rbf_function.hpp) wrapped in a PlanarWrenchModel
// (planar_wrench_model.hpp), or for an HDF5 file whose centres have three columns a 3-D
// SpatialRbfFunction (spatial_rbf_function.hpp) wrapped in a SpatialWrenchModel, built from a JSON
// object such as
//
//     {"type": "rbf", "file": "sand.h5"}
//     {"type": "rbf", "file": "granular/robosimian_sand_rbf", "cutoff_width": 0.01}
//
// Keys (every one optional except "file"):
//   file          path, relative to the configuration file: an HDF5 model file (.h5, .hdf5), a folder
//                 holding the published inputs.txt and weights.txt, or the centres file (.txt) of the
//                 published format
//   format        "auto" (default: detected from the path as above), "published" or "hdf5"
//   weights_file  published format only: the weights file (default: weights.txt next to the centres)
//   kernel        published format only: one of rbfKernelNames(), default "thin_plate"
//   scaling       published format only: [s_phi, s_beta] > 0, default [5, 1]
//   epsilon       published format only: kernel shape parameter > 0, default 1
//   torque_centre m up the leg from the foot point; default: the file's (HDF5) or 0.1572 (published)
//   cutoff        m, zero wrench for phi >= cutoff; default: the file's (HDF5) or 0.1 (published)
//   cutoff_width  m > 0, blending band below the cut-off; default: the file's (HDF5) or 0.02
// The kernel, scaling and epsilon of an HDF5 file belong to its fitted weights and cannot be
// overridden (an InputError says so); the geometry keys override the file's values.
// The model's configuration() holds every key with the value in use: file (resolved), format
// ("published" or "hdf5"), for the published format weights_file, kernel, scaling and epsilon,
// and torque_centre, cutoff, cutoff_width.
// A 3-D model file takes file, format, cutoff and cutoff_width only (the other keys are refused with
// a message); its configuration() holds file, format ("hdf5"), cutoff and cutoff_width.
// Every error is an InputError naming the configuration key (ctx.where) and the file.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "config/json_params.hpp"

namespace nmdp {

// Every key makeRbfModel accepts besides "type".
extern const std::vector<std::string> kRbfParameters;

// Returns a PlanarWrenchModel (or, for a 3-D file, a SpatialWrenchModel) of type name "rbf".
// `params` may hold "type" (it must then be "rbf").
std::unique_ptr<ContactModel> makeRbfModel(const nlohmann::json& params, const ConfigContext& ctx);

}  // namespace nmdp
