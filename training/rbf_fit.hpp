// RBF fitting of wrench spaces (DESIGN.md §7.2, §9), planar (features (φ, β), vertices (F_x, F_z,
// τ_y)) and spatial (features (φ, β, γ), vertices (τ_x, τ_y, τ_z, F_x, F_y, F_z); training/
// spatial_rbf_fit.hpp), by one code path: one RBF interpolant per wrench component, all vertices at
// once, centred at the fit points,
//
//     [Φ + λI  P] [W]   [Y]        Φ_ik = κ(‖S(f_i − f_k)‖),  P = [1 φ β (γ)] (the optional linear tail),
//     [Pᵀ      0] [a] = [0],       λ ≥ 0 the ridge,
//
// solved with an LU factorization (Eigen). The kernels and the scaling S are those of
// contact_models/rbf_function.hpp, so the result is an RbfFunction the "rbf" contact model loads.
//
// Leave-one-point-out error (Rippa 1999): removing point i (its data and its centre) and refitting
// changes the prediction at f_i by e_i = c_i / (A⁻¹)_ii, c = A⁻¹ [Y; 0], A the matrix above, for
// each column of Y; exact for interpolation (λ = 0), with the ridge and with the tail. It costs one
// inverse instead of P refits. The report divides, for each point and vertex, the largest component
// |e| by the largest |entry| of Y at that point ("the largest wrench at that point"); at zero-wrench
// points (above the surface) by the largest |entry| of all of Y instead, since theirs is zero.
#pragma once
#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "contact_models/rbf_function.hpp"
#include "training/augmentation.hpp"
#include "training/fit_warnings.hpp"

namespace nmdp {

namespace h5 {
class File;
}

struct RbfFitSettings {
  RbfKernelSpec spec;       // kernel, scaling S, epsilon
  double ridge = 0.0;       // λ ≥ 0, added to the kernel matrix's diagonal
  bool polynomial = false;  // the linear tail a + b φ + c β (+ d γ)
  // rbf.scaling as given in FIT.json: 0 not given (spec.scaling is the planar default), 2 numbers
  // (in spec.scaling) or 3 (in spatial_scaling, for spatial data only).
  int scaling_given = 0;
  // s_φ, s_β, s_γ: by default 1 cm of depth weighs as 0.2 rad of tilt.
  Eigen::Vector3d spatial_scaling = Eigen::Vector3d(20.0, 1.0, 1.0);
};

// The solution of the system above for any points (PointSetView: 2 or 3 features, W = 3 or 6
// entries per vertex), with Rippa's leave-one-point-out error; the planar and spatial fits share it.
struct RbfSolution {
  Eigen::MatrixXd weights;       // P×WK
  Eigen::MatrixXd polynomial;    // empty or (1 + F)×WK: rows = coefficients of 1, φ, β (, γ)
  Eigen::MatrixXd loo_error;     // P×WK
  Eigen::MatrixXd loo_relative;  // P×K, relativeVertexErrors
  Eigen::VectorXd point_scale;   // P, pointScales
  double rcond = 0.0;
};
// Throws as fitRbf. `scaling` has F entries.
RbfSolution solveRbfSystem(const PointSetView& points, RbfKernel kernel, const Eigen::VectorXd& scaling,
                           double epsilon, double ridge, bool polynomial, const std::string& where);

// The part of the fit report shared by planar and spatial fits: from the "points:" line to the
// leave-one-point-out table, the worst points and the RMS line (see formatRbfFitReport).
std::string formatRbfLooReport(const PointSetView& points, const RbfSolution& fit, double seconds);

struct RbfFit {
  RbfParameters parameters;      // centres = the fit points
  Eigen::MatrixXd loo_error;     // P×3K: Y − the prediction of the fit without that point
  Eigen::MatrixXd loo_relative;  // P×K: max over (F_x, F_z, τ_y) of |loo_error| / point_scale
  Eigen::VectorXd point_scale;   // P: the largest |Y| entry at the point (of all Y at zero points)
  double rcond = 0.0;            // reciprocal condition number estimate of A (1-norm)
};

// Systems with a reciprocal condition number below this are refused as singular.
constexpr double kRbfMinRcond = 1e-13;

// Fits the points. Throws InputError "`where`: ..." for fewer than 2 points (4 with the tail), and
// for a singular system, naming the two closest points (after scaling) and the remedies. Throws
// std::invalid_argument on invalid settings (negative ridge, non-positive scaling or epsilon).
RbfFit fitRbf(const PlanarPoints& points, const RbfFitSettings& settings, const std::string& where);

// What a fit records: the settings as JSON (every key with the value used), the points and the LOO
// error, a text report.
struct RbfFitRecord {
  nlohmann::ordered_json settings;
  PlanarPoints points;  // the fitted points, augmented
  RbfFit fit;
  std::string data;    // the data set it came from
  double seconds = 0;  // wall time of augmentation and fit
  std::vector<std::string> from_data;  // the settings decided from the data (resolveFitConfig)
  AboveSurfaceCheck above_surface;     // the model between the surface and the cut-off
  std::vector<FitWarning> warnings;    // the leave-one-point-out error, the model above the surface
};

// The report printed after a fit and stored in the model file: settings (and which were decided
// from the data), sizes, condition, the leave-one-point-out error per vertex (largest and RMS over
// the measured points, largest over all points, the worst point) and the worst points, the model's
// largest wrench above the surface, and the warnings (fit_warnings.hpp).
std::string formatRbfFitReport(const RbfFitRecord& record);

// Writes the model file of contact_models/rbf_function.hpp (format_version 1), which the "rbf"
// contact model loads as it is, plus a group /fit (ignored by the loader):
//   /fit                attributes: data (string), settings (JSON text), report (text), seconds,
//                       from_data (text, one decided setting a line), warnings (text, as in the
//                       report), above_surface_share (the largest wrench above the surface over
//                       the largest below), loo_rms (RMS relative LOO error over the measured points)
//   /fit/points         P×2 float64 (φ, β), the fitted points (= /rbf/centres)
//   /fit/origin         P int64: 0 measured, 1 mirrored, 2 above the surface
//   /fit/values         P×3K float64, the fitted values (after scaling and augmentation)
//   /fit/loo_error      P×3K float64, the leave-one-point-out error, same units
//   /fit/loo_relative   P×K float64, relative to the largest wrench at the point
// Atomically (path + ".partial", renamed on success).
void saveRbfFit(const std::string& path, const RbfFitRecord& record, const PlanarGeometry& geometry);

// The /fit group above (without above_surface_share) into an open file: the planar and the spatial
// fit files share it (P×F points, P×WK values and errors).
struct RbfFitGroup {
  const std::string& data;
  const nlohmann::ordered_json& settings;
  const std::string& report;
  double seconds;
  const std::vector<std::string>& from_data;
  const std::vector<FitWarning>& warnings;
  PointSetView points;
  const Eigen::MatrixXd& loo_error;
  const Eigen::MatrixXd& loo_relative;
};
void writeRbfFitGroup(h5::File& file, const RbfFitGroup& group);

}  // namespace nmdp
