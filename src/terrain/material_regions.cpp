#include "terrain/material_regions.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nmdp {

namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The quadratic B-spline on [−1.5, 1.5] (unit integral), its derivative and its integral from −1.5.
double bspline(double t) {
  const double a = std::abs(t);
  if (a <= 0.5) return 0.75 - t * t;
  if (a < 1.5) return 0.5 * (1.5 - a) * (1.5 - a);
  return 0.0;
}
double bsplineSlope(double t) {
  const double a = std::abs(t);
  if (a <= 0.5) return -2.0 * t;
  if (a < 1.5) return (t > 0 ? -1.0 : 1.0) * (1.5 - a);
  return 0.0;
}
double bsplineIntegral(double t) {
  if (t <= -1.5) return 0.0;
  if (t <= -0.5) return (t + 1.5) * (t + 1.5) * (t + 1.5) / 6.0;
  if (t <= 0.5) return 1.0 / 6.0 + 0.75 * (t + 0.5) - (t * t * t + 0.125) / 3.0;
  if (t < 1.5) return 1.0 - (1.5 - t) * (1.5 - t) * (1.5 - t) / 6.0;
  return 1.0;
}

// Whether the segment a→b meets the closed box [lo, hi] (Liang–Barsky clipping).
bool segmentMeetsBox(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) {
      if (a[axis] < lo[axis] || a[axis] > hi[axis]) return false;
      continue;
    }
    double ta = (lo[axis] - a[axis]) / d[axis], tb = (hi[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

bool onSegment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

// Whether the closed segments ab and cd share a point.
bool segmentsMeet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && onSegment(a, b, c)) || (d2 == 0 && onSegment(a, b, d)) || (d3 == 0 && onSegment(c, d, a)) ||
         (d4 == 0 && onSegment(c, d, b));
}

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

double pointBoundaryDistance(const Vec2& p, const std::vector<Vec2>& points) {
  double best = INFINITY;
  for (size_t i = 0; i < points.size(); ++i)
    best = std::min(best, pointSegmentDistance(p, points[i], points[(i + 1) % points.size()]));
  return best;
}

bool polygonContains(const std::vector<Vec2>& points, const Vec2& p) {
  bool inside = false;
  for (size_t i = 0, j = points.size() - 1; i < points.size(); j = i++) {
    const Vec2& a = points[i];
    const Vec2& b = points[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

double signedArea(const std::vector<Vec2>& points) {
  double twice = 0.0;
  for (size_t i = 0; i < points.size(); ++i) twice += cross(points[i], points[(i + 1) % points.size()]);
  return 0.5 * twice;
}

// w = ∮ S(u − x) κ(y − v) dv over the polygon's edges (counter-clockwise), with its gradient.
double polygonWeight(const std::vector<Vec2>& points, double orientation, const BlendKernel& kernel, double x, double y,
                     double& wx, double& wy) {
  const double h = kernel.h;
  const Vec2 lo(x - h, y - h), hi(x + h, y + h);
  bool near_edge = false;
  for (size_t i = 0; i < points.size() && !near_edge; ++i)
    near_edge = segmentMeetsBox(points[i], points[(i + 1) % points.size()], lo, hi);
  wx = wy = 0.0;
  if (!near_edge) return polygonContains(points, Vec2(x, y)) ? 1.0 : 0.0;

  static constexpr double kNode = 0.7745966692414834;  // √(3/5)
  static constexpr double kNodes[3] = {-kNode, 0.0, kNode};
  static constexpr double kWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double knots[4] = {-h, -h / 3.0, h / 3.0, h};
  double w = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec2& a = points[i];
    const Vec2& b = points[(i + 1) % points.size()];
    const double du = b.x() - a.x(), dv = b.y() - a.y();
    if (dv == 0.0) continue;  // dv = 0 along the edge: no contribution
    const double ta = (y - h - a.y()) / dv, tb = (y + h - a.y()) / dv;
    const double t_lo = std::max(0.0, std::min(ta, tb)), t_hi = std::min(1.0, std::max(ta, tb));
    if (!(t_lo < t_hi)) continue;
    // Breakpoints: where u − x or y − v crosses a knot of the kernel.
    double breaks[10];
    int n = 0;
    breaks[n++] = t_lo;
    for (double q : knots) {
      const double tv = (y - q - a.y()) / dv;
      if (tv > t_lo && tv < t_hi) breaks[n++] = tv;
      if (du != 0.0) {
        const double tu = (x + q - a.x()) / du;
        if (tu > t_lo && tu < t_hi) breaks[n++] = tu;
      }
    }
    breaks[n++] = t_hi;
    std::sort(breaks, breaks + n);
    for (int k = 0; k + 1 < n; ++k) {
      const double half = 0.5 * (breaks[k + 1] - breaks[k]), mid = 0.5 * (breaks[k + 1] + breaks[k]);
      if (!(half > 0.0)) continue;
      for (int g = 0; g < 3; ++g) {
        const double t = mid + half * kNodes[g];
        const double u = a.x() + t * du, v = a.y() + t * dv;
        const double c = kWeights[g] * half * dv;
        const double kv = kernel.density(y - v);
        w += c * kernel.step(u - x) * kv;
        wx -= c * kernel.density(u - x) * kv;
        wy += c * kernel.step(u - x) * kernel.slope(y - v);
      }
    }
  }
  wx *= orientation;
  wy *= orientation;
  return std::clamp(orientation * w, 0.0, 1.0);
}

}  // namespace

double BlendKernel::density(double s) const { return 1.5 / h * bspline(1.5 * s / h); }
double BlendKernel::slope(double s) const { return 2.25 / (h * h) * bsplineSlope(1.5 * s / h); }
double BlendKernel::step(double s) const { return bsplineIntegral(1.5 * s / h); }

MaterialRegion MaterialRegion::rectangle(const Vec2& min, const Vec2& max) {
  MaterialRegion r;
  r.kind = Kind::Rectangle;
  r.points = {min, Vec2(max.x(), min.y()), max, Vec2(min.x(), max.y())};
  return r;
}

MaterialRegion MaterialRegion::circle(const Vec2& centre, double radius) {
  MaterialRegion r;
  r.kind = Kind::Circle;
  r.centre = centre;
  r.radius = radius;
  return r;
}

MaterialRegion MaterialRegion::polygon(std::vector<Vec2> points) {
  MaterialRegion r;
  r.kind = Kind::Polygon;
  r.orientation = signedArea(points) >= 0 ? 1.0 : -1.0;
  r.points = std::move(points);
  return r;
}

double MaterialRegion::weight(const BlendKernel& kernel, double x, double y, double& wx, double& wy) const {
  switch (kind) {
    case Kind::Rectangle: {
      const Vec2& lo = points[0];
      const Vec2& hi = points[2];
      const double X = kernel.step(x - lo.x()) - kernel.step(x - hi.x());
      const double Y = kernel.step(y - lo.y()) - kernel.step(y - hi.y());
      wx = (kernel.density(x - lo.x()) - kernel.density(x - hi.x())) * Y;
      wy = X * (kernel.density(y - lo.y()) - kernel.density(y - hi.y()));
      return X * Y;
    }
    case Kind::Circle: {
      const Vec2 d(x - centre.x(), y - centre.y());
      const double rho = d.norm();
      const double s = radius - rho;
      if (rho > 0.0) {
        const double k = kernel.density(s);
        wx = -k * d.x() / rho;
        wy = -k * d.y() / rho;
      } else {
        wx = wy = 0.0;  // the centre lies at least h inside (radius > h), where w = 1
      }
      return kernel.step(s);
    }
    case Kind::Polygon: return polygonWeight(points, orientation, kernel, x, y, wx, wy);
  }
  return 0.0;
}

double MaterialRegion::reach(const BlendKernel& kernel) const {
  return kind == Kind::Circle ? kernel.h : kernel.h * std::sqrt(2.0);
}

Vec2 MaterialRegion::lower() const {
  if (kind == Kind::Circle) return centre.array() - radius;
  Vec2 lo = points[0];
  for (const Vec2& p : points) lo = lo.cwiseMin(p);
  return lo;
}

Vec2 MaterialRegion::upper() const {
  if (kind == Kind::Circle) return centre.array() + radius;
  Vec2 hi = points[0];
  for (const Vec2& p : points) hi = hi.cwiseMax(p);
  return hi;
}

bool MaterialRegion::contains(const Vec2& p) const {
  if (kind == Kind::Circle) return (p - centre).norm() <= radius;
  return polygonContains(points, p);
}

std::string polygonProblem(const std::vector<Vec2>& points) {
  const size_t n = points.size();
  if (n < 3) return "a polygon needs at least 3 points [x, y], got " + std::to_string(n);
  for (size_t i = 0; i < n; ++i)
    if (!points[i].allFinite()) return "point " + std::to_string(i) + " is not finite";
  for (size_t i = 0; i < n; ++i)
    if (points[i] == points[(i + 1) % n])
      return "points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) + " are the same" +
             (i + 1 == n ? " (do not repeat the first point at the end: the polygon closes itself)" : "");
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = points[i];
    const Vec2& b = points[(i + 1) % n];
    const Vec2& c = points[(i + 2) % n];
    if (cross(b - a, c - b) == 0.0 && (b - a).dot(c - b) < 0.0)
      return "the edges at point " + std::to_string((i + 1) % n) + " fold back on each other (a zero-width spike)";
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segmentsMeet(a, b, points[j], points[(j + 1) % n]))
        return "edges " + std::to_string(i) + " and " + std::to_string(j) +
               " cross or touch: the polygon intersects itself (give its points in order around it)";
    }
  }
  double scale = 0.0;
  for (const Vec2& p : points) scale = std::max(scale, (p - points[0]).norm());
  if (!(std::abs(signedArea(points)) > 1e-12 * scale * scale)) return "the polygon has zero area (its points are collinear)";
  return "";
}

double regionSeparation(const MaterialRegion& a, const MaterialRegion& b) {
  using Kind = MaterialRegion::Kind;
  if (a.kind == Kind::Circle && b.kind == Kind::Circle)
    return std::max(0.0, (a.centre - b.centre).norm() - a.radius - b.radius);
  if (a.kind == Kind::Circle || b.kind == Kind::Circle) {
    const MaterialRegion& circle = a.kind == Kind::Circle ? a : b;
    const MaterialRegion& poly = a.kind == Kind::Circle ? b : a;
    if (poly.contains(circle.centre)) return 0.0;
    return std::max(0.0, pointBoundaryDistance(circle.centre, poly.points) - circle.radius);
  }
  const size_t na = a.points.size(), nb = b.points.size();
  for (size_t i = 0; i < na; ++i)
    for (size_t j = 0; j < nb; ++j)
      if (segmentsMeet(a.points[i], a.points[(i + 1) % na], b.points[j], b.points[(j + 1) % nb])) return 0.0;
  if (a.contains(b.points[0]) || b.contains(a.points[0])) return 0.0;
  double best = INFINITY;
  for (const Vec2& p : a.points) best = std::min(best, pointBoundaryDistance(p, b.points));
  for (const Vec2& p : b.points) best = std::min(best, pointBoundaryDistance(p, a.points));
  return best;
}

}  // namespace nmdp
