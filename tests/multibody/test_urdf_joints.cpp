// The URDF loader's joints: prismatic and continuous kinds, locked joints (equivalent to the
// unlocked model at the locked value), armature, and massless movable joints (rejected with advice
// unless given armature or locked). Fixture URDFs are generated and written to a unique temporary
// directory.
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
// Continuous and prismatic joints.

struct SliderFixture {
  Vec3 slide_xyz{0.1, 0.2, 0.3}, slide_rpy{0.3, -0.2, 0.5}, slide_axis{1, 1, 0};
  Vec3 spin_xyz{0.0, 0.4, 0.05}, spin_rpy{0.2, 0.1, -0.3}, spin_axis{0, 0.6, 0.8};
  std::string urdf() const {
    InertialSpec base, carriage, wheel;
    base.mass = 2;
    base.I = inertiaMatrix(0.1, 0.1, 0.1, 0, 0, 0);
    carriage.mass = 1;
    carriage.xyz = Vec3(0.01, 0, 0.02);
    carriage.I = inertiaMatrix(0.01, 0.02, 0.03, 0, 0, 0);
    wheel.mass = 0.5;
    wheel.xyz = Vec3(0.03, 0.01, 0);
    wheel.I = inertiaMatrix(0.002, 0.003, 0.004, 0.0001, 0, 0);
    // The continuous joint deliberately has no <limit>.
    return robotXml("slider", linkXml("base", &base) +
                                  jointXml("slide", "prismatic", "base", "carriage", slide_xyz, slide_rpy, slide_axis) +
                                  linkXml("carriage", &carriage) +
                                  jointXml("spin", "continuous", "carriage", "wheel", spin_xyz, spin_rpy, spin_axis) +
                                  linkXml("wheel", &wheel));
  }
};

TEST(UrdfLoaderJointKinds, PrismaticTranslatesAndContinuousRotates) {
  TempDir dir;
  SliderFixture fx;
  const std::string path = dir.write("slider.urdf", fx.urdf());
  UrdfOptions opt;
  opt.base = BaseType::Fixed;
  const Model m = loadUrdf(path, opt);
  ASSERT_EQ(m.nq, 2);
  EXPECT_EQ(m.dof_names, (std::vector<std::string>{"slide", "spin"}));
  EXPECT_EQ(m.bodies[0].kind, JointKind::Prismatic);
  EXPECT_EQ(m.bodies[1].kind, JointKind::Revolute);
  EXPECT_NEAR(m.bodies[0].axis.norm(), 1.0, 1e-15) << "axes are normalized";

  const Mat3 R0 = rpyMatrix(fx.slide_rpy), R1 = rpyMatrix(fx.spin_rpy);
  const Vec3 u0 = fx.slide_axis.normalized(), u1 = fx.spin_axis.normalized();
  const int carriage = m.linkIndex("carriage"), wheel = m.linkIndex("wheel"), base = m.linkIndex("base");
  Data d(m);
  for (double s : {-0.7, 0.0, 0.25, 1.3}) {
    for (double th : {-2.0, 0.0, 0.9, 7.0, 40.0}) {  // a continuous joint has no limits
      forwardKinematics(m, d, Eigen::Vector2d(s, th));
      Mat3 R;
      Vec3 p;
      linkPose(m, d, base, R, p);
      EXPECT_LT((R - Mat3::Identity()).norm() + p.norm(), 1e-15);
      linkPose(m, d, carriage, R, p);
      EXPECT_LT((R - R0).norm(), 1e-12) << "a prismatic joint does not rotate";
      EXPECT_LT((p - (fx.slide_xyz + R0 * u0 * s)).norm(), 1e-12) << "translation along the axis (joint frame)";
      const Mat3 Rw = R0 * R1 * Eigen::AngleAxisd(th, u1).toRotationMatrix();
      const Vec3 pw = fx.slide_xyz + R0 * u0 * s + R0 * fx.spin_xyz;
      linkPose(m, d, wheel, R, p);
      EXPECT_LT((R - Rw).norm(), 1e-12) << "s=" << s << " th=" << th;
      EXPECT_LT((p - pw).norm(), 1e-12);
      // A point on the wheel stays at the same distance from the spin axis.
      const Vec3 world_axis = R0 * R1 * u1;
      const Vec3 point = linkPoint(m, d, wheel, Vec3(0.1, -0.05, 0.02));
      const Vec3 rel = point - pw;
      const Vec3 local = Vec3(0.1, -0.05, 0.02);
      EXPECT_NEAR((rel - rel.dot(world_axis) * world_axis).norm(), (local - local.dot(u1) * u1).norm(), 1e-12);
    }
  }
  // Full turns of the continuous joint give the same pose.
  Mat3 Ra, Rb;
  Vec3 pa, pb;
  forwardKinematics(m, d, Eigen::Vector2d(0.3, 0.4));
  linkPose(m, d, wheel, Ra, pa);
  forwardKinematics(m, d, Eigen::Vector2d(0.3, 0.4 + 4 * M_PI));
  linkPose(m, d, wheel, Rb, pb);
  EXPECT_LT((Ra - Rb).norm() + (pa - pb).norm(), 1e-12);
}

// ------------------------------------------------------------------------------------------------
// Locked joints: same kinematics and dynamics as the unlocked model with the joint held at its value.

void expectLockedEquivalent(const std::string& path, const UrdfOptions& unlocked_options,
                            const std::map<std::string, double>& locks, int expected_nq) {
  UrdfOptions locked_options = unlocked_options;
  for (const auto& [name, value] : locks) locked_options.locked_joints[name] = value;
  const Model U = loadUrdf(path, unlocked_options);
  const Model L = loadUrdf(path, locked_options);
  ASSERT_EQ(L.nq, expected_nq);
  ASSERT_EQ(L.nq, U.nq - static_cast<int>(locks.size()));
  ASSERT_EQ(L.links.size(), U.links.size());
  EXPECT_NEAR(L.total_mass, U.total_mass, 1e-12 * U.total_mass);
  for (const auto& [name, value] : locks) {
    EXPECT_EQ(L.dofIndex(name), -1) << name << " must not be a coordinate once locked";
    EXPECT_GE(U.dofIndex(name), 0) << name;
  }
  std::vector<int> map;  // locked-model coordinate -> unlocked-model coordinate
  for (const std::string& name : L.dof_names) {
    map.push_back(U.dofIndex(name));
    ASSERT_GE(map.back(), 0) << name;
  }
  const int n = L.nq;
  Data dl(L), du(U);
  std::mt19937 rng(17);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd ql = randomVector(rng, n, 1.2);
    const Eigen::VectorXd qdl = randomVector(rng, n, 2.0);
    const Eigen::VectorXd qddl = randomVector(rng, n, 3.0);
    Eigen::VectorXd qu = Eigen::VectorXd::Zero(U.nq), qdu = qu, qddu = qu;
    for (const auto& [name, value] : locks) qu[U.dofIndex(name)] = value;
    for (int i = 0; i < n; ++i) {
      qu[map[i]] = ql[i];
      qdu[map[i]] = qdl[i];
      qddu[map[i]] = qddl[i];
    }
    crba(L, dl, ql);
    crba(U, du, qu);
    for (size_t k = 0; k < U.links.size(); ++k) {
      const int kl = L.linkIndex(U.links[k].name);
      ASSERT_GE(kl, 0) << U.links[k].name;
      Mat3 Rl, Ru;
      Vec3 pl, pu;
      linkPose(L, dl, kl, Rl, pl);
      linkPose(U, du, static_cast<int>(k), Ru, pu);
      EXPECT_LT((Rl - Ru).norm(), 1e-12) << U.links[k].name << " trial " << trial;
      EXPECT_LT((pl - pu).norm(), 1e-12) << U.links[k].name << " trial " << trial;
    }
    Eigen::MatrixXd Hsub(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) Hsub(i, j) = du.H(map[i], map[j]);
    EXPECT_LT(relativeError(dl.H, Hsub), 1e-12) << "trial " << trial;
    // Inverse dynamics with the locked joint at rest.
    rnea(L, dl, ql, qdl, qddl);
    rnea(U, du, qu, qdu, qddu);
    Eigen::VectorXd tausub(n);
    for (int i = 0; i < n; ++i) tausub[i] = du.tau[map[i]];
    EXPECT_LT(relativeError(dl.tau, tausub), 1e-12) << "trial " << trial;
  }
}

TEST(UrdfLoaderLockedJoints, QuadrupedKneeLocked) {
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    SCOPED_TRACE(baseTypeName(base));
    UrdfOptions opt;
    opt.base = base;
    const int nbase = base == BaseType::Floating ? 6 : base == BaseType::Planar ? 3 : 0;
    expectLockedEquivalent(quadrupedUrdf(), opt, {{"FL_knee_joint", -1.2}}, nbase + 11);
  }
}

TEST(UrdfLoaderLockedJoints, LockedLinkKeepsItsName) {
  UrdfOptions opt;
  opt.locked_joints["FL_knee_joint"] = -1.2;
  const Model m = loadUrdf(quadrupedUrdf(), opt);
  const Link& calf = m.links[m.linkIndex("FL_calf")];
  EXPECT_EQ(calf.parent_joint, "FL_knee_joint");
  EXPECT_FALSE(calf.parent_joint_movable);
  EXPECT_EQ(calf.body, m.links[m.linkIndex("FL_thigh")].body) << "a locked link is merged into its parent's body";
}

TEST(UrdfLoaderLockedJoints, PrismaticAndContinuousLocked) {
  TempDir dir;
  const std::string path = dir.write("slider.urdf", SliderFixture().urdf());
  UrdfOptions opt;
  opt.base = BaseType::Floating;
  expectLockedEquivalent(path, opt, {{"slide", 0.35}}, 7);
  expectLockedEquivalent(path, opt, {{"spin", -2.5}}, 7);
}

TEST(UrdfLoaderLockedJoints, RoboSimianPaperConfiguration) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  const std::string path = sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  std::map<std::string, double> locks;
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {0, 1, 3, 5, 7}) locks["limb" + std::to_string(limb) + "_joint" + std::to_string(j)] = 0.0;
  UrdfOptions planar;
  planar.base = BaseType::Planar;
  expectLockedEquivalent(path, planar, locks, 3 + 12);

  UrdfOptions paper = planar;
  paper.locked_joints = locks;
  const Model m = loadUrdf(path, paper);
  std::vector<std::string> expected = {"base_x", "base_z", "base_pitch"};
  for (int limb = 1; limb <= 4; ++limb)
    for (int j : {2, 4, 6}) expected.push_back("limb" + std::to_string(limb) + "_joint" + std::to_string(j));
  EXPECT_EQ(m.dof_names, expected);
  EXPECT_NEAR(m.total_mass, scanUrdfMass(path), 1e-9);
}

// ------------------------------------------------------------------------------------------------
// Armature.

TEST(UrdfLoaderArmature, AddedToTheDiagonalAndToInverseDynamics) {
  const double a = 0.05, def = 0.02;
  UrdfOptions plain, one, all;
  one.armature["FL_knee_joint"] = a;
  all.armature["FL_knee_joint"] = a;
  all.default_armature = def;
  const Model m0 = loadUrdf(quadrupedUrdf(), plain);
  const Model m1 = loadUrdf(quadrupedUrdf(), one);
  const Model m2 = loadUrdf(quadrupedUrdf(), all);
  const int k = m0.dofIndex("FL_knee_joint");
  ASSERT_GE(k, 0);
  Eigen::VectorXd add_one = Eigen::VectorXd::Zero(m0.nq), add_all = Eigen::VectorXd::Zero(m0.nq);
  add_one[k] = a;
  for (int i = 0; i < m0.nq; ++i) add_all[i] = m0.bodies[i].is_base ? 0.0 : (i == k ? a : def);
  for (int i = 0; i < m0.nq; ++i) {
    EXPECT_EQ(m1.bodies[i].armature, add_one[i]) << m0.dof_names[i];
    EXPECT_EQ(m2.bodies[i].armature, add_all[i]) << m0.dof_names[i];
  }
  Data d0(m0), d1(m1), d2(m2);
  std::mt19937 rng(23);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd q = randomVector(rng, m0.nq, 1.0);
    const Eigen::VectorXd qd = randomVector(rng, m0.nq, 2.0);
    const Eigen::VectorXd qdd = randomVector(rng, m0.nq, 4.0);
    crba(m0, d0, q);
    crba(m1, d1, q);
    crba(m2, d2, q);
    const Eigen::MatrixXd H0 = d0.H;
    EXPECT_LT((d1.H - H0 - Eigen::MatrixXd(add_one.asDiagonal())).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT((d2.H - H0 - Eigen::MatrixXd(add_all.asDiagonal())).cwiseAbs().maxCoeff(), 1e-13);
    rnea(m0, d0, q, qd, qdd);
    rnea(m1, d1, q, qd, qdd);
    rnea(m2, d2, q, qd, qdd);
    const double scale = d0.tau.cwiseAbs().maxCoeff();
    EXPECT_LT((d1.tau - d0.tau - add_one.cwiseProduct(qdd)).cwiseAbs().maxCoeff(), 1e-13 * scale);
    EXPECT_LT((d2.tau - d0.tau - add_all.cwiseProduct(qdd)).cwiseAbs().maxCoeff(), 1e-13 * scale);
  }
}

TEST(UrdfLoaderArmature, RejectsUnknownJointAndNegativeValue) {
  UrdfOptions bad_name, negative, on_fixed;
  bad_name.armature["no_such_joint"] = 0.1;
  negative.armature["FL_knee_joint"] = -0.1;
  on_fixed.armature["imu_joint"] = 0.1;
  EXPECT_NE(inputErrorMessage([&] { loadUrdf(quadrupedUrdf(), bad_name); }).find("no_such_joint"), std::string::npos);
  EXPECT_NE(inputErrorMessage([&] { loadUrdf(quadrupedUrdf(), negative); }).find("FL_knee_joint"), std::string::npos);
  EXPECT_NE(inputErrorMessage([&] { loadUrdf(quadrupedUrdf(), on_fixed); }).find("imu_joint"), std::string::npos);
}

// ------------------------------------------------------------------------------------------------
// A movable joint that moves no mass or inertia.

std::string masslessJointUrdf() {
  InertialSpec base, arm, zero;
  base.mass = 3;
  base.I = inertiaMatrix(0.05, 0.06, 0.07, 0, 0, 0);
  arm.mass = 1;
  arm.xyz = Vec3(0, 0, -0.1);
  arm.I = inertiaMatrix(0.01, 0.01, 0.001, 0, 0, 0);
  zero.mass = 0;  // explicit zero mass and zero inertia
  return robotXml("dead", linkXml("base", &base) +
                              jointXml("live_joint", "revolute", "base", "arm", Vec3(0.1, 0, 0), Vec3::Zero(), Vec3::UnitY()) +
                              linkXml("arm", &arm) +
                              jointXml("dead_joint", "revolute", "base", "ghost", Vec3(-0.1, 0, 0), Vec3::Zero(), Vec3::UnitX()) +
                              linkXml("ghost", nullptr) + jointXml("ghost_weld", "fixed", "ghost", "ghost_tip", Vec3(0, 0, -0.3), Vec3::Zero()) +
                              linkXml("ghost_tip", &zero));
}

TEST(UrdfLoaderMasslessJoint, RejectedWithAdvice) {
  TempDir dir;
  const std::string path = dir.write("dead.urdf", masslessJointUrdf());
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    SCOPED_TRACE(baseTypeName(base));
    UrdfOptions opt;
    opt.base = base;
    const std::string msg = inputErrorMessage([&] { loadUrdf(path, opt); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("dead_joint"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lock"), std::string::npos) << msg;
    EXPECT_NE(msg.find("armature"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("live_joint"), std::string::npos) << "only the offending joint is named: " << msg;
  }
}

TEST(UrdfLoaderMasslessJoint, LoadsWithArmatureOrLocked) {
  TempDir dir;
  const std::string path = dir.write("dead.urdf", masslessJointUrdf());
  UrdfOptions with_armature;
  with_armature.armature["dead_joint"] = 0.01;
  const Model m = loadUrdf(path, with_armature);
  EXPECT_EQ(m.nq, 6 + 2);
  const int k = m.dofIndex("dead_joint");
  ASSERT_GE(k, 0);
  Data d(m);
  std::mt19937 rng(29);
  crba(m, d, randomVector(rng, m.nq, 1.0));
  EXPECT_NEAR(d.H(k, k), 0.01, 1e-15);
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(d.H).info(), Eigen::Success);

  UrdfOptions with_default;
  with_default.default_armature = 0.002;
  EXPECT_NO_THROW(loadUrdf(path, with_default));

  UrdfOptions locked;
  locked.locked_joints["dead_joint"] = 0.0;
  const Model ml = loadUrdf(path, locked);
  EXPECT_EQ(ml.nq, 6 + 1);
  EXPECT_EQ(ml.dofIndex("dead_joint"), -1);
}

TEST(UrdfLoaderMasslessJoint, RoboSimianMasslessLink0WithMassiveSubtreeLoads) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  const std::string path = sharedPath("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  for (BaseType base : {BaseType::Floating, BaseType::Planar, BaseType::Fixed}) {
    SCOPED_TRACE(baseTypeName(base));
    UrdfOptions opt;
    opt.base = base;
    Model m;
    ASSERT_NO_THROW(m = loadUrdf(path, opt));
    const int nbase = base == BaseType::Floating ? 6 : base == BaseType::Planar ? 3 : 0;
    EXPECT_EQ(m.nq, nbase + 32);
    for (int limb = 1; limb <= 4; ++limb) {
      const std::string link0 = "limb" + std::to_string(limb) + "_link0";
      const int l = m.linkIndex(link0);
      ASSERT_GE(l, 0) << link0;
      EXPECT_EQ(m.links[l].mass, 0.0) << link0;
      const int b = m.links[l].body;
      ASSERT_GE(b, 0);
      EXPECT_EQ(m.bodies[b].mass, 0.0) << link0 << " is massless itself";
      double subtree = 0;
      for (int i = b; i < m.subtree_end[b]; ++i) subtree += m.bodies[i].mass;
      EXPECT_GT(subtree, 0.0) << link0 << " carries a massive subtree";
    }
    Data d(m);
    std::mt19937 rng(31);
    crba(m, d, randomVector(rng, m.nq, 1.0));
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(d.H).info(), Eigen::Success);
  }
}

}  // namespace
}  // namespace nmdp::test
