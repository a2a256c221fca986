#include "contact_models/patched_model.hpp"

#include <limits>
#include <sstream>
#include <stdexcept>

namespace nmdp {

PatchedModel::PatchedModel(std::shared_ptr<const MaterialLayout> layout, std::vector<std::unique_ptr<ContactModel>> models)
    : layout_(std::move(layout)), models_(std::move(models)) {
  if (!layout_) throw std::invalid_argument("PatchedModel: no material layout");
  if (static_cast<int>(models_.size()) != layout_->materialCount())
    throw std::invalid_argument("PatchedModel: " + std::to_string(models_.size()) + " models for " +
                                std::to_string(layout_->materialCount()) + " materials");
  for (const auto& m : models_) {
    if (!m) throw std::invalid_argument("PatchedModel: a null material model");
    offsets_.push_back(vertex_count_);
    vertex_count_ += m->vertexCount();
  }
  parts_.resize(models_.size());

  for (const auto& m : models_) {
    std::vector<Eigen::Index>& columns = feature_column_.emplace_back();
    const std::vector<ContactFeatureInfo> info = m->featureInfo();
    for (const ContactFeatureInfo& column : info) {
      Eigen::Index at = 0;
      while (at < static_cast<Eigen::Index>(feature_info_.size()) && feature_info_[at].name != column.name) ++at;
      if (at == static_cast<Eigen::Index>(feature_info_.size())) feature_info_.push_back(column);
      else if (feature_info_[at].unit != column.unit)
        throw std::invalid_argument("PatchedModel: the materials' feature '" + column.name + "' has units '" +
                                    feature_info_[at].unit + "' and '" + column.unit + "'");
      columns.push_back(at);
    }
    one_row_.emplace_back(1, static_cast<Eigen::Index>(info.size()));
  }
  feature_info_.push_back({"material", "1",
                           "index of the material with the largest weight at the sphere centre, whose features the "
                           "row holds: 0 the ground's default, m >= 1 patch m - 1"});
  feature_info_.push_back({"weight", "1", "that material's weight w_m in [0, 1] at the sphere centre"});
  point_w_.resize(models_.size());
  point_wx_.resize(models_.size());
  point_wy_.resize(models_.size());
  one_frame_.resize(1);
}

void PatchedModel::features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::Index columns = static_cast<Eigen::Index>(feature_info_.size());
  requireFeatureShape("patched", frames.size(), out, columns);
  out.setConstant(std::numeric_limits<double>::quiet_NaN());
  for (std::size_t b = 0; b < frames.size(); ++b) {
    const Eigen::Index row = static_cast<Eigen::Index>(b);
    layout_->weights(frames[b].position.x(), frames[b].position.y(), point_w_.data(), point_wx_.data(),
                     point_wy_.data());
    size_t m = 0;
    for (size_t k = 1; k < models_.size(); ++k)
      if (point_w_[k] > point_w_[m]) m = k;
    one_frame_[0] = frames[b];
    Eigen::MatrixXd& own = one_row_[m];
    models_[m]->features(one_frame_, terrain, own);
    for (Eigen::Index j = 0; j < own.cols(); ++j) out(row, feature_column_[m][static_cast<size_t>(j)]) = own(0, j);
    out(row, columns - 2) = static_cast<double>(m);
    out(row, columns - 1) = point_w_[m];
  }
}

DerivativeSupport PatchedModel::derivative() const {
  DerivativeSupport weakest = DerivativeSupport::Analytic;
  for (const auto& m : models_) {
    const DerivativeSupport d = m->derivative();
    if (d == DerivativeSupport::None) return d;
    if (d == DerivativeSupport::Autograd) weakest = d;
  }
  return weakest;
}

std::string PatchedModel::describe() const {
  std::ostringstream s;
  s << "patched ground, " << layout_->describe() << ": default " << models_[0]->describe();
  for (size_t m = 1; m < models_.size(); ++m) {
    const std::vector<MaterialPatch>& patches = layout_->patches();
    s << "; " << (m - 1 < patches.size() ? "'" + patches[m - 1].name + "'" : "material " + std::to_string(m)) << " "
      << models_[m]->describe();
  }
  return s.str();
}

void PatchedModel::evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                            std::vector<ContactWrenches>& out, bool with_derivatives) const {
  const size_t B = frames.size();
  const size_t M = models_.size();
  if (out.size() != B) out.resize(B);
  w_.resize(B * M);
  wx_.resize(B * M);
  wy_.resize(B * M);
  for (size_t b = 0; b < B; ++b)
    layout_->weights(frames[b].position.x(), frames[b].position.y(), &w_[b * M], &wx_[b * M], &wy_[b * M]);
  for (size_t b = 0; b < B; ++b) {
    ContactWrenches& o = out[b];
    if (o.V.cols() != vertex_count_) o.resize(vertex_count_);
    o.V.setZero();
    if (with_derivatives)
      for (Mat6X& d : o.dV) d.setZero();
  }
  for (size_t m = 0; m < M; ++m) {
    bool used = false;
    for (size_t b = 0; b < B && !used; ++b) used = w_[b * M + m] != 0.0 || wx_[b * M + m] != 0.0 || wy_[b * M + m] != 0.0;
    if (!used) continue;
    std::vector<ContactWrenches>& part = parts_[m];
    const int K = models_[m]->vertexCount();
    if (part.size() != B) part.resize(B);
    for (ContactWrenches& p : part)
      if (p.V.cols() != K) p.resize(K);
    models_[m]->evaluate(frames, terrain, part, with_derivatives);
    const int offset = offsets_[m];
    for (size_t b = 0; b < B; ++b) {
      const double w = w_[b * M + m], gx = wx_[b * M + m], gy = wy_[b * M + m];
      if (w == 0.0 && gx == 0.0 && gy == 0.0) continue;
      ContactWrenches& o = out[b];
      const ContactWrenches& p = part[b];
      if (w == 1.0) o.V.middleCols(offset, K) = p.V;
      else o.V.middleCols(offset, K) = w * p.V;
      if (!with_derivatives) continue;
      for (int i = 0; i < 6; ++i) o.dV[i].middleCols(offset, K) = w * p.dV[i];
      o.dV[3].middleCols(offset, K) += gx * p.V;
      o.dV[4].middleCols(offset, K) += gy * p.V;
    }
  }
}

}  // namespace nmdp
