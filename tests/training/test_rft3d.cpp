// Three-dimensional resistive force theory (training/rft3d_*): the element law reduces to the planar
// law in the x–z plane bit for bit; closed forms (a horizontal plate pushed down); symmetries (a
// symmetric foot dragged sideways is resisted straight back with no yaw moment; turning foot and
// motion about the vertical turns the wrench; the mirror y → −y); the sagittal restriction equals
// the planar RFT of the same plate; convergence in the element count; and bad arguments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "training/rft.hpp"
#include "training/rft3d_foot.hpp"
#include "training/rft3d_law.hpp"
#include "training/rft3d_samples.hpp"

namespace nmdp::test {
namespace {
using Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;
constexpr double kPerCm3 = 1e6;  // ζ is given in N/cm³

RftMedium sand() {
  RftMedium m;
  m.zeta = 2.71;
  return m;
}

Rft3dFoot sphere(double radius = 0.02, int elements = 64) {
  Rft3dFoot f;
  f.shape = Rft3dShape::Sphere;
  f.radius = radius;
  f.elements = elements;
  return f;
}

Rft3dFoot rectangle(Rft3dShape shape, double length, double width, int elements = 32) {
  Rft3dFoot f;
  f.shape = shape;
  f.length = length;
  f.width = width;
  f.elements = elements;
  return f;
}

double scale(const Wrench6& w) { return w.force.norm(); }

TEST(Rft3dLaw, ReducesToThePlanarLawInTheSagittalPlaneBitForBit) {
  const RftMedium m = sand();
  int compared = 0;
  for (double tilt = -kPi; tilt < kPi; tilt += 0.37)
    for (double psi = -kPi; psi < kPi; psi += 0.29) {
      const double nx = std::sin(tilt), nz = -std::cos(tilt), vx = std::sin(psi), vz = -std::cos(psi);
      double sx = 0, sz = 0;
      rftStressPerDepth(m, nx, nz, vx, vz, &sx, &sz);
      const Vector3d s = rft3dStressPerDepth(m, Vector3d(nx, 0, nz), Vector3d(vx, 0, vz));
      EXPECT_EQ(s.x(), sx) << tilt << " " << psi;
      EXPECT_EQ(s.z(), sz) << tilt << " " << psi;
      EXPECT_EQ(s.y(), 0.0);
      ++compared;
    }
  // Straight down on a horizontal element, and the vertical motions.
  double sx = 0, sz = 0;
  rftStressPerDepth(m, 0.3, -std::sqrt(1 - 0.09), 0, -1, &sx, &sz);
  const Vector3d s = rft3dStressPerDepth(m, Vector3d(0.3, 0, -std::sqrt(1 - 0.09)), Vector3d(0, 0, -1));
  EXPECT_EQ(s.x(), sx);
  EXPECT_EQ(s.z(), sz);
  EXPECT_GT(compared, 300);
}

TEST(Rft3dLaw, IsInvariantToTheSideOfAThinElementAndZeroWithoutMotion) {
  const RftMedium m = sand();
  const Vector3d n = Vector3d(0.3, -0.5, -0.8).normalized(), v = Vector3d(0.4, 0.7, -0.2).normalized();
  const Vector3d a = rft3dStressPerDepth(m, n, v), b = rft3dStressPerDepth(m, -n, v);
  EXPECT_LT((a - b).norm(), 1e-12 * a.norm()) << a.transpose() << " | " << b.transpose();
  EXPECT_GT(a.norm(), 1e4);
  EXPECT_EQ(rft3dStressPerDepth(m, n, Vector3d::Zero()), Vector3d::Zero());
  // The stress lies in the vertical plane of the motion: nothing along ẑ × v̂.
  EXPECT_NEAR(a.dot(Vector3d::UnitZ().cross(v).normalized()), 0.0, 1e-9 * a.norm());
}

TEST(Rft3d, HorizontalPlatePushedDownMatchesPlanarRftClosedForm) {
  // F_z = ζ α_z(0, π/2) A d, with α_z(0, π/2) = 1 for the generic coefficients.
  const RftMedium m = sand();
  const double length = 0.04, width = 0.03, d = 0.02;
  const Wrench6 w = rft3dWrench(m, rectangle(Rft3dShape::Plate, length, width, 8), -d, 0.0, 0.0, Vector3d(0, 0, -1));
  const double alpha_z = rftAlpha(m.coefficients, 0.0, kPi / 2).z;
  const double expected = m.zeta * kPerCm3 * alpha_z * length * width * d;
  EXPECT_NEAR(alpha_z, 1.0, 1e-12);
  EXPECT_NEAR(w.force.z(), expected, 1e-12 * expected);  // 65.04 N
  EXPECT_NEAR(w.force.x(), 0.0, 1e-12 * expected);
  EXPECT_NEAR(w.force.y(), 0.0, 1e-12 * expected);
  EXPECT_LT(w.torque.norm(), 1e-12 * expected);  // the plate is centred on P
  // Rate independence: only the direction of the velocity matters.
  const Wrench6 fast =
      rft3dWrench(m, rectangle(Rft3dShape::Plate, length, width, 8), -d, 0.0, 0.0, Vector3d(0, 0, -7.5));
  EXPECT_NEAR(fast.force.z(), w.force.z(), 1e-12 * expected);
}

TEST(Rft3d, SymmetricFeetDraggedSidewaysAreResistedStraightBackWithoutYaw) {
  const RftMedium m = sand();
  const Rft3dFoot feet[] = {sphere(0.02, 64), rectangle(Rft3dShape::Plate, 0.04, 0.04, 32)};
  for (const Rft3dFoot& foot : feet)
    for (double heading : {0.0, 0.5, kPi / 2, 2.0, kPi, -1.1}) {
      const Vector3d drag(std::cos(heading), std::sin(heading), 0.0);
      const Wrench6 w = rft3dWrench(m, foot, -0.02, 0.0, 0.0, drag);
      const Vector3d horizontal(w.force.x(), w.force.y(), 0.0);
      ASSERT_GT(horizontal.norm(), 1.0) << rft3dShapeName(foot.shape);
      // Opposite to the drag: no component across it.
      EXPECT_LT(horizontal.dot(drag), -0.999999 * horizontal.norm()) << rft3dShapeName(foot.shape) << " " << heading;
      EXPECT_NEAR(horizontal.cross(drag).z(), 0.0, 1e-9 * horizontal.norm()) << rft3dShapeName(foot.shape);
      EXPECT_NEAR(w.torque.z(), 0.0, 1e-9 * scale(w) * 0.02) << rft3dShapeName(foot.shape) << " " << heading;
    }
}

TEST(Rft3d, TurningFootAndMotionAboutTheVerticalTurnsTheWrench) {
  const RftMedium m = sand();
  const Rft3dFoot feet[] = {sphere(0.02, 48), rectangle(Rft3dShape::Plate, 0.05, 0.03, 24),
                            rectangle(Rft3dShape::Blade, 0.06, 0.02, 24)};
  const Eigen::Matrix3d frame = rft3dFootFrame(0.5, 0.3);
  const Vector3d v = Vector3d(0.6, -0.3, -0.5).normalized();
  for (const Rft3dFoot& foot : feet)
    for (double yaw : {0.7, kPi / 2, -2.4}) {
      const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
      const Wrench6 w = rft3dWrenchInFrame(m, foot, -0.03, frame, v);
      const Wrench6 turned = rft3dWrenchInFrame(m, foot, -0.03, Rz * frame, Rz * v);
      ASSERT_GT(scale(w), 1.0) << rft3dShapeName(foot.shape);
      EXPECT_LT((turned.force - Rz * w.force).norm(), 1e-9 * scale(w)) << rft3dShapeName(foot.shape) << " " << yaw;
      EXPECT_LT((turned.torque - Rz * w.torque).norm(), 1e-9 * scale(w) * 0.06) << rft3dShapeName(foot.shape);
    }
}

TEST(Rft3d, MirrorYToMinusY) {
  // Under y → −y: γ → −γ, v_y → −v_y, the force (F_x, −F_y, F_z), the torque (−τ_x, τ_y, −τ_z).
  const RftMedium m = sand();
  const Rft3dFoot feet[] = {sphere(0.02, 48), rectangle(Rft3dShape::Plate, 0.05, 0.03, 24),
                            rectangle(Rft3dShape::Blade, 0.06, 0.02, 24)};
  const Vector3d v = Vector3d(0.2, 0.8, -0.4).normalized(), mirrored(v.x(), -v.y(), v.z());
  for (const Rft3dFoot& foot : feet) {
    const Wrench6 w = rft3dWrench(m, foot, -0.025, 0.4, 0.35, v);
    const Wrench6 mw = rft3dWrench(m, foot, -0.025, 0.4, -0.35, mirrored);
    ASSERT_GT(std::abs(w.force.y()), 0.01 * scale(w)) << rft3dShapeName(foot.shape);  // not trivially zero
    const double tol = 1e-10 * scale(w);
    EXPECT_NEAR(mw.force.x(), w.force.x(), tol) << rft3dShapeName(foot.shape);
    EXPECT_NEAR(mw.force.y(), -w.force.y(), tol) << rft3dShapeName(foot.shape);
    EXPECT_NEAR(mw.force.z(), w.force.z(), tol) << rft3dShapeName(foot.shape);
    EXPECT_NEAR(mw.torque.x(), -w.torque.x(), tol) << rft3dShapeName(foot.shape);
    EXPECT_NEAR(mw.torque.y(), w.torque.y(), tol) << rft3dShapeName(foot.shape);
    EXPECT_NEAR(mw.torque.z(), -w.torque.z(), tol) << rft3dShapeName(foot.shape);
  }
}

TEST(Rft3d, SagittalRestrictionOfARectangleEqualsThePlanarRftOfThePlate) {
  // A 3-D plate or blade at γ = 0 moving in the x–z plane is the planar plate of the same width:
  // the stress does not vary across it. Wholly submerged, both integrals are exact (the integrand
  // is linear along the plate): equal to rounding. Crossing the surface, the planar code clips
  // exactly and the 3-D cells do not: equal within the 3-D convergence (0.5 %).
  const RftMedium m = sand();
  for (Rft3dShape shape : {Rft3dShape::Plate, Rft3dShape::Blade}) {
    RftFoot planar;
    planar.shape = shape == Rft3dShape::Plate ? RftShape::Plate : RftShape::Blade;
    planar.length = 0.05;
    planar.width = 0.03;
    planar.elements = 40;
    const Rft3dFoot foot = rectangle(shape, 0.05, 0.03, 40);
    for (double depth : {-0.06, -0.09, -0.01})
      for (double beta : {-0.5, 0.0, 0.7})
        for (double psi : {0.0, 0.8, 1.6, 2.5, -1.2}) {
          const Vector3d v(std::sin(psi), 0.0, -std::cos(psi));
          const PlanarWrench p = rftWrench(m, planar, depth, beta, {v.x(), v.z(), 0.0});
          const Wrench6 w = rft3dWrench(m, foot, depth, beta, 0.0, v);
          const double size = std::hypot(p.fx, p.fz);
          const double tol = (depth < -0.05 ? 1e-9 : 5e-3) * size;
          EXPECT_NEAR(w.force.x(), p.fx, tol) << rft3dShapeName(shape) << " " << depth << " " << beta << " " << psi;
          EXPECT_NEAR(w.force.z(), p.fz, tol) << rft3dShapeName(shape) << " " << depth << " " << beta << " " << psi;
          EXPECT_NEAR(w.torque.y(), p.wy, tol * 0.05) << rft3dShapeName(shape) << " " << depth;
          EXPECT_NEAR(w.force.y(), 0.0, 1e-9 * size);
          EXPECT_NEAR(w.torque.x(), 0.0, 1e-9 * size * 0.05);
          EXPECT_NEAR(w.torque.z(), 0.0, 1e-9 * size * 0.05);
        }
  }
}

TEST(Rft3d, ConvergesInTheElementCount) {
  // The default count (64 per direction) is within 0.5 % of a fine reference (512), for feet
  // crossing the surface, shallow and deep, in every cube direction. The error is measured against
  // the state's largest force and torque over the directions (the scale of its wrench space): a
  // sphere lifted out of shallow sand meets almost nothing, and a relative error of almost nothing
  // says nothing about the samples.
  const RftMedium m = sand();
  struct Case {
    Rft3dFoot coarse, fine;
    double depth, beta, gamma;
  };
  const Case cases[] = {
      {sphere(0.02, 64), sphere(0.02, 512), -0.005, 0.0, 0.0},
      {sphere(0.02, 64), sphere(0.02, 512), -0.02, 0.3, 0.2},
      {sphere(0.02, 64), sphere(0.02, 512), -0.06, 0.0, 0.0},
      {rectangle(Rft3dShape::Plate, 0.05, 0.03, 64), rectangle(Rft3dShape::Plate, 0.05, 0.03, 512), -0.005, 0.6, 0.4},
      {rectangle(Rft3dShape::Blade, 0.06, 0.02, 64), rectangle(Rft3dShape::Blade, 0.06, 0.02, 512), -0.03, 0.5, -0.3},
  };
  double worst = 0;
  for (const Case& c : cases) {
    std::vector<Wrench6> coarse, fine;
    double force_scale = 0, torque_scale = 0;
    for (const Vector3d& v : rft3dCubeDirections()) {
      coarse.push_back(rft3dWrench(m, c.coarse, c.depth, c.beta, c.gamma, v));
      fine.push_back(rft3dWrench(m, c.fine, c.depth, c.beta, c.gamma, v));
      force_scale = std::max(force_scale, fine.back().force.norm());
      torque_scale = std::max(torque_scale, fine.back().torque.norm());
    }
    ASSERT_GT(force_scale, 0.1);
    for (size_t j = 0; j < fine.size(); ++j) {
      const double ef = (coarse[j].force - fine[j].force).norm() / force_scale;
      const double et = (coarse[j].torque - fine[j].torque).norm() / torque_scale;
      worst = std::max({worst, ef, et});
      EXPECT_LT(ef, 0.005) << rft3dShapeName(c.coarse.shape) << " depth " << c.depth << " direction " << j;
      EXPECT_LT(et, 0.005) << rft3dShapeName(c.coarse.shape) << " depth " << c.depth << " direction " << j;
    }
  }
  std::printf("worst error of 64 against 512 elements: %.5f of the state's largest force or torque\n", worst);
}

TEST(Rft3d, ZeroAboveTheSurfaceAndForNoMotion) {
  const RftMedium m = sand();
  EXPECT_EQ(rft3dWrench(m, sphere(), 0.0, 0.0, 0.0, Vector3d(0, 0, -1)).force, Vector3d::Zero());
  EXPECT_EQ(rft3dWrench(m, sphere(), 0.01, 0.0, 0.0, Vector3d(0, 0, -1)).force, Vector3d::Zero());
  EXPECT_EQ(rft3dWrench(m, sphere(), -0.02, 0.0, 0.0, Vector3d::Zero()).force, Vector3d::Zero());
  // A blade leaning sideways dips its lower corner by (w/2) sin γ cos β: 1.9 mm here, so it is
  // clear of the sand with P 5 mm up, and not with P on the surface.
  const Rft3dFoot blade = rectangle(Rft3dShape::Blade, 0.05, 0.02);
  EXPECT_EQ(rft3dWrench(m, blade, 0.005, 0.3, 0.2, Vector3d(1, 0, -1)).force, Vector3d::Zero());
  EXPECT_GT(rft3dWrench(m, blade, 0.0, 0.3, 0.2, Vector3d(1, 0, -1)).force.norm(), 0.0);
}

TEST(Rft3d, BadArgumentsThrow) {
  const RftMedium m = sand();
  const double nan = std::nan("");
  EXPECT_THROW(rft3dWrench(m, sphere(), nan, 0, 0, Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, sphere(), -0.01, nan, 0, Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, sphere(), -0.01, 0, nan, Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, sphere(), -0.01, 0, 0, Vector3d(1, nan, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, sphere(0.0), -0.01, 0, 0, Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, sphere(0.02, 0), -0.01, 0, 0, Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(rft3dWrench(m, rectangle(Rft3dShape::Plate, 0.05, 0.0), -0.01, 0, 0, Vector3d(1, 0, 0)),
               std::invalid_argument);
  EXPECT_THROW(rft3dFibonacciDirections(0), std::invalid_argument);
}

TEST(Rft3d, QuadrupedSphereAtTwoCentimetres) {
  // The project's quadruped foot (sphere r = 0.02 m in ζ = 2.71 N/cm³), 2 cm deep: its drags along
  // +x and +y are the same turned (an axisymmetric foot), and it is held up when pushed down.
  const RftMedium m = sand();
  const Wrench6 x = rft3dWrench(m, sphere(), -0.02, 0.0, 0.0, Vector3d(1, 0, 0));
  const Wrench6 y = rft3dWrench(m, sphere(), -0.02, 0.0, 0.0, Vector3d(0, 1, 0));
  const Wrench6 down = rft3dWrench(m, sphere(), -0.02, 0.0, 0.0, Vector3d(0, 0, -1));
  std::printf("sphere 2 cm +x: F %.4f %.4f %.4f N, tau %.6f %.6f %.6f N m\n", x.force.x(), x.force.y(), x.force.z(),
              x.torque.x(), x.torque.y(), x.torque.z());
  std::printf("sphere 2 cm +y: F %.4f %.4f %.4f N, tau %.6f %.6f %.6f N m\n", y.force.x(), y.force.y(), y.force.z(),
              y.torque.x(), y.torque.y(), y.torque.z());
  std::printf("sphere 2 cm -z: F %.4f %.4f %.4f N, tau %.6f %.6f %.6f N m\n", down.force.x(), down.force.y(),
              down.force.z(), down.torque.x(), down.torque.y(), down.torque.z());
  EXPECT_LT(x.force.x(), -1.0);
  EXPECT_NEAR(y.force.y(), x.force.x(), 1e-3 * std::abs(x.force.x()));
  EXPECT_NEAR(y.force.z(), x.force.z(), 1e-3 * std::abs(x.force.x()));
  EXPECT_GT(down.force.z(), 10.0);
  EXPECT_NEAR(down.force.x(), 0.0, 1e-9 * down.force.z());
  EXPECT_NEAR(down.force.y(), 0.0, 1e-9 * down.force.z());
}

}  // namespace
}  // namespace nmdp::test
