#include "training/rbf_fit.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/hdf5_file.hpp"
#include "training/fit_report.hpp"
#include "common/input_error.hpp"
#include "common/limits.hpp"

namespace nmdp {

namespace {
// Φ_ik = κ(‖S(f_i − f_k)‖) into the top-left P×P block of A, from the scaled points (P×F). The
// distance is taken over rows of F fixed columns, so that the planar fit keeps the rounding it has
// always had (a dynamic row length changes how the compiler fuses the sum of squares).
template <int F>
void fillKernelMatrix(const Eigen::MatrixXd& scaled_points, RbfKernel kernel, double epsilon, Eigen::MatrixXd& A) {
  const Eigen::Matrix<double, Eigen::Dynamic, F> scaled = scaled_points;
  for (Eigen::Index i = 0; i < scaled.rows(); ++i)
    for (Eigen::Index k = 0; k <= i; ++k) {
      double kappa = 0.0, g = 0.0;
      rbfKernel(kernel, epsilon, (scaled.row(i) - scaled.row(k)).squaredNorm(), &kappa, &g);
      A(i, k) = A(k, i) = kappa;
    }
}
}  // namespace

RbfSolution solveRbfSystem(const PointSetView& points, RbfKernel kernel, const Eigen::VectorXd& scaling,
                           double epsilon, double ridge, bool polynomial, const std::string& where) {
  if (!(ridge >= 0.0) || !std::isfinite(ridge)) throw std::invalid_argument("fitRbf: the ridge must be finite and >= 0");
  if (!(scaling.minCoeff() > 0.0) || !scaling.allFinite())
    throw std::invalid_argument("fitRbf: the scaling must be positive");
  if (!(epsilon > 0.0) || !std::isfinite(epsilon)) throw std::invalid_argument("fitRbf: epsilon must be positive");
  if (scaling.size() != points.features.cols())
    throw std::invalid_argument("fitRbf: the scaling needs one entry per feature");

  const Eigen::Index P = points.features.rows(), F = points.features.cols();
  const Eigen::Index T = polynomial ? 1 + F : 0;
  const Eigen::Index needed = polynomial ? 2 + F : 2;
  if (P < needed)
    throw InputError(where + ": " + std::to_string(P) + " feature point" + (P == 1 ? "" : "s") +
                     (P == 1 ? " " + featurePointText(points.features, 0) : "") +
                     " after augmentation; an RBF fit needs at least " + std::to_string(needed) +
                     (polynomial ? " (with the polynomial tail)" : "") + " distinct points");
  if (!points.values.allFinite() || !points.features.allFinite())
    throw InputError(where + ": non-finite feature or wrench after augmentation");
  if (P > limits::kMaxRbfCentres)
    throw InputError(where + ": " + std::to_string(P) + " feature points after augmentation, more than the " +
                     std::to_string(limits::kMaxRbfCentres) + " centres an RBF model may have (its fit solves a dense P x P system)");

  // A = [Φ + λI, P; Pᵀ, 0].
  const Eigen::MatrixXd scaled = points.features * scaling.asDiagonal();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(P + T, P + T);
  if (F == 2)
    fillKernelMatrix<2>(scaled, kernel, epsilon, A);
  else if (F == 3)
    fillKernelMatrix<3>(scaled, kernel, epsilon, A);
  else
    throw std::invalid_argument("fitRbf: points need 2 or 3 features");
  A.topLeftCorner(P, P).diagonal().array() += ridge;
  if (T) {
    A.block(0, P, P, 1).setOnes();
    A.block(0, P + 1, P, F) = points.features;
    A.block(P, 0, T, P) = A.block(0, P, P, T).transpose();
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(P + T, points.values.cols());
  rhs.topRows(P) = points.values;

  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
  RbfSolution out;
  out.rcond = lu.rcond();
  if (!(out.rcond >= kRbfMinRcond)) {
    // Name the two closest points: duplicates (or near-duplicates) are the usual cause.
    Eigen::Index a = 0, b = 1;
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < P; ++i)
      for (Eigen::Index k = 0; k < i; ++k)
        if (const double d = (scaled.row(i) - scaled.row(k)).norm(); d < best) {
          best = d;
          a = k;
          b = i;
        }
    std::ostringstream s;
    s << where << ": the RBF system is singular (reciprocal condition number " << std::setprecision(3) << out.rcond
      << " < " << kRbfMinRcond << "); the closest points are " << a << " " << featurePointText(points.features, a)
      << " (" << pointOriginName(points.origin[a]) << ") and " << b << " " << featurePointText(points.features, b)
      << " (" << pointOriginName(points.origin[b]) << "), " << best
      << " apart after scaling: remove duplicate or nearly coincident points, or set rbf.ridge > 0";
    if (polynomial)
      s << " (with the polynomial tail, the points must also not lie on one " << (F == 2 ? "line" : "plane") << ")";
    throw InputError(s.str());
  }
  const Eigen::MatrixXd inverse = lu.inverse();
  const Eigen::MatrixXd solution = inverse * rhs;
  if (!solution.allFinite()) throw InputError(where + ": the RBF system has no finite solution; set rbf.ridge > 0");

  out.weights = solution.topRows(P);
  if (T) out.polynomial = solution.bottomRows(T);
  out.loo_error.resize(P, points.values.cols());
  for (Eigen::Index i = 0; i < P; ++i) out.loo_error.row(i) = solution.row(i) / inverse(i, i);
  out.point_scale = pointScales(points.values);
  out.loo_relative = relativeVertexErrors(out.loo_error, out.point_scale, points.wrench_size);
  return out;
}

RbfFit fitRbf(const PlanarPoints& points, const RbfFitSettings& settings, const std::string& where) {
  const RbfKernelSpec& spec = settings.spec;
  RbfSolution solved = solveRbfSystem(viewOf(points), spec.kernel, spec.scaling, spec.epsilon, settings.ridge,
                                      settings.polynomial, where);
  RbfFit out;
  out.parameters.spec = spec;
  out.parameters.centres = points.features;
  out.parameters.weights = std::move(solved.weights);
  out.parameters.polynomial = std::move(solved.polynomial);
  out.loo_error = std::move(solved.loo_error);
  out.loo_relative = std::move(solved.loo_relative);
  out.point_scale = std::move(solved.point_scale);
  out.rcond = solved.rcond;
  return out;
}

namespace {
// "phi, beta" or "phi, beta, gamma" of point i, in the stream's current format.
void putFeatures(std::ostream& s, const Eigen::Ref<const Eigen::MatrixXd>& f, Eigen::Index i) {
  for (Eigen::Index c = 0; c < f.cols(); ++c) s << (c ? ", " : "") << f(i, c);
}
}  // namespace

std::string formatRbfLooReport(const PointSetView& pts, const RbfSolution& fit, double seconds) {
  const Eigen::Index P = pts.pointCount(), K = pts.vertexCount(), F = pts.features.cols();
  std::ostringstream s;
  std::array<int, 3> counts{0, 0, 0};
  for (PointOrigin o : pts.origin) ++counts[static_cast<int>(o)];
  s << "points: " << P << " (" << counts[0] << " measured, " << counts[1] << " mirrored, " << counts[2]
    << " zero-wrench above the surface), " << K << " vertices, " << (P + (fit.polynomial.size() ? 1 + F : 0))
    << " unknowns per component\n";
  s << std::setprecision(3) << "reciprocal condition number " << fit.rcond << ", fit time " << std::fixed
    << 1e3 * seconds << " ms\n"
    << std::defaultfloat;
  s << "leave-one-point-out error, relative to the largest wrench at the point (%):\n";
  s << "  vertex   max(measured)  rms(measured)   max(all)   worst point\n";
  for (Eigen::Index j = 0; j < K; ++j) {
    double max_measured = 0.0, sum2 = 0.0, max_all = 0.0;
    Eigen::Index worst = 0, measured = 0;
    for (Eigen::Index i = 0; i < P; ++i) {
      const double e = fit.loo_relative(i, j);
      if (pts.origin[i] == PointOrigin::Measured) {
        max_measured = std::max(max_measured, e);
        sum2 += e * e;
        ++measured;
      }
      if (!(e <= max_all)) {
        max_all = e;
        worst = i;
      }
    }
    s << "  " << std::setw(6) << j << std::fixed << std::setprecision(2) << std::setw(15) << 100 * max_measured
      << std::setw(15) << 100 * std::sqrt(sum2 / std::max<Eigen::Index>(measured, 1)) << std::setw(11) << 100 * max_all
      << std::defaultfloat << std::setprecision(4) << "   " << worst << " (";
    putFeatures(s, pts.features, worst);
    s << ", " << pointOriginName(pts.origin[worst]) << ")\n";
  }
  // The points whose left-out prediction is worst, over all vertices.
  std::vector<Eigen::Index> order(P);
  for (Eigen::Index i = 0; i < P; ++i) order[i] = i;
  const Eigen::VectorXd per_point = fit.loo_relative.rowwise().maxCoeff();
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return per_point[a] > per_point[b]; });
  s << "worst points (largest over the vertices, %):";
  for (Eigen::Index n = 0; n < std::min<Eigen::Index>(5, P); ++n) {
    const Eigen::Index i = order[n];
    s << (n ? "," : "") << " " << i << " (";
    putFeatures(s, pts.features, i);
    s << ") " << std::fixed << std::setprecision(2) << 100 * per_point[i] << std::defaultfloat << std::setprecision(6);
  }
  s << "\n" << std::setprecision(3) << "RMS over the measured points with a wrench, each at its worst vertex: "
    << 100 * measuredRms(fit.loo_relative, pts) << " % (warned above " << 100 * kLooWarnRms << " %)\n";
  return s.str();
}

std::string formatRbfFitReport(const RbfFitRecord& r) {
  std::string s = fitReportOpening("RBF", r.data, r.settings, r.from_data);
  RbfSolution solved;  // the report's view of the fit (copies are cheap next to the fit itself)
  solved.polynomial = r.fit.parameters.polynomial;
  solved.loo_relative = r.fit.loo_relative;
  solved.rcond = r.fit.rcond;
  s += formatRbfLooReport(viewOf(r.points), solved, r.seconds);
  return s + formatAboveSurface(r.above_surface) + formatFitWarnings(r.warnings);
}

void writeRbfFitGroup(h5::File& file, const RbfFitGroup& g) {
  file.createGroup("/fit");
  file.writeStringAttribute("/fit", "data", g.data);
  file.writeStringAttribute("/fit", "settings", g.settings.dump());
  file.writeStringAttribute("/fit", "report", g.report);
  file.writeDoubleAttribute("/fit", "seconds", g.seconds);
  std::string from_data;
  for (const std::string& d : g.from_data) from_data += d + "\n";
  file.writeStringAttribute("/fit", "from_data", from_data);
  file.writeStringAttribute("/fit", "warnings", g.warnings.empty() ? "" : formatFitWarnings(g.warnings));
  file.writeDoubleAttribute("/fit", "loo_rms", measuredRms(g.loo_relative, g.points));
  file.writeMatrix("/fit/points", g.points.features);
  Eigen::VectorXi origin(g.points.origin.size());
  for (size_t i = 0; i < g.points.origin.size(); ++i) origin[i] = static_cast<int>(g.points.origin[i]);
  file.writeIntegerVector("/fit/origin", origin);
  file.writeMatrix("/fit/values", g.points.values);
  file.writeMatrix("/fit/loo_error", g.loo_error);
  file.writeMatrix("/fit/loo_relative", g.loo_relative);
}

void saveRbfFit(const std::string& path, const RbfFitRecord& r, const PlanarGeometry& geometry) {
  const RbfFunction function(r.fit.parameters);
  h5::File file = h5::File::createAtomic(path);
  writeRbfModel(file, function, geometry);
  writeRbfFitGroup(file, {r.data, r.settings, formatRbfFitReport(r), r.seconds, r.from_data, r.warnings,
                          viewOf(r.points), r.fit.loo_error, r.fit.loo_relative});
  file.writeDoubleAttribute("/fit", "above_surface_share", r.above_surface.share());
  file.commit();
}

}  // namespace nmdp
