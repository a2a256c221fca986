#include "contact_models/contact_model.hpp"

#include <stdexcept>
#include <string>

#include "common/named_enum.hpp"

namespace nmdp {

namespace {
constexpr EnumName<DerivativeSupport> kDerivativeSupports[] = {
    {DerivativeSupport::Analytic, "analytic"}, {DerivativeSupport::Autograd, "autograd"}, {DerivativeSupport::None, "none"}};
}  // namespace

const char* derivativeSupportName(DerivativeSupport d) { return nameOf(kDerivativeSupports, d); }

std::vector<ContactFeatureInfo> ContactModel::featureInfo() const {
  return {{"depth", "m", "signed distance of the foot sphere's surface to the terrain, negative below it"}};
}

void ContactModel::requireFeatureShape(const char* model, std::size_t frames, const Eigen::Ref<Eigen::MatrixXd>& out,
                                       Eigen::Index columns) {
  if (out.rows() == static_cast<Eigen::Index>(frames) && out.cols() == columns) return;
  // Only a programming error gets here, so the message may allocate.
  throw std::logic_error(std::string(model) + " features: the output is " + std::to_string(out.rows()) + " x " +
                         std::to_string(out.cols()) + ", expected " + std::to_string(frames) + " contacts x " +
                         std::to_string(columns) + " features");
}

void ContactModel::features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            Eigen::Ref<Eigen::MatrixXd> out) const {
  requireFeatureShape("contact model", frames.size(), out, 1);
  TerrainQuery query;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    terrain.query(frames[i].position, query, false);
    out(static_cast<Eigen::Index>(i), 0) = query.distance - frames[i].radius;
  }
}

}  // namespace nmdp
