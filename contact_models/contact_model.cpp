#include "contact_models/contact_model.hpp"

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

void ContactModel::features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            Eigen::Ref<Eigen::MatrixXd> out) const {
  TerrainQuery query;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    terrain.query(frames[i].position, query, false);
    out(static_cast<Eigen::Index>(i), 0) = query.distance - frames[i].radius;
  }
}

}  // namespace nmdp
