// The material weights of patches and of a material map: they sum to 1, stay in [0, 1], are C¹
// (the analytic gradient matches central differences of w, and the gradient itself changes by
// O(step) across the blending band, at the corners of a rectangle and of a polygon), are exactly 1
// inside a patch and 0 outside its band, and a polygon's contour integral gives the rectangle's
// closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "terrain/material_layout.hpp"
#include "terrain/material_regions.hpp"

namespace nmdp {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kBlend = 0.1;  // m

std::vector<double> weightsAt(const MaterialLayout& layout, double x, double y, std::vector<double>* gx = nullptr,
                              std::vector<double>* gy = nullptr) {
  const int M = layout.materialCount();
  std::vector<double> w(M), wx(M), wy(M);
  layout.weights(x, y, w.data(), wx.data(), wy.data());
  if (gx) *gx = wx;
  if (gy) *gy = wy;
  return w;
}

// Points on a grid around `centre` (half-size `half`), which covers the band and the corner there.
std::vector<Vec2> pointsAround(const Vec2& centre, double half, int n = 23) {
  std::vector<Vec2> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out.emplace_back(centre.x() - half + 2 * half * i / (n - 1.0) + 1e-4 * j, centre.y() - half + 2 * half * j / (n - 1.0) + 7e-5 * i);
  return out;
}

// Sums to 1, in [0, 1]; the gradient matches central differences of w (h = 1e-6 m, error ~ h² w''' +
// rounding 1e-16 / h: 1e-6 of the largest gradient, ~ 1 / kBlend = 10 per m, is ample); the
// gradient's own central difference over 2e-4 m stays below the largest second derivative the
// kernel allows (C¹: no jump of the gradient anywhere, a jump of g would show as g / 2e-4).
void expectSmoothPartition(const MaterialLayout& layout, const std::vector<Vec2>& points, const std::string& label) {
  const int M = layout.materialCount();
  const double h = 1e-6, H = 1e-4;
  // |∇²w| ≤ (1.5/h_k)² · 2 · (1.5/h_k) / ... bounded by 4 (1.5 / (kBlend / 2))³ kBlend-scale: take the
  // kernel's bound max|κ'| · max ∫κ = 2.25 / h_k² · 1 · 2 (two directions).
  const double second_bound = 2 * 2.25 / (0.25 * kBlend * kBlend) * 2;
  int in_band = 0;
  for (const Vec2& p : points) {
    std::vector<double> gx, gy;
    const std::vector<double> w = weightsAt(layout, p.x(), p.y(), &gx, &gy);
    double sum = 0;
    for (int m = 0; m < M; ++m) {
      sum += w[m];
      EXPECT_GE(w[m], 0.0) << label;
      EXPECT_LE(w[m], 1.0) << label;
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << label << " at " << p.transpose();
    const std::vector<double> xp = weightsAt(layout, p.x() + h, p.y()), xm = weightsAt(layout, p.x() - h, p.y());
    const std::vector<double> yp = weightsAt(layout, p.x(), p.y() + h), ym = weightsAt(layout, p.x(), p.y() - h);
    std::vector<double> gxp, gyp, gxm, gym, dummy;
    weightsAt(layout, p.x() + H, p.y(), &gxp, &dummy);
    weightsAt(layout, p.x() - H, p.y(), &gxm, &dummy);
    weightsAt(layout, p.x(), p.y() + H, &dummy, &gyp);
    weightsAt(layout, p.x(), p.y() - H, &dummy, &gym);
    for (int m = 0; m < M; ++m) {
      EXPECT_NEAR(gx[m], (xp[m] - xm[m]) / (2 * h), 1e-5) << label << " material " << m << " at " << p.transpose();
      EXPECT_NEAR(gy[m], (yp[m] - ym[m]) / (2 * h), 1e-5) << label << " material " << m << " at " << p.transpose();
      EXPECT_LT(std::abs(gxp[m] - gxm[m]) / (2 * H), second_bound) << label << " at " << p.transpose();
      EXPECT_LT(std::abs(gyp[m] - gym[m]) / (2 * H), second_bound) << label << " at " << p.transpose();
    }
    if (w[0] > 0 && w[0] < 1) ++in_band;
  }
  EXPECT_GT(in_band, 20) << label << ": the points should cover the band";
}

TEST(MaterialLayout, RectangleWeightsArePartitionOfUnityAndC1AtItsCorners) {
  const MaterialLayout layout({{"pit", MaterialRegion::rectangle(Vec2(0.5, -1.0), Vec2(2.0, 1.0))}}, kBlend);
  ASSERT_EQ(layout.materialCount(), 2);
  for (const Vec2& corner : {Vec2(0.5, -1.0), Vec2(2.0, 1.0), Vec2(0.5, 1.0)})
    expectSmoothPartition(layout, pointsAround(corner, 0.1), "rectangle corner");
  expectSmoothPartition(layout, pointsAround(Vec2(0.5, 0.0), 0.1), "rectangle edge");
}

TEST(MaterialLayout, PolygonWeightsArePartitionOfUnityAndC1AtConvexAndReflexCorners) {
  // An L shape, clockwise: convex corners and one reflex corner at (1, 1).
  const std::vector<Vec2> L = {{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}};
  ASSERT_EQ(polygonProblem(L), "");
  const MaterialLayout layout({{"L", MaterialRegion::polygon(L)}}, kBlend);
  for (const Vec2& corner : {Vec2(0, 0), Vec2(1, 1), Vec2(2, 1), Vec2(1, 2)})
    expectSmoothPartition(layout, pointsAround(corner, 0.1), "L corner " + std::to_string(corner.x()) + "," + std::to_string(corner.y()));
  // A triangle with a sharp (30°) corner.
  const std::vector<Vec2> tri = {{0, 0}, {2, 0}, {2, 2 * std::tan(M_PI / 6)}};
  const MaterialLayout sharp({{"tri", MaterialRegion::polygon(tri)}}, kBlend);
  expectSmoothPartition(sharp, pointsAround(Vec2(0.05, 0.02), 0.1), "sharp corner");
}

TEST(MaterialLayout, CircleWeightsArePartitionOfUnityAndC1) {
  const MaterialLayout layout({{"disc", MaterialRegion::circle(Vec2(1, 1), 0.5)}}, kBlend);
  expectSmoothPartition(layout, pointsAround(Vec2(1.5, 1.0), 0.08), "circle");
  expectSmoothPartition(layout, pointsAround(Vec2(1.0 + 0.5 / std::sqrt(2.0), 1.0 + 0.5 / std::sqrt(2.0)), 0.08), "circle diagonal");
}

TEST(MaterialLayout, PolygonContourIntegralEqualsTheRectangleClosedForm) {
  // The same region as a rectangle (closed-form product of steps) and as a polygon of either
  // orientation (Green's theorem, Gauss–Legendre per piece): one smoothed indicator, so they agree
  // to rounding (1e-13 of a weight of 1).
  const MaterialRegion rect = MaterialRegion::rectangle(Vec2(0, 0), Vec2(1, 0.5));
  const MaterialRegion ccw = MaterialRegion::polygon({{0, 0}, {1, 0}, {1, 0.5}, {0, 0.5}});
  const MaterialRegion cw = MaterialRegion::polygon({{0, 0}, {0, 0.5}, {1, 0.5}, {1, 0}});
  BlendKernel kernel;
  kernel.h = kBlend / 2;
  int band = 0;
  for (const Vec2& p : pointsAround(Vec2(1, 0.5), 0.1, 31)) {
    double rx, ry, px, py, qx, qy;
    const double r = rect.weight(kernel, p.x(), p.y(), rx, ry);
    EXPECT_NEAR(ccw.weight(kernel, p.x(), p.y(), px, py), r, 1e-13) << p.transpose();
    EXPECT_NEAR(cw.weight(kernel, p.x(), p.y(), qx, qy), r, 1e-13) << p.transpose();
    EXPECT_NEAR(px, rx, 1e-11);
    EXPECT_NEAR(py, ry, 1e-11);
    EXPECT_NEAR(qx, rx, 1e-11);
    EXPECT_NEAR(qy, ry, 1e-11);
    if (r > 0 && r < 1) ++band;
  }
  EXPECT_GT(band, 100);
}

TEST(MaterialLayout, ExactlyOneInsideAndZeroOutsideTheBand) {
  const std::vector<Vec2> L = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (const MaterialRegion& region : {MaterialRegion::rectangle(Vec2(0, 0), Vec2(2, 2)), MaterialRegion::polygon(L),
                                       MaterialRegion::circle(Vec2(1, 1), 0.9)}) {
    const MaterialLayout layout({{"patch", region}}, kBlend);
    std::vector<double> gx, gy;
    std::vector<double> w = weightsAt(layout, 0.5, 0.5, &gx, &gy);  // 0.5 m inside: beyond the band
    EXPECT_EQ(w[1], 1.0);
    EXPECT_EQ(w[0], 0.0);
    EXPECT_EQ(gx[1], 0.0);
    EXPECT_EQ(gy[1], 0.0);
    w = weightsAt(layout, -0.2, 0.5, &gx, &gy);  // 0.2 m outside
    EXPECT_EQ(w[0], 1.0);
    EXPECT_EQ(w[1], 0.0);
    EXPECT_EQ(gx[0], 0.0);
    // Half way across a straight edge: 1/2 each.
    w = weightsAt(layout, 0.0, 1.0, &gx, &gy);
    if (region.kind != MaterialRegion::Kind::Circle) {
      EXPECT_NEAR(w[1], 0.5, 1e-14);
    }
  }
}

TEST(MaterialLayout, RegionSeparationAndPolygonProblems) {
  const MaterialRegion a = MaterialRegion::rectangle(Vec2(0, 0), Vec2(1, 1));
  EXPECT_NEAR(regionSeparation(a, MaterialRegion::rectangle(Vec2(1.3, 0), Vec2(2, 1))), 0.3, 1e-12);
  EXPECT_EQ(regionSeparation(a, MaterialRegion::rectangle(Vec2(0.5, 0.5), Vec2(2, 2))), 0.0);
  EXPECT_EQ(regionSeparation(a, MaterialRegion::rectangle(Vec2(0.2, 0.2), Vec2(0.4, 0.4))), 0.0);  // inside
  EXPECT_NEAR(regionSeparation(a, MaterialRegion::circle(Vec2(2, 0.5), 0.5)), 0.5, 1e-12);
  EXPECT_EQ(regionSeparation(a, MaterialRegion::circle(Vec2(0.5, 0.5), 0.1)), 0.0);
  EXPECT_NEAR(regionSeparation(MaterialRegion::circle(Vec2(0, 3), 1), MaterialRegion::circle(Vec2(3, 3), 1)), 1.0, 1e-12);
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}}), "");
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}, {2, 0}}), "");                  // collinear: zero area
  EXPECT_NE(polygonProblem({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), "");          // a bow tie
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}), "");  // closed by repeating the first point
  EXPECT_EQ(polygonProblem({{0, 0}, {1, 0}, {1, 1}, {0, 1}}), "");
}

TEST(MaterialLayout, MaterialMapSumsToOneIsC1AndExactInUniformAreas) {
  MaterialGrid grid;
  grid.x0 = -1.0;
  grid.y0 = -0.5;
  grid.dx = 0.1;
  grid.dy = 0.2;
  grid.nx = 20;
  grid.ny = 8;
  grid.materials = 3;
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i) grid.material.push_back(i < 8 ? 0 : (j < 4 ? 1 : 2));
  const MaterialLayout layout(grid);
  ASSERT_EQ(layout.materialCount(), 3);
  // Where materials 0, 1 and 2 meet: node (8, 4) at (-0.2, 0.3).
  const int M = 3;
  const double h = 1e-6;
  int mixed = 0;
  for (const Vec2& p : pointsAround(Vec2(-0.25, 0.2), 0.2)) {
    std::vector<double> gx, gy;
    const std::vector<double> w = weightsAt(layout, p.x(), p.y(), &gx, &gy);
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-14);
    const std::vector<double> xp = weightsAt(layout, p.x() + h, p.y()), xm = weightsAt(layout, p.x() - h, p.y());
    const std::vector<double> yp = weightsAt(layout, p.x(), p.y() + h), ym = weightsAt(layout, p.x(), p.y() - h);
    for (int m = 0; m < M; ++m) {
      EXPECT_GE(w[m], 0.0);
      EXPECT_NEAR(gx[m], (xp[m] - xm[m]) / (2 * h), 1e-5 * 10) << p.transpose();
      EXPECT_NEAR(gy[m], (yp[m] - ym[m]) / (2 * h), 1e-5 * 10) << p.transpose();
    }
    if (w[1] > 0 && w[2] > 0 && w[0] > 0) ++mixed;
  }
  EXPECT_GT(mixed, 5);
  std::vector<double> gx, gy;
  EXPECT_EQ(weightsAt(layout, -0.9, 0.0, &gx, &gy)[0], 1.0);
  EXPECT_EQ(gx[0], 0.0);
  EXPECT_EQ(weightsAt(layout, 0.5, -0.4)[1], 1.0);
  EXPECT_EQ(weightsAt(layout, 5.0, 9.0)[2], 1.0);  // beyond the grid: the border's material
}

}  // namespace
}  // namespace nmdp
