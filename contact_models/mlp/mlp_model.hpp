// The "mlp" contact model: an MlpFunction (mlp_function.hpp, libtorch) wrapped in a
// PlanarWrenchModel (planar_wrench_model.hpp), or for a spatial (3-D) model file in a
// SpatialWrenchModel (spatial_wrench_model.hpp), built from a JSON object such as
//
//     {"type": "mlp", "file": "sand_mlp.h5"}
//     {"type": "mlp", "file": "sand_mlp.h5", "cutoff_width": 0.01}
//
// Keys (every one optional except "file"):
//   file          path, relative to the configuration file: the HDF5 model file (format in
//                 mlp_function.hpp), written by saveMlpModel or 'nmdp fit'
//   torque_centre m up the leg from the foot point; default: the file's (planar files only: with a
//                 spatial file it is an InputError, the torque being about the foot point)
//   cutoff        m, zero wrench for phi >= cutoff; default: the file's
//   cutoff_width  m > 0, blending band below the cut-off; default: the file's
//   jacobian      how dV/dξ gets dW/df (mlp_function.hpp): "forward-mode" (default, libtorch
//                 forward-mode autograd), "double-backward" (reverse-mode autograd twice) or
//                 "tangents" (hand-coded forward-mode tangents, fastest; derivative() = analytic)
// The weights, the normalization and the activation belong to the file and cannot be overridden.
// The model's configuration() holds every key above with the value in use (file resolved).
// Building a model
// calls torch::set_num_threads(1) (process-global, see mlp_function.hpp).
// Every error is an InputError naming the configuration key (ctx.where) and the file.
// This header includes no libtorch header.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "config/json_params.hpp"

namespace nmdp {

// Every key makeMlpModel accepts besides "type".
extern const std::vector<std::string> kMlpParameters;

// Returns a PlanarWrenchModel or, for a spatial file, a SpatialWrenchModel of type name "mlp". `params` may hold "type" (it must then be "mlp").
std::unique_ptr<ContactModel> makeMlpModel(const nlohmann::json& params, const ConfigContext& ctx);

}  // namespace nmdp
