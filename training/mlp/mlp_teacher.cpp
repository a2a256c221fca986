// The teacher grid of fitMlp (training/mlp/mlp_fit.hpp): the RBF of the "rbf" section through the
// training points, sampled on a grid over their box at or below the surface.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact_models/rbf_function.hpp"
#include "training/mlp/mlp_training.hpp"
#include "training/rbf_fit.hpp"

namespace nmdp {

// The RBF of `rbf` through the training points, sampled on the grid s.teacher_grid over the box of
// the training points at or below the surface (measured and mirrored).
PlanarPoints mlpTeacherSamples(const PlanarPoints& points, const std::vector<int>& train, const MlpFitSettings& s,
                            const RbfFitSettings& rbf_settings, const std::string& where) {
  PlanarPoints fitted;
  fitted.features.resize(train.size(), 2);
  fitted.values.resize(train.size(), points.values.cols());
  for (size_t r = 0; r < train.size(); ++r) {
    fitted.features.row(r) = points.features.row(train[r]);
    fitted.values.row(r) = points.values.row(train[r]);
    fitted.origin.push_back(points.origin[train[r]]);
  }
  const RbfFunction rbf(fitRbf(fitted, rbf_settings, where + " (mlp.teacher_grid's RBF)").parameters);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i = 0; i < fitted.pointCount(); ++i)
    if (fitted.origin[i] != PointOrigin::AboveSurface) {
      lo = lo.cwiseMin(fitted.features.row(i).transpose());
      hi = hi.cwiseMax(fitted.features.row(i).transpose());
    }
  PlanarPoints teacher;
  if (!(lo[0] <= hi[0])) return teacher;  // no point at or below the surface
  const int n0 = s.teacher_grid[0], n1 = s.teacher_grid[1];
  const std::vector<double> rows = teacherDepthRows(lo[0], hi[0], n0, s.teacher_depth_power);
  std::vector<double> columns;
  for (int b = 0; b < n1; ++b) columns.push_back(n1 > 1 ? lo[1] + (hi[1] - lo[1]) * b / (n1 - 1.0) : lo[1]);
  // Extra columns beside the data's angles, where the thin-plate teacher bends sharply (its
  // ρ² log ρ kernel at the zero-wrench surface points).
  if (!s.teacher_refinement.empty()) {
    std::vector<double> data_angles;
    for (int i = 0; i < fitted.pointCount(); ++i)
      if (fitted.origin[i] != PointOrigin::AboveSurface) data_angles.push_back(fitted.features(i, 1));
    std::sort(data_angles.begin(), data_angles.end());
    data_angles.erase(std::unique(data_angles.begin(), data_angles.end()), data_angles.end());
    for (double angle : data_angles)
      for (double offset : s.teacher_refinement)
        for (double c : {angle - offset, angle + offset})
          if (c >= lo[1] && c <= hi[1]) columns.push_back(c);
    std::sort(columns.begin(), columns.end());  // columns closer than 1e-9 rad are one (round-off)
    columns.erase(std::unique(columns.begin(), columns.end(), [](double a, double b) { return b - a <= 1e-9; }),
                  columns.end());
  }
  const int nc = static_cast<int>(columns.size());
  teacher.features.resize(n0 * nc, 2);
  for (int a = 0; a < n0; ++a)
    for (int b = 0; b < nc; ++b) teacher.features.row(a * nc + b) << rows[a], columns[b];
  rbf.evaluate(teacher.features, teacher.values, nullptr, nullptr);
  teacher.origin.assign(n0 * nc, PointOrigin::Measured);
  return teacher;
}

std::vector<double> teacherDepthRows(double lo, double hi, int n, double power) {
  std::vector<double> rows(std::max(n, 0));
  for (int a = 0; a < n; ++a)
    rows[a] = n < 2 ? lo
              : power == 1.0 ? lo + (hi - lo) * a / (n - 1.0)  // the even grid, as before the option existed
              : a + 1 == n ? hi
                           : lo + (hi - lo) * (1.0 - std::pow(1.0 - a / (n - 1.0), power));
  return rows;
}

}  // namespace nmdp
