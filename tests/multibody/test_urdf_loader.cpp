// The URDF loader's bodies: fixed-joint merging (inertia included), massless links, the total mass
// of the project's quadruped and the real robots of ../shared, and the coordinates of each base
// type. Joints: test_urdf_joints.cpp. Fixture URDFs are generated and written to a unique
// temporary directory.
#include <cmath>

#include "common/input_error.hpp"
#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/rnea.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"
#include "urdf_text.hpp"

namespace nmdp::test {
namespace {

// ------------------------------------------------------------------------------------------------
// Fixed joints are merged into the parent body, inertia included.

struct MergeFixture {
  // torso --hinge(revolute)--> A --weld(fixed)--> B --tip(revolute)--> C
  InertialSpec torso, a, b, c;
  Vec3 hinge_xyz{0.2, -0.1, 0.05}, hinge_rpy{0.1, 0.2, -0.3}, hinge_axis{0.3, 0.5, 0.8};
  Vec3 weld_xyz{0.1, -0.2, 0.3}, weld_rpy{0.4, -0.5, 0.6};
  Vec3 tip_xyz{0.05, 0.15, -0.25}, tip_axis{1, 0, 0};  // tip origin rpy = 0 (relative to B)

  MergeFixture() {
    torso.mass = 4.0;
    torso.xyz = Vec3(0.01, 0.02, -0.03);
    torso.I = inertiaMatrix(0.2, 0.3, 0.25, 0.01, -0.02, 0.015);
    a.mass = 1.3;
    a.xyz = Vec3(0.05, 0.02, -0.1);
    a.rpy = Vec3(0.1, 0.2, 0.3);
    a.I = inertiaMatrix(0.02, 0.03, 0.025, 0.002, -0.001, 0.0015);
    b.mass = 0.7;
    b.xyz = Vec3(-0.03, 0.07, 0.2);
    b.rpy = Vec3(-0.3, 0.25, 0.9);
    b.I = inertiaMatrix(0.011, 0.007, 0.009, -0.001, 0.0005, 0.0008);
    c.mass = 0.4;
    c.xyz = Vec3(0.0, 0.0, -0.12);
    c.I = inertiaMatrix(0.004, 0.005, 0.002, 0.0, 0.0003, 0.0);
  }

  std::string twoLinkUrdf() const {
    return robotXml("merge_two", linkXml("torso", &torso) + jointXml("hinge", "revolute", "torso", "A", hinge_xyz, hinge_rpy, hinge_axis) +
                                     linkXml("A", &a) + jointXml("weld", "fixed", "A", "B", weld_xyz, weld_rpy) +
                                     linkXml("B", &b) + jointXml("tip", "revolute", "B", "C", tip_xyz, Vec3::Zero(), tip_axis) +
                                     linkXml("C", &c));
  }

  // Combined inertia of A and B in A's frame, by the parallel-axis theorem.
  void combined(double& m, Vec3& com, Mat3& Icom) const {
    const Mat3 Rw = rpyMatrix(weld_rpy);
    const double ma = a.mass, mb = b.mass;
    const Vec3 ca = a.xyz;
    const Vec3 cb = weld_xyz + Rw * b.xyz;
    const Mat3 Ia = rpyMatrix(a.rpy) * a.I * rpyMatrix(a.rpy).transpose();
    const Mat3 Rb = Rw * rpyMatrix(b.rpy);
    const Mat3 Ib = Rb * b.I * Rb.transpose();
    m = ma + mb;
    com = (ma * ca + mb * cb) / m;
    auto shift = [](double mass, const Vec3& d) { return mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()); };
    Icom = Ia + shift(ma, ca - com) + Ib + shift(mb, cb - com);
  }

  std::string singleLinkUrdf() const {
    InertialSpec ab;
    combined(ab.mass, ab.xyz, ab.I);
    const Vec3 tip_in_a = weld_xyz + rpyMatrix(weld_rpy) * tip_xyz;
    return robotXml("merge_one", linkXml("torso", &torso) + jointXml("hinge", "revolute", "torso", "A", hinge_xyz, hinge_rpy, hinge_axis) +
                                     linkXml("A", &ab) + jointXml("tip", "revolute", "A", "C", tip_in_a, weld_rpy, tip_axis) +
                                     linkXml("C", &c));
  }
};

TEST(UrdfLoaderFixedJoints, MergedIntoParentWithCombinedInertia) {
  TempDir dir;
  MergeFixture fx;
  const std::string two = dir.write("two.urdf", fx.twoLinkUrdf());
  const std::string one = dir.write("one.urdf", fx.singleLinkUrdf());
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    SCOPED_TRACE(baseTypeName(base));
    UrdfOptions opt;
    opt.base = base;
    const Model m2 = loadUrdf(two, opt);
    const Model m1 = loadUrdf(one, opt);
    ASSERT_EQ(m2.nq, m1.nq);
    ASSERT_EQ(m2.dof_names, m1.dof_names);
    const int nbase = base == BaseType::Floating ? 6 : base == BaseType::Planar ? 3 : 0;
    EXPECT_EQ(m2.nq, nbase + 2);
    ASSERT_EQ(m2.links.size(), 4u);
    EXPECT_EQ(m2.links[m2.linkIndex("B")].body, m2.links[m2.linkIndex("A")].body);
    EXPECT_FALSE(m2.links[m2.linkIndex("B")].parent_joint_movable);
    EXPECT_EQ(m2.links[m2.linkIndex("B")].parent_joint, "weld");

    // Total mass, and the merged body's mass, com and rotational inertia against the independent sum.
    double m;
    Vec3 com;
    Mat3 Icom;
    fx.combined(m, com, Icom);
    const double total = fx.torso.mass + fx.a.mass + fx.b.mass + fx.c.mass;
    EXPECT_NEAR(m2.total_mass, total, 1e-12);
    EXPECT_NEAR(m1.total_mass, total, 1e-12);
    const Body& hinge = m2.bodies[m2.dofIndex("hinge")];
    EXPECT_NEAR(hinge.mass, m, 1e-12);
    EXPECT_LT((hinge.com - com).norm(), 1e-12);
    EXPECT_LT((hinge.inertia_com - Icom).cwiseAbs().maxCoeff(), 1e-12);
    const Body& hinge1 = m1.bodies[m1.dofIndex("hinge")];
    EXPECT_LT((hinge1.inertia_com - Icom).cwiseAbs().maxCoeff(), 1e-12);

    Data d2(m2), d1(m1);
    std::mt19937 rng(3);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = randomVector(rng, m2.nq, 1.5);
      const Eigen::VectorXd qd = randomVector(rng, m2.nq, 2.0);
      const Eigen::VectorXd qdd = randomVector(rng, m2.nq, 3.0);
      crba(m2, d2, q);
      crba(m1, d1, q);
      EXPECT_LT(relativeError(d2.H, d1.H), 1e-12) << "trial " << trial;
      for (int i = 0; i < m2.nq; ++i)
        EXPECT_LT(relativeError(d2.Iw[i], d1.Iw[i]), 1e-12) << "spatial inertia of body " << i;
      rnea(m2, d2, q, qd, qdd);
      rnea(m1, d1, q, qd, qdd);
      EXPECT_LT(relativeError(d2.tau, d1.tau), 1e-12) << "trial " << trial;

      // Frames: C is the same; B = A · weld.
      Mat3 Rc2, Rc1, Ra, Rb;
      Vec3 pc2, pc1, pa, pb;
      linkPose(m2, d2, m2.linkIndex("C"), Rc2, pc2);
      linkPose(m1, d1, m1.linkIndex("C"), Rc1, pc1);
      EXPECT_LT((Rc2 - Rc1).norm() + (pc2 - pc1).norm(), 1e-12);
      linkPose(m2, d2, m2.linkIndex("A"), Ra, pa);
      linkPose(m2, d2, m2.linkIndex("B"), Rb, pb);
      EXPECT_LT((Rb - Ra * rpyMatrix(fx.weld_rpy)).norm(), 1e-12);
      EXPECT_LT((pb - (pa + Ra * fx.weld_xyz)).norm(), 1e-12);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Links without <inertial> are massless.

TEST(UrdfLoaderMassless, LinksWithoutInertialLoadAsMassless) {
  TempDir dir;
  InertialSpec chassis, arm;
  chassis.mass = 5.0;
  chassis.I = inertiaMatrix(0.1, 0.2, 0.15, 0, 0, 0);
  arm.mass = 0.8;
  arm.xyz = Vec3(0, 0, -0.1);
  arm.I = inertiaMatrix(0.01, 0.01, 0.002, 0, 0, 0);
  const std::string path = dir.write(
      "massless.urdf",
      robotXml("massless", linkXml("root_frame", nullptr) +
                               jointXml("root_to_chassis", "fixed", "root_frame", "chassis", Vec3(0, 0, 0.1), Vec3(0, 0, 0.2)) +
                               linkXml("chassis", &chassis) +
                               jointXml("shoulder", "revolute", "chassis", "arm", Vec3(0.2, 0, 0), Vec3::Zero(), Vec3::UnitY()) +
                               linkXml("arm", &arm) + jointXml("arm_to_sensor", "fixed", "arm", "sensor", Vec3(0, 0, -0.2), Vec3::Zero()) +
                               linkXml("sensor", nullptr)));
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    SCOPED_TRACE(baseTypeName(base));
    UrdfOptions opt;
    opt.base = base;
    const Model m = loadUrdf(path, opt);
    EXPECT_EQ(m.links[m.root_link].name, "root_frame");
    EXPECT_EQ(m.links[m.linkIndex("root_frame")].mass, 0.0);
    EXPECT_EQ(m.links[m.linkIndex("sensor")].mass, 0.0);
    EXPECT_NEAR(m.total_mass, 5.8, 1e-12);
    Data d(m);
    std::mt19937 rng(1);
    crba(m, d, randomVector(rng, m.nq, 1.0));
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(d.H).info(), Eigen::Success) << "H must be positive definite";
  }
}

TEST(UrdfLoaderMassless, A1RootLinkWithoutInertial) {
  NMDP_REQUIRE_SHARED("robots/a1/urdf/a1.urdf");
  const std::string path = sharedPath("robots/a1/urdf/a1.urdf");
  const Model m = loadUrdf(path);
  EXPECT_EQ(m.links[m.root_link].name, "base");
  EXPECT_EQ(m.links[m.root_link].mass, 0.0);
  EXPECT_EQ(m.nq, 6 + 12);
  EXPECT_GT(m.bodies[m.root_body].mass, 0.0) << "the trunk welded to `base` must carry the base's mass";
  Data d(m);
  std::mt19937 rng(5);
  crba(m, d, randomVector(rng, m.nq, 1.0));
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(d.H).info(), Eigen::Success);
}

// ------------------------------------------------------------------------------------------------
// Total masses of the project's quadruped and the real robots.

void expectTotalMass(const std::string& path, double documented, double documented_tol) {
  SCOPED_TRACE(path);
  const double scanned = scanUrdfMass(path);
  EXPECT_NEAR(scanned, documented, documented_tol) << "the URDF's masses do not add up to the documented total";
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    UrdfOptions opt;
    opt.base = base;
    const Model m = loadUrdf(path, opt);
    EXPECT_NEAR(m.total_mass, scanned, 1e-9 * scanned) << baseTypeName(base);
    double links = 0, bodies = 0;
    for (const Link& l : m.links) links += l.mass;
    for (const Body& b : m.bodies) bodies += b.mass;
    bodies += m.world_second_moment(3, 3);
    EXPECT_NEAR(links, scanned, 1e-9 * scanned);
    EXPECT_NEAR(bodies, scanned, 1e-9 * scanned) << "merged body masses must add up to the total";
  }
}

TEST(UrdfLoaderTotalMass, Quadruped) { expectTotalMass(quadrupedUrdf(), 17.41, 1e-9); }
TEST(UrdfLoaderTotalMass, A1) {
  NMDP_REQUIRE_SHARED("robots/a1/urdf/a1.urdf");
  expectTotalMass(sharedPath("robots/a1/urdf/a1.urdf"), 13.7, 0.05);
}
TEST(UrdfLoaderTotalMass, Solo12) {
  NMDP_REQUIRE_SHARED("robots/solo12/urdf/solo12.urdf");
  expectTotalMass(sharedPath("robots/solo12/urdf/solo12.urdf"), 2.5, 0.01);
}
TEST(UrdfLoaderTotalMass, RoboSimian) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  expectTotalMass(sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf"), 99.9, 0.05);
}

// ------------------------------------------------------------------------------------------------
// Base types and degree-of-freedom names.

TEST(UrdfLoaderBase, QuadrupedCoordinatesPerBaseType) {
  std::vector<std::string> actuated;
  for (const char* leg : {"FL", "FR", "RL", "RR"})
    for (const char* j : {"hip", "thigh", "knee"}) actuated.push_back(std::string(leg) + "_" + j + "_joint");
  struct Expect {
    BaseType base;
    std::vector<std::string> base_names;
  };
  for (const Expect& e : {Expect{BaseType::Floating, {"base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw"}},
                          Expect{BaseType::Planar, {"base_x", "base_z", "base_pitch"}}, Expect{BaseType::Fixed, {}}}) {
    SCOPED_TRACE(baseTypeName(e.base));
    UrdfOptions opt;
    opt.base = e.base;
    const Model m = loadUrdf(quadrupedUrdf(), opt);
    std::vector<std::string> names = e.base_names;
    names.insert(names.end(), actuated.begin(), actuated.end());
    EXPECT_EQ(m.nq, static_cast<int>(e.base_names.size()) + 12);
    EXPECT_EQ(m.nv(), m.nq);
    EXPECT_EQ(m.dof_names, names);
    EXPECT_EQ(m.base, e.base);
    ASSERT_EQ(static_cast<int>(m.bodies.size()), m.nq);
    for (int i = 0; i < m.nq; ++i) {
      EXPECT_EQ(m.bodies[i].joint_name, names[i]);
      EXPECT_EQ(m.bodies[i].is_base, i < static_cast<int>(e.base_names.size()));
      EXPECT_LT(m.bodies[i].parent, i) << "parents precede children";
      EXPECT_EQ(m.dofIndex(names[i]), i);
    }
    if (e.base == BaseType::Fixed) {
      EXPECT_EQ(m.root_body, -1);
      EXPECT_EQ(m.links[m.root_link].body, -1);
    } else {
      EXPECT_EQ(m.root_body, static_cast<int>(e.base_names.size()) - 1);
      EXPECT_EQ(m.links[m.root_link].body, m.root_body);
    }
    if (e.base == BaseType::Planar) {
      EXPECT_EQ(m.bodies[0].kind, JointKind::Prismatic);
      EXPECT_EQ(m.bodies[0].axis, Vec3::UnitX());
      EXPECT_EQ(m.bodies[1].axis, Vec3::UnitZ());
      EXPECT_EQ(m.bodies[2].kind, JointKind::Revolute);
      EXPECT_EQ(m.bodies[2].axis, Vec3::UnitY());
    }
  }
  EXPECT_EQ(parseBaseType("floating"), BaseType::Floating);
  EXPECT_EQ(parseBaseType("planar"), BaseType::Planar);
  EXPECT_EQ(parseBaseType("fixed"), BaseType::Fixed);
  EXPECT_THROW(parseBaseType("free"), InputError);
}

TEST(UrdfLoaderBase, RealRobotsActuatedCounts) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  struct Case {
    std::string rel;
    int actuated;
  };
  for (const Case& c : {Case{"robots/a1/urdf/a1.urdf", 12}, Case{"robots/solo12/urdf/solo12.urdf", 12},
                        Case{"robots/robosimian/robosimian_caesar_new_all_active.urdf", 32},
                        Case{"robots/robosimian/robosimian_caesar_new.urdf", 28}}) {
    SCOPED_TRACE(c.rel);
    for (auto [base, nbase] : {std::pair{BaseType::Floating, 6}, std::pair{BaseType::Planar, 3}, std::pair{BaseType::Fixed, 0}}) {
      UrdfOptions opt;
      opt.base = base;
      EXPECT_EQ(loadUrdf(sharedPath(c.rel), opt).nq, nbase + c.actuated) << baseTypeName(base);
    }
  }
}

}  // namespace
}  // namespace nmdp::test
