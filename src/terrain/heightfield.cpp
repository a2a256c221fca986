#include "terrain/heightfield.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"

namespace nmdp {

void heightToQuery(const Vec3& p, const HeightSample& s, TerrainQuery& out, bool derivatives) {
  out.distance = p.z() - s.h;
  const Vec3 g(-s.hx, -s.hy, 1.0);  // ∇φ; ‖g‖ ≥ 1
  const double norm = g.norm();
  out.normal = g / norm;
  if (derivatives) {
    out.gradient = g;
    Mat3 dg = Mat3::Zero();  // ∂(∇φ)/∂p
    dg(0, 0) = -s.hxx;
    dg(0, 1) = -s.hxy;
    dg(1, 0) = -s.hxy;
    dg(1, 1) = -s.hyy;
    out.normal_jacobian = (Mat3::Identity() - out.normal * out.normal.transpose()) * dg / norm;
  }
}

// ------------------------------------------------------------------------------------------------
// The CSV reader.

namespace {

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

[[noreturn]] void failAt(const std::string& path, long line, long column, const std::string& what) {
  std::ostringstream m;
  m << displayPath(path) << ": line " << line;
  if (column > 0) m << ", column " << column;
  m << ": " << what;
  throw InputError(m.str());
}

// Parses one cell; throws InputError naming its position.
double parseCell(std::string_view cell, const std::string& path, long line, long column) {
  const std::string_view whole = trim(cell);
  const std::string text = std::string(whole.substr(0, 40)) + (whole.size() > 40 ? "..." : "");  // as messages show it
  if (whole.empty())
    failAt(path, line, column,
           "empty cell: holes in a heightfield are not supported, every grid node needs a finite height");
  std::string_view digits = whole;
  if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);  // from_chars rejects '+'
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range)
    failAt(path, line, column, "'" + std::string(text) + "' is out of the range of a double");
  if (ec != std::errc() || end != digits.data() + digits.size())
    failAt(path, line, column,
           "'" + std::string(text) + "' is not a number (values are separated by commas; comment lines start with '#')");
  if (std::isnan(value))
    failAt(path, line, column,
           "'" + std::string(text) + "': holes in a heightfield are not supported, every grid node needs a finite height");
  if (!std::isfinite(value)) failAt(path, line, column, "'" + std::string(text) + "' is not a finite height");
  return value;
}

}  // namespace

HeightGrid readHeightGridCsv(const std::string& path) {
  std::istringstream in(readInputFile(path, "heightfield file"));

  HeightGrid grid;
  long line_no = 0, first_row_line = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    long column = 0;
    size_t start = 0;
    const std::string_view whole(line);
    while (true) {
      const size_t comma = whole.find(',', start);
      const std::string_view cell = whole.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
      ++column;
      if (static_cast<std::int64_t>(grid.z.size()) >= limits::kMaxHeightfieldCells)
        failAt(path, line_no, column, "more than " + std::to_string(limits::kMaxHeightfieldCells) +
                                          " heights, beyond the largest heightfield nmdp takes (4096 x 4096)");
      grid.z.push_back(parseCell(cell, path, line_no, column));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (grid.ny == 0) {
      grid.nx = static_cast<int>(std::min<long>(column, INT_MAX));
      first_row_line = line_no;
    } else if (column != grid.nx) {
      std::ostringstream m;
      m << "this row has " << column << " value" << (column == 1 ? "" : "s") << " but the first row (line "
        << first_row_line << ") has " << grid.nx << ": every row of the grid needs the same number of values";
      failAt(path, line_no, 0, m.str());
    }
    if (grid.ny == INT_MAX) failAt(path, line_no, 0, "too many rows");
    ++grid.ny;
  }
  if (grid.nx < 2 || grid.ny < 2) {
    std::ostringstream m;
    m << path << ": a heightfield needs at least 2x2 values (2 rows of 2 comma-separated heights), got "
      << (grid.ny == 0 ? std::string("none") : std::to_string(grid.ny) + " row" + (grid.ny == 1 ? "" : "s") + " of " +
                                                    std::to_string(grid.nx));
    throw InputError(m.str());
  }
  return grid;
}

// ------------------------------------------------------------------------------------------------
// The spline.

namespace {

// Slopes of the not-a-knot cubic spline through values y[k·stride], k = 0..n−1, spacing h, into
// m[k·stride]. For n ≥ 4 the slopes solve the tridiagonal system
//   m0 + 2 m1                   = (−5 y0 + 4 y1 + y2) / 2h         (not-a-knot at x1, with row 1 eliminated)
//   m_{k−1} + 4 m_k + m_{k+1}   = 3 (y_{k+1} − y_{k−1}) / h        (C² at x_k)
//   2 m_{n−2} + m_{n−1}         = (5 y_{n−1} − 4 y_{n−2} − y_{n−3}) / 2h
// by the Thomas algorithm (stable here: every pivot is ≥ 3/7 for n ≥ 4).
void splineSlopes(const double* y, double* m, int n, int stride, double h, std::vector<double>& scratch_c,
                  std::vector<double>& scratch_d) {
  auto Y = [&](int k) { return y[static_cast<size_t>(k) * stride]; };
  auto M = [&](int k) -> double& { return m[static_cast<size_t>(k) * stride]; };
  if (n == 2) {
    M(0) = M(1) = (Y(1) - Y(0)) / h;
    return;
  }
  if (n == 3) {  // the parabola through the three points
    M(0) = (-3 * Y(0) + 4 * Y(1) - Y(2)) / (2 * h);
    M(1) = (Y(2) - Y(0)) / (2 * h);
    M(2) = (Y(0) - 4 * Y(1) + 3 * Y(2)) / (2 * h);
    return;
  }
  std::vector<double>& c = scratch_c;
  std::vector<double>& d = scratch_d;
  c.assign(n, 0.0);
  d.assign(n, 0.0);
  // Row 0: b = 1, c = 2.
  c[0] = 2.0;
  d[0] = (-5 * Y(0) + 4 * Y(1) + Y(2)) / (2 * h);
  for (int k = 1; k < n - 1; ++k) {  // a = 1, b = 4, c = 1
    const double denom = 4.0 - c[k - 1];
    c[k] = 1.0 / denom;
    d[k] = (3 * (Y(k + 1) - Y(k - 1)) / h - d[k - 1]) / denom;
  }
  {  // Row n−1: a = 2, b = 1.
    const int k = n - 1;
    const double denom = 1.0 - 2.0 * c[k - 1];
    d[k] = ((5 * Y(k) - 4 * Y(k - 1) - Y(k - 2)) / (2 * h) - 2.0 * d[k - 1]) / denom;
  }
  M(n - 1) = d[n - 1];
  for (int k = n - 2; k >= 0; --k) M(k) = d[k] - c[k] * M(k + 1);
}

// Cubic Hermite weights on a cell of width w at t ∈ [0, 1], for derivative order 0, 1, 2 in x:
// value weights v0, v1 (of the node values) and slope weights s0, s1 (of the node slopes).
struct HermiteWeights {
  double v0[3], s0[3], v1[3], s1[3];
};

inline void hermite(double t, double w, bool zero_derivatives, HermiteWeights& hw) {
  const double t2 = t * t, t3 = t2 * t;
  hw.v0[0] = 2 * t3 - 3 * t2 + 1;
  hw.s0[0] = (t3 - 2 * t2 + t) * w;
  hw.v1[0] = -2 * t3 + 3 * t2;
  hw.s1[0] = (t3 - t2) * w;
  if (zero_derivatives) {  // clamped outside the grid: h does not vary along this axis
    for (int o = 1; o < 3; ++o) hw.v0[o] = hw.s0[o] = hw.v1[o] = hw.s1[o] = 0.0;
    return;
  }
  hw.v0[1] = (6 * t2 - 6 * t) / w;
  hw.s0[1] = 3 * t2 - 4 * t + 1;
  hw.v1[1] = (-6 * t2 + 6 * t) / w;
  hw.s1[1] = 3 * t2 - 2 * t;
  hw.v0[2] = (12 * t - 6) / (w * w);
  hw.s0[2] = (6 * t - 4) / w;
  hw.v1[2] = (-12 * t + 6) / (w * w);
  hw.s1[2] = (6 * t - 2) / w;
}

// Cell index and local coordinate along one axis; `outside` when the coordinate was clamped.
inline void locate(double x, double x0, double dx, int n, int& cell, double& t, bool& outside) {
  const double s = (x - x0) / dx;
  const double last = static_cast<double>(n - 1);
  outside = false;
  if (!(s > 0.0)) {  // also catches s = 0
    outside = s < 0.0;
    cell = 0;
    t = 0.0;
  } else if (!(s < last)) {
    outside = s > last;
    cell = n - 2;
    t = 1.0;
  } else {
    cell = std::min(static_cast<int>(s), n - 2);
    t = s - cell;
  }
}

}  // namespace

HeightfieldTerrain::HeightfieldTerrain(HeightGrid grid, std::string source)
    : grid_(std::move(grid)), source_(std::move(source)) {
  const HeightGrid& g = grid_;
  if (g.nx < 2 || g.ny < 2) throw std::invalid_argument("heightfield terrain: needs at least 2x2 grid nodes");
  if (g.nx > INT_MAX / g.ny) throw std::invalid_argument("heightfield terrain: grid too large");
  if (!(g.dx > 0.0) || !(g.dy > 0.0) || !std::isfinite(g.dx) || !std::isfinite(g.dy))
    throw std::invalid_argument("heightfield terrain: the grid spacing must be positive and finite");
  if (!std::isfinite(g.x0) || !std::isfinite(g.y0))
    throw std::invalid_argument("heightfield terrain: the grid origin must be finite");
  const size_t count = static_cast<size_t>(g.nx) * static_cast<size_t>(g.ny);
  if (g.z.size() != count) throw std::invalid_argument("heightfield terrain: expected nx*ny heights");
  for (double v : g.z)
    if (!std::isfinite(v)) throw std::invalid_argument("heightfield terrain: every height must be finite");

  zx_.assign(count, 0.0);
  zy_.assign(count, 0.0);
  zxy_.assign(count, 0.0);
  std::vector<double> c, d;
  for (int j = 0; j < g.ny; ++j)  // h_x: spline along each row
    splineSlopes(&g.z[static_cast<size_t>(j) * g.nx], &zx_[static_cast<size_t>(j) * g.nx], g.nx, 1, g.dx, c, d);
  for (int i = 0; i < g.nx; ++i) {  // h_y and h_xy: splines along each column of h and h_x
    splineSlopes(&g.z[i], &zy_[i], g.ny, g.nx, g.dy, c, d);
    splineSlopes(&zx_[i], &zxy_[i], g.ny, g.nx, g.dy, c, d);
  }
}

HeightSample HeightfieldTerrain::sample(double x, double y, bool second) const {
  HeightSample s;
  if (std::isnan(x) || std::isnan(y)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.h = s.hx = s.hy = s.hxx = s.hxy = s.hyy = nan;
    return s;
  }
  const HeightGrid& g = grid_;
  int i = 0, j = 0;
  double t = 0.0, u = 0.0;
  bool out_x = false, out_y = false;
  locate(x, g.x0, g.dx, g.nx, i, t, out_x);
  locate(y, g.y0, g.dy, g.ny, j, u, out_y);
  HermiteWeights wx, wy;
  hermite(t, g.dx, out_x, wx);
  hermite(u, g.dy, out_y, wy);

  // The 4 corners: (a, b) ∈ {0, 1}², node (i + a, j + b).
  const size_t k00 = static_cast<size_t>(j) * g.nx + i;
  const size_t corner[2][2] = {{k00, k00 + g.nx}, {k00 + 1, k00 + 1 + g.nx}};  // [a][b]
  auto eval = [&](int ox, int oy) {
    double r = 0.0;
    for (int a = 0; a < 2; ++a) {
      const double vx = a == 0 ? wx.v0[ox] : wx.v1[ox];
      const double sx = a == 0 ? wx.s0[ox] : wx.s1[ox];
      for (int b = 0; b < 2; ++b) {
        const double vy = b == 0 ? wy.v0[oy] : wy.v1[oy];
        const double sy = b == 0 ? wy.s0[oy] : wy.s1[oy];
        const size_t k = corner[a][b];
        r += vx * vy * g.z[k] + sx * vy * zx_[k] + vx * sy * zy_[k] + sx * sy * zxy_[k];
      }
    }
    return r;
  };
  s.h = eval(0, 0);
  s.hx = eval(1, 0);
  s.hy = eval(0, 1);
  if (second) {
    s.hxx = eval(2, 0);
    s.hxy = eval(1, 1);
    s.hyy = eval(0, 2);
  }
  return s;
}

void HeightfieldTerrain::query(const Vec3& p, TerrainQuery& out, bool derivatives) const {
  heightToQuery(p, sample(p.x(), p.y(), derivatives), out, derivatives);
}

std::string HeightfieldTerrain::describe() const {
  const auto [lo, hi] = std::minmax_element(grid_.z.begin(), grid_.z.end());
  std::ostringstream s;
  s << "heightfield";
  if (!source_.empty()) s << " '" << source_ << "'";
  s << ": " << grid_.nx << "x" << grid_.ny << " nodes, origin (" << grid_.x0 << ", " << grid_.y0 << ") m, spacing ("
    << grid_.dx << ", " << grid_.dy << ") m, heights in [" << *lo << ", " << *hi
    << "] m; bicubic spline, clamped to the border outside the grid";
  return s.str();
}

}  // namespace nmdp
