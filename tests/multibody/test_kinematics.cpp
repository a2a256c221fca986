// Jacobians and their θ-derivatives against central finite differences; the floating-base chart.
#include "multibody/base_chart.hpp"
#include "multibody/kinematics.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {

// World angular displacement taking Rm to Rp, divided by the step.
Vec3 angularRate(const Mat3& Rp, const Mat3& Rm, double two_eps) {
  const Eigen::AngleAxisd aa(Rp * Rm.transpose());
  return aa.axis() * aa.angle() / two_eps;
}

class Kinematics : public RobotTest {};

TEST_P(Kinematics, SpatialJacobianMatchesFiniteDifferences) {
  Data data(model), fd(model);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = randomVector(rng, model.nq, 1.0);
  const Vec3 local = randomVector(rng, 3, 0.1);
  const double eps = 1e-6;
  forwardKinematics(model, data, q);
  for (int link = 0; link < static_cast<int>(model.links.size()); ++link) {
    const int body = model.links[link].body;
    Mat6X J(6, model.nq);
    spatialJacobian(model, data, body, linkPoint(model, data, link, local), J);
    Mat6X Jfd(6, model.nq);
    for (int j = 0; j < model.nq; ++j) {
      Eigen::VectorXd qp = q, qm = q;
      qp[j] += eps;
      qm[j] -= eps;
      Mat3 Rp, Rm;
      Vec3 pp, pm;
      forwardKinematics(model, fd, qp);
      linkPose(model, fd, link, Rp, pp);
      const Vec3 xp = linkPoint(model, fd, link, local);
      forwardKinematics(model, fd, qm);
      linkPose(model, fd, link, Rm, pm);
      const Vec3 xm = linkPoint(model, fd, link, local);
      Jfd.col(j).head<3>() = angularRate(Rp, Rm, 2 * eps);
      Jfd.col(j).tail<3>() = (xp - xm) / (2 * eps);
    }
    EXPECT_LT((J - Jfd).cwiseAbs().maxCoeff(), 1e-8) << model.links[link].name;
    Mat3X Jp(3, model.nq);
    pointJacobian(model, data, body, linkPoint(model, data, link, local), Jp);
    EXPECT_LT((Jp - J.bottomRows(3)).cwiseAbs().maxCoeff(), 1e-14);  // same columns (FMA may round differently)
  }
}

// forwardKinematics turns coordinate axes (±x, ±y, ±z) by mixing two columns; the poses, motion
// axes and world inertias must be those of the plain recursion R_i = R_λ(i) X_i Rot(a_i, q_i).
// One revolute body gets a general axis, the other path.
TEST_P(Kinematics, PosesMatchThePlainRecursion) {
  Model m = model;
  for (Body& b : m.bodies)
    if (!b.is_base && b.kind == JointKind::Revolute) {
      b.axis = Vec3(1, -2, 3).normalized();
      break;
    }
  Data data(m);
  std::mt19937 rng(5);
  data.base_chart = Eigen::AngleAxisd(0.3, Vec3(0.6, 0.0, 0.8)).toRotationMatrix();
  const Eigen::VectorXd q = randomVector(rng, m.nq, 1.0);
  forwardKinematics(m, data, q);
  std::vector<Mat3> R(m.nq);
  std::vector<Vec3> p(m.nq);
  int coordinate_axes = 0;
  for (int i = 0; i < m.nq; ++i) {
    const Body& b = m.bodies[i];
    const Mat3 place = b.uses_base_chart ? data.base_chart : b.placement_rotation;
    const Mat3 Rj = b.parent < 0 ? place : Mat3(R[b.parent] * place);
    const Vec3 pj = b.parent < 0 ? b.placement_translation : Vec3(p[b.parent] + R[b.parent] * b.placement_translation);
    const Vec3 axis = Rj * b.axis;
    Vec6 S;
    if (b.kind == JointKind::Revolute) {
      R[i] = Rj * Eigen::AngleAxisd(q[i], b.axis).toRotationMatrix();
      p[i] = pj;
      S.head<3>() = axis;  // (block assignments: GCC 12 -Warray-bounds flags Eigen's comma initializer here)
      S.tail<3>() = pj.cross(axis);
      coordinate_axes += b.axis.cwiseAbs().maxCoeff() == 1.0;
    } else {
      R[i] = Rj;
      p[i] = pj + axis * q[i];
      S.head<3>().setZero();
      S.tail<3>() = axis;
    }
    EXPECT_LT((data.R[i] - R[i]).norm(), 1e-14) << "body " << i;
    EXPECT_LT((data.p[i] - p[i]).norm(), 1e-14) << "body " << i;
    EXPECT_LT((data.S[i] - S).norm(), 1e-14) << "body " << i;
    if (b.mass == 0.0) continue;
    const Vec3 c = p[i] + R[i] * b.com;
    const Mat3 cx = skew(c);
    Mat6 I;
    I.topLeftCorner<3, 3>() = R[i] * b.inertia_com * R[i].transpose() + b.mass * cx * cx.transpose();
    I.topRightCorner<3, 3>() = b.mass * cx;
    I.bottomLeftCorner<3, 3>() = b.mass * cx.transpose();
    I.bottomRightCorner<3, 3>() = b.mass * Mat3::Identity();
    EXPECT_LT((data.Iw[i] - I).norm(), 1e-12 * I.norm()) << "body " << i;
  }
  EXPECT_GT(coordinate_axes, 0) << "the fast path was not exercised";
}

TEST_P(Kinematics, JacobianDerivativesMatchFiniteDifferences) {
  Data data(model), fd(model);
  std::mt19937 rng(4);
  const Eigen::VectorXd q = randomVector(rng, model.nq, 1.0);
  const Vec3 local = randomVector(rng, 3, 0.1);
  Vec6 wrench = randomVector(rng, 6, 10.0);
  const double eps = 1e-6;
  forwardKinematics(model, data, q);
  // The deepest link of every branch and one link half way.
  for (int link = 0; link < static_cast<int>(model.links.size()); link += 3) {
    const int body = model.links[link].body;
    auto jacobianAt = [&](const Eigen::VectorXd& x) {
      forwardKinematics(model, fd, x);
      Mat6X J(6, model.nq);
      spatialJacobian(model, fd, body, linkPoint(model, fd, link, local), J);
      return J;
    };
    Eigen::MatrixXd JTf(model.nq, model.nq);
    JTf.setZero();
    addJacobianTransposeWrenchDerivative(model, data, body, linkPoint(model, data, link, local), wrench, JTf);
    Eigen::MatrixXd JTf_fd(model.nq, model.nq);
    for (int l = 0; l < model.nq; ++l) {
      Eigen::VectorXd qp = q, qm = q;
      qp[l] += eps;
      qm[l] -= eps;
      const Mat6X dJ_fd = (jacobianAt(qp) - jacobianAt(qm)) / (2 * eps);
      Mat6X dJ(6, model.nq);
      spatialJacobianDerivative(model, data, body, linkPoint(model, data, link, local), l, dJ);
      EXPECT_LT((dJ - dJ_fd).cwiseAbs().maxCoeff(), 1e-7) << model.links[link].name << " l=" << l;
      JTf_fd.col(l) = dJ_fd.transpose() * wrench;
    }
    EXPECT_LT((JTf - JTf_fd).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, JTf_fd.cwiseAbs().maxCoeff()))
        << model.links[link].name;
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, Kinematics, ::testing::ValuesIn(derivativeRobots()),
                         [](const auto& info) { return info.param.name; });

std::vector<Vec6> bodyVelocities(const Model& model, const Data& data, const Eigen::VectorXd& qd) {
  std::vector<Vec6> v(model.nq);
  for (int i = 0; i < model.nq; ++i) {
    v[i] = data.S[i] * qd[i];
    if (model.bodies[i].parent >= 0) v[i] += v[model.bodies[i].parent];
  }
  return v;
}

TEST(FloatingChart, RebasePreservesPoseAndVelocity) {
  const Model model = loadUrdf(quadrupedUrdf());
  Data data(model);
  std::mt19937 rng(9);
  Eigen::VectorXd q = randomVector(rng, model.nq, 1.2);
  Eigen::VectorXd qd = randomVector(rng, model.nq, 2.0);
  forwardKinematics(model, data, q);
  const std::vector<Mat3> R0 = data.R;
  const std::vector<Vec3> p0 = data.p;
  const std::vector<Vec6> v0 = bodyVelocities(model, data, qd);
  rebaseFloatingChart(model, data, q, qd);
  EXPECT_EQ(q.segment<3>(3), Vec3::Zero());
  forwardKinematics(model, data, q);
  const std::vector<Vec6> v1 = bodyVelocities(model, data, qd);
  // The intermediate virtual frames (after roll, after pitch) belong to the chart, not the robot.
  for (int i = model.root_body; i < model.nq; ++i) {
    EXPECT_LT((data.R[i] - R0[i]).norm(), 1e-12);
    EXPECT_LT((data.p[i] - p0[i]).norm(), 1e-12);
    EXPECT_LT((v1[i] - v0[i]).norm(), 1e-12) << model.bodies[i].name;
  }
}

TEST(FloatingChart, BasePoseReportsRollPitchYaw) {
  const Model model = loadUrdf(quadrupedUrdf());
  Data data(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq);
  q.head<3>() << 0.1, -0.2, 0.45;
  data.base_chart = (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.2, Vec3::UnitY()) *
                     Eigen::AngleAxisd(0.1, Vec3::UnitX())).toRotationMatrix();
  forwardKinematics(model, data, q);
  Vec3 position, rpy;
  basePose(model, data, position, rpy);
  EXPECT_LT((position - Vec3(0.1, -0.2, 0.45)).norm(), 1e-15);
  EXPECT_LT((rpy - Vec3(0.1, -0.2, 0.3)).norm(), 1e-14);
}

}  // namespace
}  // namespace nmdp::test
