// Terrains (DESIGN.md §8, §10): plane, heightfield (bicubic spline from a CSV file) and procedural
// slopes + Gaussian hills, built through makeTerrain.
//  * derivatives: ∇φ against central differences of φ, ∂n/∂p against central differences of n,
//    ‖n‖ = 1, at random points (for the heightfield also on and next to cell boundaries);
//  * the heightfield interpolates its nodes, is C¹ (in fact C²) across cell boundaries, reproduces
//    bicubic polynomials exactly and approximates a smooth function to O(h⁴), and is clamped to
//    its border outside the grid;
//  * bad input (holes, 'nan', ragged rows, missing file, non-numeric cells, too small grids, bad
//    spacing, unknown type or key) throws InputError naming the file, line and column or the key;
//  * query() allocates nothing (operator new is counted in this test binary).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "common/input_error.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/plane.hpp"
#include "terrain/procedural.hpp"
#include "terrain/terrain_factory.hpp"
#include "test_support.hpp"

#define NMDP_COUNT_OPERATOR_NEW  // operator new is counted in this test binary (not malloc)
#include "test_allocation_counter.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {
using nlohmann::json;

// A grid sampled from f, written as CSV with full precision (and a comment header).
struct GridSpec {
  double x0, y0, dx, dy;
  int nx, ny;
  double x(int i) const { return x0 + i * dx; }
  double y(int j) const { return y0 + j * dy; }
  double xEnd() const { return x(nx - 1); }
  double yEnd() const { return y(ny - 1); }
  json config(const std::string& file) const {
    return {{"type", "heightfield"}, {"file", file}, {"origin", {x0, y0}}, {"spacing", {dx, dy}}};
  }
};

template <class F>
std::string gridCsv(const GridSpec& g, F f) {
  std::ostringstream s;
  s.precision(17);
  s << "# test grid, " << g.nx << " x " << g.ny << "\n";
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) s << (i ? "," : "") << f(g.x(i), g.y(j));
    s << "\n";
  }
  return s.str();
}

// A smooth test surface and its derivatives.
double smoothH(double x, double y) { return 0.15 * std::sin(1.1 * x + 0.3) * std::cos(0.8 * y) + 0.02 * x * y - 0.03 * x * x; }

// A bicubic polynomial (degree ≤ 3 in x and in y) and its derivatives.
struct Cubic {
  double h(double x, double y) const {
    return 0.3 + 0.2 * x - 0.1 * y + 0.05 * x * x - 0.04 * x * y + 0.03 * y * y + 0.02 * x * x * x -
           0.01 * x * x * y + 0.015 * x * y * y - 0.025 * y * y * y + 0.01 * x * x * x * y * y * y;
  }
  double hx(double x, double y) const {
    return 0.2 + 0.1 * x - 0.04 * y + 0.06 * x * x - 0.02 * x * y + 0.015 * y * y + 0.03 * x * x * y * y * y;
  }
  double hy(double x, double y) const {
    return -0.1 - 0.04 * x + 0.06 * y - 0.01 * x * x + 0.03 * x * y - 0.075 * y * y + 0.03 * x * x * x * y * y;
  }
  double hxx(double x, double y) const { return 0.1 + 0.12 * x - 0.02 * y + 0.06 * x * y * y * y; }
  double hxy(double x, double y) const { return -0.04 - 0.02 * x + 0.03 * y + 0.09 * x * x * y * y; }
  double hyy(double x, double y) const { return 0.06 + 0.03 * x - 0.15 * y + 0.06 * x * x * x * y; }
};

// ∇φ and ∂n/∂p against central differences at p; ‖n‖ = 1; the query without derivatives agrees.
void checkDerivatives(const Terrain& terrain, const Vec3& p, double tol, const std::string& label) {
  SCOPED_TRACE(label + " at p = (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " +
               std::to_string(p.z()) + ")");
  TerrainQuery q, q0;
  terrain.query(p, q, true);
  terrain.query(p, q0, false);
  EXPECT_EQ(q.distance, q0.distance);
  EXPECT_EQ(q.normal, q0.normal);
  EXPECT_NEAR(q.normal.norm(), 1.0, 1e-14);
  EXPECT_GT(q.normal.dot(q.gradient), 0.0);
  EXPECT_LT((q.normal - q.gradient.normalized()).norm(), 1e-14);
  const double eps = 1e-6;
  const Eigen::MatrixXd fd_grad = centralDifference(
      [&](const Eigen::VectorXd& x) {
        TerrainQuery r;
        terrain.query(Vec3(x), r, false);
        return Eigen::VectorXd::Constant(1, r.distance);
      },
      Eigen::VectorXd(p), eps);
  const Eigen::MatrixXd fd_normal = centralDifference(
      [&](const Eigen::VectorXd& x) {
        TerrainQuery r;
        terrain.query(Vec3(x), r, false);
        return Eigen::VectorXd(r.normal);
      },
      Eigen::VectorXd(p), eps);
  EXPECT_LT((Eigen::MatrixXd(q.gradient.transpose()) - fd_grad).cwiseAbs().maxCoeff(), tol)
      << "gradient " << q.gradient.transpose() << "\nfd " << fd_grad;
  EXPECT_LT((Eigen::MatrixXd(q.normal_jacobian) - fd_normal).cwiseAbs().maxCoeff(), tol)
      << "normal_jacobian\n" << q.normal_jacobian << "\nfd\n" << fd_normal;
  // n stays unit: nᵀ ∂n/∂p = 0.
  EXPECT_LT((q.normal.transpose() * q.normal_jacobian).cwiseAbs().maxCoeff(), 1e-13);
}

#define EXPECT_MESSAGE_HAS(message, part) \
  EXPECT_NE(std::string(message).find(part), std::string::npos) << "message: " << (message) << "\nmissing: " << (part)

// ------------------------------------------------------------------------------------------------
// Plane.

TEST(Terrain, TiltedPlaneDerivatives) {
  const auto terrain = makeTerrain(json{{"type", "plane"}, {"normal", {0.3, -0.2, 1.0}}, {"offset", 0.1}}, {"test", ""});
  const Vec3 n = Vec3(0.3, -0.2, 1.0).normalized();
  TerrainQuery q;
  terrain->query(0.1 * n + 0.5 * n, q, true);
  EXPECT_NEAR(q.distance, 0.5, 1e-15);
  EXPECT_LT((q.normal - n).norm(), 1e-15);
  std::mt19937 rng(1);
  for (int k = 0; k < 20; ++k) checkDerivatives(*terrain, Vec3(randomVector(rng, 3, 2.0)), 1e-8, "tilted plane");
}

TEST(Terrain, DefaultIsAHorizontalPlane) {
  for (const json& config : {json::object(), json(), json{{"type", "plane"}}}) {
    const auto terrain = makeTerrain(config, {"scene.json: terrain", ""});
    TerrainQuery q;
    terrain->query(Vec3(1.0, -2.0, 0.25), q, true);
    EXPECT_DOUBLE_EQ(q.distance, 0.25);
    EXPECT_EQ(q.normal, Vec3::UnitZ());
    EXPECT_MESSAGE_HAS(terrain->describe(), "plane");
  }
  // No type but plane keys: still a plane.
  const auto tilted = makeTerrain(json{{"normal", {1.0, 0.0, 1.0}}}, {"scene.json: terrain", ""});
  TerrainQuery q;
  tilted->query(Vec3::Zero(), q, false);
  EXPECT_LT((q.normal - Vec3(1, 0, 1).normalized()).norm(), 1e-15);
}

// ------------------------------------------------------------------------------------------------
// Heightfield.

class HeightfieldTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = {-1.5, -1.2, 0.1, 0.12, 31, 21};
    dir_.write("smooth.csv", gridCsv(spec_, smoothH));
    terrain_ = makeTerrain(spec_.config("smooth.csv"), {"test: terrain", dir_.dir()});
    field_ = dynamic_cast<const HeightfieldTerrain*>(terrain_.get());
    ASSERT_NE(field_, nullptr);
  }
  TempDir dir_;
  GridSpec spec_{};
  std::unique_ptr<Terrain> terrain_;
  const HeightfieldTerrain* field_ = nullptr;
};

TEST_F(HeightfieldTest, LoadsTheGrid) {
  const HeightGrid& g = field_->grid();
  EXPECT_EQ(g.nx, spec_.nx);
  EXPECT_EQ(g.ny, spec_.ny);
  EXPECT_EQ(g.dx, spec_.dx);
  EXPECT_EQ(g.dy, spec_.dy);
  EXPECT_EQ(g.x0, spec_.x0);
  EXPECT_EQ(g.y0, spec_.y0);
  EXPECT_MESSAGE_HAS(terrain_->describe(), "smooth.csv");
}

TEST_F(HeightfieldTest, ReproducesNodeValues) {
  for (int j = 0; j < spec_.ny; ++j)
    for (int i = 0; i < spec_.nx; ++i) {
      TerrainQuery q;
      const double x = spec_.x(i), y = spec_.y(j);
      terrain_->query(Vec3(x, y, 0.7), q, false);
      EXPECT_NEAR(q.distance, 0.7 - smoothH(x, y), 1e-14) << "node " << i << ", " << j;
    }
}

TEST_F(HeightfieldTest, DerivativesAtRandomPointsAndCellBoundaries) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(spec_.x0 + 1e-3, spec_.xEnd() - 1e-3), uy(spec_.y0 + 1e-3, spec_.yEnd() - 1e-3),
      uz(-0.5, 0.5);
  std::uniform_int_distribution<int> ci(1, spec_.nx - 2), cj(1, spec_.ny - 2);
  for (int k = 0; k < 40; ++k) checkDerivatives(*terrain_, Vec3(ux(rng), uy(rng), uz(rng)), 1e-7, "random interior");
  // On and next to cell boundaries (the central difference straddles them), and on nodes.
  for (double offset : {0.0, 1e-9, -1e-9, 1e-7, -1e-7, 3e-7}) {
    for (int k = 0; k < 6; ++k) {
      const double xb = spec_.x(ci(rng)) + offset, yb = spec_.y(cj(rng)) + offset;
      checkDerivatives(*terrain_, Vec3(xb, uy(rng), uz(rng)), 1e-7, "x cell boundary");
      checkDerivatives(*terrain_, Vec3(ux(rng), yb, uz(rng)), 1e-7, "y cell boundary");
      checkDerivatives(*terrain_, Vec3(xb, yb, uz(rng)), 1e-7, "node");
    }
  }
}

TEST_F(HeightfieldTest, ContinuousAcrossCellBoundaries) {
  // Value and slope continuity (C¹), and second derivatives too (the spline is C²): the two
  // one-sided evaluations δ either side of every interior grid line agree up to O(δ).
  const double d = 1e-9;
  double jump[3] = {0, 0, 0};  // max jumps of h, first derivatives, second derivatives
  auto compare = [&](const HeightSample& a, const HeightSample& b) {
    jump[0] = std::max(jump[0], std::abs(a.h - b.h));
    jump[1] = std::max({jump[1], std::abs(a.hx - b.hx), std::abs(a.hy - b.hy)});
    jump[2] = std::max({jump[2], std::abs(a.hxx - b.hxx), std::abs(a.hxy - b.hxy), std::abs(a.hyy - b.hyy)});
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(spec_.x0, spec_.xEnd()), uy(spec_.y0, spec_.yEnd());
  for (int i = 1; i < spec_.nx - 1; ++i)
    for (int k = 0; k < 5; ++k) {
      const double y = uy(rng);
      compare(field_->sample(spec_.x(i) - d, y, true), field_->sample(spec_.x(i) + d, y, true));
    }
  for (int j = 1; j < spec_.ny - 1; ++j)
    for (int k = 0; k < 5; ++k) {
      const double x = ux(rng);
      compare(field_->sample(x, spec_.y(j) - d, true), field_->sample(x, spec_.y(j) + d, true));
    }
  EXPECT_LT(jump[0], 1e-9);
  EXPECT_LT(jump[1], 1e-8);
  EXPECT_LT(jump[2], 1e-6);
  // The spline is not trivially smooth: the third derivative does jump across cell boundaries
  // (checked on the h_xx slope either side of an x grid line), so the test above is not vacuous.
  const double h = 1e-4, y = 0.3;
  const double x = spec_.x(spec_.nx / 2);
  const double left = (field_->sample(x - h, y, true).hxx - field_->sample(x - 2 * h, y, true).hxx) / h;
  const double right = (field_->sample(x + 2 * h, y, true).hxx - field_->sample(x + h, y, true).hxx) / h;
  EXPECT_GT(std::abs(left - right), 1e-6);
}

TEST_F(HeightfieldTest, ApproximatesTheSmoothFunction) {
  // Cubic spline: error O(dx⁴); for this surface and spacing well below 1e-5 m.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(spec_.x0, spec_.xEnd()), uy(spec_.y0, spec_.yEnd());
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double x = ux(rng), y = uy(rng);
    worst = std::max(worst, std::abs(field_->sample(x, y, false).h - smoothH(x, y)));
  }
  EXPECT_LT(worst, 1e-5);
}

TEST_F(HeightfieldTest, ClampedOutsideTheGrid) {
  const double ym = 0.37, xm = -0.21;
  const HeightSample east_border = field_->sample(spec_.xEnd(), ym, true);
  for (double beyond : {1e-9, 0.05, 3.0, 1e6}) {
    const HeightSample east = field_->sample(spec_.xEnd() + beyond, ym, true);
    EXPECT_DOUBLE_EQ(east.h, east_border.h);
    EXPECT_DOUBLE_EQ(east.hy, east_border.hy);
    EXPECT_DOUBLE_EQ(east.hyy, east_border.hyy);
    EXPECT_EQ(east.hx, 0.0);
    EXPECT_EQ(east.hxx, 0.0);
    EXPECT_EQ(east.hxy, 0.0);
    const HeightSample south = field_->sample(xm, spec_.y0 - beyond, true);
    const HeightSample south_border = field_->sample(xm, spec_.y0, true);
    EXPECT_DOUBLE_EQ(south.h, south_border.h);
    EXPECT_DOUBLE_EQ(south.hx, south_border.hx);
    EXPECT_EQ(south.hy, 0.0);
    // Beyond a corner: the corner height, a horizontal plane.
    TerrainQuery q;
    terrain_->query(Vec3(spec_.x0 - beyond, spec_.yEnd() + beyond, 0.0), q, true);
    EXPECT_NEAR(q.distance, -smoothH(spec_.x0, spec_.yEnd()), 1e-14);
    EXPECT_EQ(q.normal, Vec3::UnitZ());
    EXPECT_EQ(q.normal_jacobian, Mat3::Zero());
  }
  // Derivatives outside (away from the border kink) still match finite differences.
  checkDerivatives(*terrain_, Vec3(spec_.xEnd() + 0.5, ym, 0.1), 1e-7, "outside east");
  checkDerivatives(*terrain_, Vec3(xm, spec_.y0 - 0.5, 0.1), 1e-7, "outside south");
  checkDerivatives(*terrain_, Vec3(spec_.x0 - 1, spec_.y0 - 1, 0.1), 1e-7, "outside corner");
}

TEST_F(HeightfieldTest, NanCoordinatesGiveNan) {
  TerrainQuery q;
  terrain_->query(Vec3(std::nan(""), 0.0, 0.0), q, true);
  EXPECT_TRUE(std::isnan(q.distance));
  EXPECT_TRUE(q.normal.hasNaN());
}

TEST(Terrain, HeightfieldReproducesBicubicPolynomials) {
  TempDir dir;
  const Cubic c;
  const GridSpec spec{-1.0, -0.6, 0.25, 0.2, 9, 7};
  dir.write("cubic.csv", gridCsv(spec, [&](double x, double y) { return c.h(x, y); }));
  const auto terrain = makeTerrain(spec.config("cubic.csv"), {"test", dir.dir()});
  const auto& field = dynamic_cast<const HeightfieldTerrain&>(*terrain);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(spec.x0, spec.xEnd()), uy(spec.y0, spec.yEnd());
  for (int k = 0; k < 500; ++k) {
    const double x = ux(rng), y = uy(rng);  // all cells, including the border cells
    const HeightSample s = field.sample(x, y, true);
    EXPECT_NEAR(s.h, c.h(x, y), 1e-13);
    EXPECT_NEAR(s.hx, c.hx(x, y), 1e-12);
    EXPECT_NEAR(s.hy, c.hy(x, y), 1e-12);
    EXPECT_NEAR(s.hxx, c.hxx(x, y), 1e-10);
    EXPECT_NEAR(s.hxy, c.hxy(x, y), 1e-10);
    EXPECT_NEAR(s.hyy, c.hyy(x, y), 1e-10);
  }
}

TEST(Terrain, SmallHeightfieldsReproduceLowDegreePolynomials) {
  // 3×3 nodes: the spline along each axis is the parabola through the three nodes; 2x2: bilinear.
  std::mt19937 rng(9);
  {
    const auto quad = [](double x, double y) { return 0.1 + 0.2 * x - 0.3 * y + 0.4 * x * x - 0.5 * x * y + 0.6 * y * y + 0.7 * x * x * y * y; };
    HeightGrid g;
    g.x0 = 0.5, g.y0 = -1.0, g.dx = 0.4, g.dy = 0.3, g.nx = 3, g.ny = 3;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) g.z.push_back(quad(g.x0 + i * g.dx, g.y0 + j * g.dy));
    const HeightfieldTerrain field(g);
    std::uniform_real_distribution<double> ux(0.5, 1.3), uy(-1.0, -0.4);
    for (int k = 0; k < 100; ++k) {
      const double x = ux(rng), y = uy(rng);
      EXPECT_NEAR(field.sample(x, y, false).h, quad(x, y), 1e-13);
    }
    checkDerivatives(field, Vec3(0.7, -0.8, 0.0), 1e-7, "3x3 grid");
  }
  {
    const auto bilinear = [](double x, double y) { return 0.1 + 0.2 * x - 0.3 * y + 0.4 * x * y; };
    HeightGrid g;
    g.x0 = 0.0, g.y0 = 0.0, g.dx = 2.0, g.dy = 1.0, g.nx = 2, g.ny = 2;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) g.z.push_back(bilinear(i * g.dx, j * g.dy));
    const HeightfieldTerrain field(g);
    std::uniform_real_distribution<double> ux(0.0, 2.0), uy(0.0, 1.0);
    for (int k = 0; k < 100; ++k) {
      const double x = ux(rng), y = uy(rng);
      EXPECT_NEAR(field.sample(x, y, false).h, bilinear(x, y), 1e-14);
    }
    checkDerivatives(field, Vec3(0.3, 0.6, 0.0), 1e-7, "2x2 grid");
  }
}

TEST(Terrain, HeightfieldCsvFormatDetails) {
  // Comments, blank lines, CRLF line ends, blanks around values, '+' signs, exponents; "offset".
  TempDir dir;
  dir.write("fmt.csv", "# comment\r\n  # indented comment\r\n\r\n 1.5 , +2\r\n3e-1,\t-4\r\n");
  const auto terrain = makeTerrain(
      json{{"type", "heightfield"}, {"file", "fmt.csv"}, {"spacing", 0.5}, {"offset", 0.25}}, {"test", dir.dir()});
  const HeightGrid& g = dynamic_cast<const HeightfieldTerrain&>(*terrain).grid();
  ASSERT_EQ(g.nx, 2);
  ASSERT_EQ(g.ny, 2);
  EXPECT_EQ(g.dx, 0.5);
  EXPECT_EQ(g.dy, 0.5);
  EXPECT_EQ(g.x0, 0.0);
  EXPECT_EQ(g.y0, 0.0);
  EXPECT_DOUBLE_EQ(g.z[0], 1.75);
  EXPECT_DOUBLE_EQ(g.z[1], 2.25);
  EXPECT_DOUBLE_EQ(g.z[2], 0.55);
  EXPECT_DOUBLE_EQ(g.z[3], -3.75);
}

TEST(Terrain, ExampleHeightfieldLoads) {
  // models/terrain/gentle_bumps.csv, with the configuration given in its header.
  const std::string path = sourcePath("models/terrain/gentle_bumps.csv");
  const auto terrain = makeTerrain(
      json{{"type", "heightfield"}, {"file", "gentle_bumps.csv"}, {"origin", {-2.4, -2.4}}, {"spacing", {0.2, 0.2}}},
      {"example", sourcePath("models/terrain")});
  const auto& field = dynamic_cast<const HeightfieldTerrain&>(*terrain);
  EXPECT_EQ(field.grid().nx, 25);
  EXPECT_EQ(field.grid().ny, 25);
  // The formula of the header, at a few points (0.1 mm rounding + interpolation error).
  const double hills[4][4] = {{0.6, 0.4, 0.03, 0.35}, {-0.8, -0.5, 0.04, 0.4}, {0.2, -1.0, -0.02, 0.3}, {-0.5, 0.9, 0.025, 0.3}};
  for (const Vec3& p : {Vec3(0.6, 0.4, 0), Vec3(-0.8, -0.5, 0), Vec3(0.0, 0.0, 0), Vec3(2.4, 2.4, 0), Vec3(5, -5, 0)}) {
    double h = 0.0;
    for (const auto& k : hills)
      h += k[2] * std::exp(-((p.x() - k[0]) * (p.x() - k[0]) + (p.y() - k[1]) * (p.y() - k[1])) / (2 * k[3] * k[3]));
    EXPECT_NEAR(field.sample(p.x(), p.y(), false).h, h, 1e-3) << p.transpose();
  }
  std::mt19937 rng(2);
  for (int k = 0; k < 10; ++k) checkDerivatives(field, Vec3(randomVector(rng, 3, 2.0)), 1e-7, "gentle_bumps");
}

// ------------------------------------------------------------------------------------------------
// Procedural.

TEST(Terrain, ProceduralSlopesAndHills) {
  const json config = {{"type", "procedural"},
                       {"slope", {0.2, -0.1}},
                       {"offset", 0.05},
                       {"hills",
                        {{{"centre", {0.5, 0.3}}, {"height", 0.2}, {"width", 0.4}},
                         {{"centre", {-0.7, 0.1}}, {"height", -0.1}, {"width", 0.25}}}}};
  const auto terrain = makeTerrain(config, {"test", ""});
  auto h = [](double x, double y) {
    return 0.05 + std::tan(0.2) * x + std::tan(-0.1) * y +
           0.2 * std::exp(-((x - 0.5) * (x - 0.5) + (y - 0.3) * (y - 0.3)) / (2 * 0.16)) -
           0.1 * std::exp(-((x + 0.7) * (x + 0.7) + (y - 0.1) * (y - 0.1)) / (2 * 0.0625));
  };
  std::mt19937 rng(4);
  for (int k = 0; k < 40; ++k) {
    const Vec3 p(randomVector(rng, 3, 1.5));
    TerrainQuery q;
    terrain->query(p, q, false);
    EXPECT_NEAR(q.distance, p.z() - h(p.x(), p.y()), 1e-14);
    checkDerivatives(*terrain, p, 1e-7, "procedural");
  }
  EXPECT_MESSAGE_HAS(terrain->describe(), "2 Gaussian hills");
}

TEST(Terrain, ProceduralSlopeMatchesTiltedPlane) {
  const double a = 0.3, b = -0.2;
  const auto slope = makeTerrain(json{{"type", "procedural"}, {"slope", {a, b}}}, {"test", ""});
  const PlaneTerrain plane(Vec3(-std::tan(a), -std::tan(b), 1.0));
  std::mt19937 rng(6);
  for (int k = 0; k < 10; ++k) {
    const Vec3 p(randomVector(rng, 3, 3.0));
    TerrainQuery qs, qp;
    slope->query(p, qs, true);
    plane.query(p, qp, true);
    EXPECT_LT((qs.normal - qp.normal).norm(), 1e-15);
    EXPECT_EQ(qs.normal_jacobian, Mat3::Zero());
    // Vertical vs Euclidean distance: φ_vertical = φ_plane · ‖∇φ‖.
    EXPECT_NEAR(qs.distance, qp.distance * qs.gradient.norm(), 1e-13);
    checkDerivatives(*slope, p, 1e-8, "slope");
  }
  // A single number is the slope along x.
  const auto along_x = makeTerrain(json{{"type", "procedural"}, {"slope", 0.1}}, {"test", ""});
  TerrainQuery q;
  along_x->query(Vec3(1.0, 5.0, 0.0), q, false);
  EXPECT_NEAR(q.distance, -std::tan(0.1), 1e-15);
}

// ------------------------------------------------------------------------------------------------
// No allocation in query().

TEST(Terrain, QueryDoesNotAllocate) {
  TempDir dir;
  const GridSpec spec{-1.0, -1.0, 0.1, 0.1, 21, 21};
  dir.write("h.csv", gridCsv(spec, smoothH));
  std::vector<std::unique_ptr<Terrain>> terrains;
  terrains.push_back(makeTerrain(json{{"type", "plane"}, {"normal", {0.1, 0.2, 1.0}}}, {"test", ""}));
  terrains.push_back(makeTerrain(spec.config("h.csv"), {"test", dir.dir()}));
  terrains.push_back(makeTerrain(
      json{{"type", "procedural"}, {"slope", {0.1, 0.0}}, {"hills", {{{"centre", {0, 0}}, {"height", 0.1}, {"width", 0.3}}}}},
      {"test", ""}));
  std::mt19937 rng(8);
  std::vector<Vec3> points;
  for (int k = 0; k < 200; ++k) points.emplace_back(randomVector(rng, 3, 1.5));
  TerrainQuery q;
  double sink = 0.0;
  for (const auto& t : terrains) t->query(points[0], q, true);  // warm up
  const AllocationCount count = countAllocations([&] {
    for (const auto& t : terrains)
      for (const Vec3& p : points) {
        t->query(p, q, true);
        sink += q.distance + q.normal_jacobian(0, 0);
        t->query(p, q, false);
        sink += q.distance;
      }
  });
  EXPECT_EQ(count.news, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

// ------------------------------------------------------------------------------------------------
// Bad input.

class TerrainBadInput : public ::testing::Test {
 protected:
  // The message of the InputError from a heightfield file with `text`.
  std::string csvError(const std::string& text) {
    dir_.write("bad.csv", text);
    return inputErrorMessage([&] {
      makeTerrain(json{{"type", "heightfield"}, {"file", "bad.csv"}, {"spacing", 0.1}}, {"scene.json: terrain", dir_.dir()});
    });
  }
  std::string configError(const json& config) {
    return inputErrorMessage([&] { makeTerrain(config, {"scene.json: terrain", dir_.dir()}); });
  }
  TempDir dir_;
};

TEST_F(TerrainBadInput, EmptyCellIsAHole) {
  const std::string m = csvError("1,2,3\n4,,6\n7,8,9\n");
  EXPECT_MESSAGE_HAS(m, "scene.json: terrain.file");
  EXPECT_MESSAGE_HAS(m, "bad.csv");
  EXPECT_MESSAGE_HAS(m, "line 2, column 2");
  EXPECT_MESSAGE_HAS(m, "holes");
}

TEST_F(TerrainBadInput, TrailingCommaIsAnEmptyCell) {
  const std::string m = csvError("1,2,3\n4,5,6,\n");
  EXPECT_MESSAGE_HAS(m, "line 2, column 4");
  EXPECT_MESSAGE_HAS(m, "empty cell");
}

TEST_F(TerrainBadInput, NanIsAHole) {
  for (const std::string nan : {"nan", "NaN", "-nan"}) {
    const std::string m = csvError("# heights\n1,2\n" + nan + ",4\n");
    EXPECT_MESSAGE_HAS(m, "bad.csv");
    EXPECT_MESSAGE_HAS(m, "line 3, column 1");
    EXPECT_MESSAGE_HAS(m, "holes");
  }
}

TEST_F(TerrainBadInput, InfinityIsRejected) {
  const std::string m = csvError("1,2\n3,inf\n");
  EXPECT_MESSAGE_HAS(m, "line 2, column 2");
  EXPECT_MESSAGE_HAS(m, "finite");
}

TEST_F(TerrainBadInput, NonNumericCell) {
  const std::string m = csvError("# header\n1,2,3\n# comment\n4,x5,6\n");
  EXPECT_MESSAGE_HAS(m, "bad.csv");
  EXPECT_MESSAGE_HAS(m, "line 4, column 2");
  EXPECT_MESSAGE_HAS(m, "'x5' is not a number");
  EXPECT_MESSAGE_HAS(csvError("1,2\n3,4m\n"), "'4m' is not a number");
  EXPECT_MESSAGE_HAS(csvError("1 2 3\n4 5 6\n"), "line 1, column 1");
}

TEST_F(TerrainBadInput, RaggedRows) {
  const std::string m = csvError("1,2,3\n4,5,6\n7,8\n");
  EXPECT_MESSAGE_HAS(m, "bad.csv");
  EXPECT_MESSAGE_HAS(m, "line 3");
  EXPECT_MESSAGE_HAS(m, "2 values");
  EXPECT_MESSAGE_HAS(m, "first row (line 1) has 3");
}

TEST_F(TerrainBadInput, TooFewValues) {
  for (const std::string text : {"", "# only a comment\n", "1,2,3\n", "1\n2\n3\n"}) {
    const std::string m = csvError(text);
    EXPECT_MESSAGE_HAS(m, "bad.csv");
    EXPECT_MESSAGE_HAS(m, "at least 2x2");
  }
}

TEST_F(TerrainBadInput, MissingFile) {
  const std::string m = configError(json{{"type", "heightfield"}, {"file", "no_such.csv"}, {"spacing", 0.1}});
  EXPECT_MESSAGE_HAS(m, "scene.json: terrain.file");
  EXPECT_MESSAGE_HAS(m, dir_.file("no_such.csv"));
  EXPECT_MESSAGE_HAS(m, "no such file");
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"file", "."}, {"spacing", 0.1}}), "it is a folder, not a file");
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"spacing", 0.1}}), "terrain.file: missing");
}

TEST_F(TerrainBadInput, BadSpacingAndOrigin) {
  dir_.write("ok.csv", "1,2\n3,4\n");
  for (const json& spacing : {json{0.1, 0.0}, json{-0.1, 0.1}, json(0.0), json(-1.0)}) {
    const std::string m = configError(json{{"type", "heightfield"}, {"file", "ok.csv"}, {"spacing", spacing}});
    EXPECT_MESSAGE_HAS(m, "scene.json: terrain.spacing");
    EXPECT_MESSAGE_HAS(m, "positive");
  }
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"file", "ok.csv"}}), "terrain.spacing: missing");
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"file", "ok.csv"}, {"spacing", {0.1, 0.1, 0.1}}}),
                     "terrain.spacing");
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"file", "ok.csv"}, {"spacing", "0.1"}}),
                     "terrain.spacing");
  EXPECT_MESSAGE_HAS(configError(json{{"type", "heightfield"}, {"file", "ok.csv"}, {"spacing", 0.1}, {"origin", 1.0}}),
                     "terrain.origin");
}

TEST_F(TerrainBadInput, UnknownType) {
  const std::string m = configError(json{{"type", "heigthfield"}});
  EXPECT_MESSAGE_HAS(m, "scene.json: terrain.type");
  EXPECT_MESSAGE_HAS(m, "'heigthfield'");
  EXPECT_MESSAGE_HAS(m, "did you mean 'heightfield'");
  EXPECT_MESSAGE_HAS(m, "plane, heightfield, procedural");
  EXPECT_MESSAGE_HAS(configError(json{{"type", 3}}), "terrain.type");
  EXPECT_MESSAGE_HAS(configError(json::array({1, 2})), "scene.json: terrain");
}

TEST_F(TerrainBadInput, UnknownKey) {
  dir_.write("ok.csv", "1,2\n3,4\n");
  std::string m = configError(json{{"type", "heightfield"}, {"file", "ok.csv"}, {"spacing", 0.1}, {"orign", {0, 0}}});
  EXPECT_MESSAGE_HAS(m, "scene.json: terrain.orign");
  EXPECT_MESSAGE_HAS(m, "did you mean 'origin'");
  m = configError(json{{"type", "plane"}, {"normals", {0, 0, 1}}});
  EXPECT_MESSAGE_HAS(m, "terrain.normals");
  m = configError(json{{"type", "procedural"}, {"hill", json::array()}});
  EXPECT_MESSAGE_HAS(m, "terrain.hill");
  EXPECT_MESSAGE_HAS(m, "did you mean 'hills'");
  m = configError(json{{"type", "procedural"}, {"hills", {{{"centre", {0, 0}}, {"height", 0.1}, {"widht", 0.2}}}}});
  EXPECT_MESSAGE_HAS(m, "scene.json: terrain.hills[0].widht");
  // No type, and a key of another type: the message says the type is missing.
  m = configError(json{{"file", "ok.csv"}});
  EXPECT_MESSAGE_HAS(m, "terrain.type: missing");
  EXPECT_MESSAGE_HAS(m, "'file'");
}

TEST_F(TerrainBadInput, BadProceduralValues) {
  std::string m = configError(json{{"type", "procedural"}, {"slope", {30, 0}}});
  EXPECT_MESSAGE_HAS(m, "terrain.slope");
  EXPECT_MESSAGE_HAS(m, "degrees?");
  m = configError(json{{"type", "procedural"}, {"hills", {{{"centre", {0, 0}}, {"height", 0.1}, {"width", 0.0}}}}});
  EXPECT_MESSAGE_HAS(m, "terrain.hills[0].width");
  m = configError(json{{"type", "procedural"}, {"hills", {{{"centre", {0, 0}}, {"width", 0.3}}}}});
  EXPECT_MESSAGE_HAS(m, "terrain.hills[0].height: missing");
  m = configError(json{{"type", "procedural"}, {"hills", {{{"centre", {0, 0, 0}}, {"height", 0.1}, {"width", 0.3}}}}});
  EXPECT_MESSAGE_HAS(m, "terrain.hills[0].centre");
  m = configError(json{{"type", "procedural"}, {"hills", {{"centre", {0, 0}}}}});  // an object, not a list
  EXPECT_MESSAGE_HAS(m, "terrain.hills");
  m = configError(json{{"type", "plane"}, {"normal", {0, 0, 0}}});
  EXPECT_MESSAGE_HAS(m, "terrain.normal");
}

}  // namespace
}  // namespace nmdp::test
