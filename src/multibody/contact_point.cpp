#include "multibody/contact_point.hpp"

#include <algorithm>

#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"

namespace nmdp {

Vec3 legAxisOf(const Model& model, int link, const Vec3& offset, double radius) {
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(model.nq));
  Mat3 R;
  Vec3 p;
  linkPose(model, data, link, R, p);
  const Vec3 centre = p + R * offset;
  for (int a = link; a >= 0; a = model.links[a].parent_link) {
    Mat3 Ra;
    Vec3 pa;
    linkPose(model, data, a, Ra, pa);
    const Vec3 up = pa - centre;
    if (up.norm() > std::max(radius, 1e-9)) return (R.transpose() * up).normalized();
  }
  return Vec3::UnitZ();
}

}  // namespace nmdp
