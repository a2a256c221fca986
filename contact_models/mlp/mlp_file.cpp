// The MLP contact model's HDF5 file (mlp_function.hpp, "The model file"): loading with every
// dataset checked against the attributes before it is read, and saving with the oldest format
// version that holds the model.
#include <algorithm>
#include <cmath>
#include <string>

#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "contact_models/file_attributes.hpp"
#include "contact_models/mlp/mlp_function.hpp"
#include "io/hdf5_file.hpp"
#include "common/text.hpp"

namespace nmdp {

namespace {

constexpr double kFormatVersion = 5.0;          // the newest version this program reads and writes
constexpr double kFormatVersionSpatial = 5.0;   // written for a spatial MLP (older programs refuse it)
constexpr double kFormatVersionSoftDepth = 4.0;   // written with output_envelope "soft_depth"
constexpr double kFormatVersionAnchors = 3.0;     // written with zero anchors (and no soft_depth)
constexpr double kFormatVersionEnvelope = 2.0;    // written with output_envelope "depth" (no anchors)
constexpr double kFormatVersionNoEnvelope = 1.0;  // written when output_envelope is "none" (no anchors)
constexpr const char* kUnits = "phi: m, beta: rad; F_x, F_z: N; tau_y: N m";
constexpr const char* kSpatialUnits = "phi: m, beta: rad, gamma: rad; tau: N m about the foot point; F: N";

std::vector<std::string> featureNames(MlpWrench wrench) {
  if (wrench == MlpWrench::Spatial) return {"phi", "beta", "gamma"};
  return {"phi", "beta"};
}

std::string layerName(size_t i) { return "/mlp/layer_" + std::to_string(i); }

}  // namespace


// An MLP contact model's size: the sand MLP has 2 hidden layers and 2 x 10^4 weights; one with 10^7
// would take seconds per step.
constexpr int kMaxLayers = 64;
constexpr Eigen::Index kMaxParameters = 10000000;

namespace {

// The attributes that say what the file holds: format version, wrench kind, activation, envelope.
void readKind(const h5::File& file, const FileAttributes& mlp, MlpParameters& p) {
  if (!file.exists("/mlp"))
    mlp.fail("not an nmdp MLP model file: group '/mlp' is missing (write one with saveMlpModel or 'nmdp fit')");
  mlp.checkFormatVersion(static_cast<int>(kFormatVersion));
  if (file.hasAttribute("/mlp", "wrench")) {
    const std::string wrench = file.readStringAttribute("/mlp", "wrench");
    if (!assignIfNamed(kMlpWrenches, wrench, &p.wrench))
      mlp.fail("attribute 'wrench' of '/mlp' is '" + wrench + "'; valid values: \"planar\" (3 outputs (F_x, F_z, "
               "tau_y) per vertex of (phi, beta)) or \"spatial\" (6 outputs (tau_x, tau_y, tau_z, F_x, F_y, F_z) per "
               "vertex of (phi, beta, gamma))");
  }
  if (file.hasAttribute("/mlp", "inputs")) {
    const int F = p.featureCount();
    if (mlp.integer("inputs", 2, 3) != F)
      mlp.fail("attribute 'inputs' of '/mlp' must be " + std::to_string(F) + " for wrench \"" +
               nameOf(kMlpWrenches, p.wrench) + "\" (the features " +
               (F == 3 ? "phi, beta, gamma" : "phi, beta") + ")");
  }
  const std::string activation = file.readStringAttribute("/mlp", "activation");
  if (const std::string problem = mlpActivationProblem(activation); !problem.empty())
    mlp.fail("attribute 'activation' of '/mlp': " + problem);
  parseMlpActivation(activation, &p.activation);
  if (file.hasAttribute("/mlp", "output_envelope")) {
    const std::string envelope = file.readStringAttribute("/mlp", "output_envelope");
    if (!parseMlpOutputEnvelope(envelope, &p.output_envelope))
      mlp.fail("attribute 'output_envelope' of '/mlp' is '" + envelope + "'; valid values: \"none\" (W = N), \"depth\" "
               "(W = (-phi) N) or \"soft_depth\" (W = w softplus(-phi/w) N)");
    if (p.output_envelope == MlpOutputEnvelope::SoftDepth) {
      if (!file.hasAttribute("/mlp", "envelope_width"))
        mlp.fail("output_envelope \"soft_depth\" needs the attribute 'envelope_width' of '/mlp' (m)");
      p.envelope_width = file.readDoubleAttribute("/mlp", "envelope_width");
    }
  }
}

// A vector: a 1-D dataset, or a 2-D one with a single row or column, of n finite values.
Eigen::VectorXd readVector(const h5::File& file, const FileAttributes& mlp, const std::string& name, Eigen::Index n,
                           const std::string& what) {
  const Eigen::MatrixXd m = file.readMatrix(name, std::max<Eigen::Index>(4 * n, 64));  // a wrong size is named below
  if (m.size() != n || (m.rows() != 1 && m.cols() != 1))
    mlp.fail("dataset '" + name + "' must hold " + std::to_string(n) + " values (" + what + "), got " + shapeText(m));
  if (const std::string bad = firstNonFinite(m); !bad.empty())
    mlp.fail("dataset '" + name + "' has a non-finite value (NaN or inf) at " + bad);
  return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(m.data(), n));
}

// The layers 0 .. layer_count − 1, each checked against the previous one and the output size wK.
void readLayers(const h5::File& file, const FileAttributes& mlp, int layer_count, int K, MlpParameters& p) {
  const int w = p.wrenchWidth();
  Eigen::Index in = p.featureCount(), parameters = 0;
  for (int i = 0; i < layer_count; ++i) {
    const std::string wn = layerName(i) + "/weight", b = layerName(i) + "/bias";
    MlpLayer l;
    l.weight = file.readMatrix(wn, kMaxParameters - parameters);
    if (i + 1 == layer_count && l.weight.rows() != w * K)
      mlp.fail("dataset '" + wn + "' is " + shapeText(l.weight) + ": the output layer must have " + std::to_string(w) +
               "K = " + std::to_string(w * K) + " rows (attribute 'vertices' = " + std::to_string(K) + ")");
    if (l.weight.cols() != in) {
      mlp.fail("dataset '" + wn + "' is " + shapeText(l.weight) + ", expected (outputs) x " + std::to_string(in) + ": " +
               (i == 0 ? std::string(p.wrench == MlpWrench::Spatial ? "the input is (phi, beta, gamma)"
                                                                    : "the input is (phi, beta)")
                       : "the previous layer " + layerName(i - 1) + " has " + std::to_string(in) + " outputs"));
    }
    l.bias = readVector(file, mlp, b, l.weight.rows(), "one per row of '" + wn + "'");
    parameters += l.weight.size() + l.bias.size();
    if (parameters > kMaxParameters)
      mlp.fail("the layers up to '" + wn + "' have " + std::to_string(parameters) + " weights and biases, more than the " +
               std::to_string(kMaxParameters) + " a contact-model MLP may have");
    p.layers.push_back(std::move(l));
    in = p.layers.back().weight.rows();
  }
  if (file.exists(layerName(layer_count)))
    mlp.fail("group '" + layerName(layer_count) + "' exists but attribute 'layers' of '/mlp' is " +
             std::to_string(layer_count) + " (layers 0.." + std::to_string(layer_count - 1) + " are read)");
}

// The optional feature names (checked) and zero anchors.
void readFeaturesAndAnchors(const h5::File& file, const FileAttributes& mlp, MlpParameters& p) {
  if (file.exists("/mlp/feature_names")) {
    const std::vector<std::string> names = file.readStrings("/mlp/feature_names");
    if (names != featureNames(p.wrench))
      mlp.fail(p.wrench == MlpWrench::Spatial
                   ? "dataset '/mlp/feature_names' must be [\"phi\", \"beta\", \"gamma\"]: a spatial MLP takes the "
                     "signed distance and the leg's sagittal and lateral lean"
                   : "dataset '/mlp/feature_names' must be [\"phi\", \"beta\"]: the MLP contact model takes the signed "
                     "distance and the sagittal leg angle");
  }
  if (!file.exists("/mlp/anchors")) return;
  const int F = p.featureCount();
  const Eigen::MatrixXd a = file.readMatrix("/mlp/anchors", F * limits::kMaxRbfCentres);
  if (a.cols() != F || a.rows() < 1)
    mlp.fail("dataset '/mlp/anchors' is " + shapeText(a) + ", expected (anchors) x " + std::to_string(F) +
             ": the points " + (F == 3 ? "(phi, beta, gamma)" : "(phi, beta)"));
  if (a.rows() > limits::kMaxRbfCentres)
    mlp.fail("dataset '/mlp/anchors' has " + std::to_string(a.rows()) + " anchors, more than the " +
             std::to_string(limits::kMaxRbfCentres) + " a model may have");
  p.anchors = a;
  if (!file.hasAttribute("/mlp", "anchor_radius"))
    mlp.fail("dataset '/mlp/anchors' needs the attribute 'anchor_radius' of '/mlp'");
  p.anchor_radius = file.readDoubleAttribute("/mlp", "anchor_radius");
}

}  // namespace

MlpModelFile loadMlpModel(const std::string& path) {
  const h5::File file = h5::File::openRead(path);
  const FileAttributes mlp(file, path, "/mlp");
  MlpModelFile out;
  MlpParameters& p = out.parameters;
  readKind(file, mlp, p);
  const int layer_count = mlp.integer("layers", 1, kMaxLayers);
  const int K = mlp.integer("vertices", 1, limits::kMaxVertices);
  const bool spatial = p.wrench == MlpWrench::Spatial;
  if (spatial && file.hasAttribute("/mlp", "torque_centre"))
    mlp.fail("attribute 'torque_centre' of '/mlp' belongs to planar models: a spatial MLP's torque is about the foot "
             "point");
  out.geometry.torque_centre = spatial ? 0.0 : mlp.finite("torque_centre");
  out.geometry.cutoff = mlp.finite("cutoff");
  out.geometry.cutoff_width = mlp.finite("cutoff_width");
  if (!(out.geometry.cutoff_width > 0.0)) mlp.fail("attribute 'cutoff_width' of '/mlp' must be positive");
  if (const std::string problem = planarGeometryProblem(out.geometry); !problem.empty())
    mlp.fail("attribute " + problem + " (of '/mlp')");
  const int F = p.featureCount(), w = p.wrenchWidth();
  const std::string features = spatial ? "phi, beta, gamma" : "phi, beta";
  p.input_mean = readVector(file, mlp, "/mlp/input_mean", F, "mean of " + features);
  p.input_std = readVector(file, mlp, "/mlp/input_std", F, "standard deviation of " + features);
  const std::string per_vertex = std::to_string(w) + " per vertex, attribute 'vertices' = " + std::to_string(K);
  p.output_scale = readVector(file, mlp, "/mlp/output_scale", w * K, per_vertex);
  p.output_offset = readVector(file, mlp, "/mlp/output_offset", w * K, per_vertex);
  readLayers(file, mlp, layer_count, K, p);
  readFeaturesAndAnchors(file, mlp, p);
  if (const std::string problem = mlpParameterProblem(p); !problem.empty()) mlp.fail(problem);
  return out;
}

namespace {
// Throws std::invalid_argument "`where`: ..." for parameters or a geometry the format cannot hold.
void checkSavable(const std::string& where, const MlpParameters& p, const PlanarGeometry& geometry) {
  if (const std::string problem = mlpParameterProblem(p); !problem.empty())
    throw std::invalid_argument(where + ": " + problem);
  if (!(geometry.cutoff_width > 0.0) || !std::isfinite(geometry.cutoff_width) || !std::isfinite(geometry.cutoff) ||
      !std::isfinite(geometry.torque_centre))
    throw std::invalid_argument(where + ": the geometry must be finite with cutoff_width > 0");
}
}  // namespace

namespace {

// Both kinds: a planar file has a torque centre, a spatial one none.
void writeAnyMlpModel(h5::File& file, const MlpParameters& p, const PlanarGeometry& geometry) {
  checkSavable("writeMlpModel(" + file.path() + ")", p, geometry);
  const bool spatial = p.wrench == MlpWrench::Spatial;
  file.writeStringAttribute("/", "nmdp_model", "mlp");
  file.createGroup("/mlp");
  const bool envelope = p.output_envelope != MlpOutputEnvelope::None;
  const bool anchored = p.anchors.rows() > 0;
  file.writeDoubleAttribute("/mlp", "format_version",
                            spatial                                             ? kFormatVersionSpatial
                            : p.output_envelope == MlpOutputEnvelope::SoftDepth ? kFormatVersionSoftDepth
                            : anchored                                          ? kFormatVersionAnchors
                            : envelope                                          ? kFormatVersionEnvelope
                                                                                : kFormatVersionNoEnvelope);
  file.writeStringAttribute("/mlp", "activation", mlpActivationName(p.activation));
  file.writeDoubleAttribute("/mlp", "layers", static_cast<double>(p.layers.size()));
  file.writeDoubleAttribute("/mlp", "vertices", p.vertexCount());
  file.writeStringAttribute("/mlp", "wrench", nameOf(kMlpWrenches, p.wrench));
  if (spatial)
    file.writeDoubleAttribute("/mlp", "inputs", p.featureCount());
  else
    file.writeDoubleAttribute("/mlp", "torque_centre", geometry.torque_centre);
  file.writeDoubleAttribute("/mlp", "cutoff", geometry.cutoff);
  file.writeDoubleAttribute("/mlp", "cutoff_width", geometry.cutoff_width);
  file.writeStringAttribute("/mlp", "units", spatial ? kSpatialUnits : kUnits);
  if (envelope) file.writeStringAttribute("/mlp", "output_envelope", mlpOutputEnvelopeName(p.output_envelope));
  if (p.output_envelope == MlpOutputEnvelope::SoftDepth) file.writeDoubleAttribute("/mlp", "envelope_width", p.envelope_width);
  file.writeStrings("/mlp/feature_names", featureNames(p.wrench));
  file.writeVector("/mlp/input_mean", p.input_mean);
  file.writeVector("/mlp/input_std", p.input_std);
  file.writeVector("/mlp/output_scale", p.output_scale);
  file.writeVector("/mlp/output_offset", p.output_offset);
  for (size_t i = 0; i < p.layers.size(); ++i) {
    file.createGroup(layerName(i));
    file.writeMatrix(layerName(i) + "/weight", p.layers[i].weight);
    file.writeVector(layerName(i) + "/bias", p.layers[i].bias);
  }
  if (anchored) {
    file.writeMatrix("/mlp/anchors", p.anchors);
    file.writeDoubleAttribute("/mlp", "anchor_radius", p.anchor_radius);
  }
}

PlanarGeometry asPlanar(const SpatialGeometry& g) { return PlanarGeometry{0.0, g.cutoff, g.cutoff_width}; }

void requireWrench(const std::string& where, const MlpParameters& p, MlpWrench wrench) {
  if (p.wrench != wrench)
    throw std::invalid_argument(where + ": a " + nameOf(kMlpWrenches, p.wrench) + " MLP given with a " +
                                nameOf(kMlpWrenches, wrench) + " geometry");
}

}  // namespace

void saveMlpModel(const std::string& path, const MlpParameters& p, const PlanarGeometry& geometry) {
  requireWrench("saveMlpModel(" + path + ")", p, MlpWrench::Planar);
  checkSavable("saveMlpModel(" + path + ")", p, geometry);  // before any file is created
  h5::File file = h5::File::createAtomic(path);
  writeMlpModel(file, p, geometry);
  file.commit();
}

void writeMlpModel(h5::File& file, const MlpParameters& p, const PlanarGeometry& geometry) {
  requireWrench("writeMlpModel(" + file.path() + ")", p, MlpWrench::Planar);
  writeAnyMlpModel(file, p, geometry);
}

void saveMlpModel(const std::string& path, const MlpParameters& p, const SpatialGeometry& geometry) {
  requireWrench("saveMlpModel(" + path + ")", p, MlpWrench::Spatial);
  checkSavable("saveMlpModel(" + path + ")", p, asPlanar(geometry));  // before any file is created
  h5::File file = h5::File::createAtomic(path);
  writeMlpModel(file, p, geometry);
  file.commit();
}

void writeMlpModel(h5::File& file, const MlpParameters& p, const SpatialGeometry& geometry) {
  requireWrench("writeMlpModel(" + file.path() + ")", p, MlpWrench::Spatial);
  writeAnyMlpModel(file, p, asPlanar(geometry));
}

void saveMlpModel(const std::string& path, const MlpFunction& function, const PlanarGeometry& geometry) {
  saveMlpModel(path, function.parameters(), geometry);
}


}  // namespace nmdp
