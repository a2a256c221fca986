// A contact model for ground of several materials (terrain/material_layout.hpp): each contact takes
// the models of the materials under its sphere centre (x, y), blended by their weights w_m:
//
//     V = [w_0 V_0, w_1 V_1, ..., w_{M−1} V_{M−1}]    (K = Σ K_m columns),
//
// i.e. the polytope conv{0, w_m V_m}, and
//
//     dV_m/dξ_i = w_m dV_m/dξ_i + V_m ∂w_m/∂ξ_i,   ∂w_m/∂ξ = (0, 0, 0, ∂w_m/∂x, ∂w_m/∂y, 0)
//
// (the translations of ξ move the centre; the rotations, about the centre, do not). Where a
// contact's weight of material m is 0, m's columns are 0; a material's model is evaluated only
// when some contact of the batch stands on it, so on one material only that model runs, and where
// w_m = 1 its columns are that model's V bit for bit. derivative() is the weakest of the
// materials' (Analytic < Autograd < None). Allocates nothing once warmed up (the batch is passed
// whole to each evaluated model, so that models which size scratch per batch keep their buffers).
//
// Features: a contact reports the features of the material with the largest weight under its
// centre (the lowest index on a tie, e.g. the default at the middle of a band), as that material's
// model computes them. The columns are fixed for the model's lifetime: the union of the materials'
// columns by name, in the order they first appear (material 0's first, so "depth" leads), then
// "material" (the index m of that material: 0 the default, m ≥ 1 patch m − 1) and "weight" (its
// w_m). A column the reporting material does not have is NaN (e.g. "beta" where a Coulomb default
// reports). Two materials with one column name but different units throw std::invalid_argument.
#pragma once
#include <memory>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "terrain/material_layout.hpp"

namespace nmdp {

class PatchedModel : public ContactModel {
 public:
  // models[m] for material m (models.size() == layout->materialCount()); models[0] the default.
  // Throws std::invalid_argument for a size mismatch or a null model.
  PatchedModel(std::shared_ptr<const MaterialLayout> layout, std::vector<std::unique_ptr<ContactModel>> models);

  int vertexCount() const override { return vertex_count_; }
  DerivativeSupport derivative() const override;
  std::string describe() const override;
  // The default material's configuration (the patches' models are in the terrain's configuration).
  nlohmann::json configuration() const override { return models_[0]->configuration(); }
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain& terrain, std::vector<ContactWrenches>& out,
                bool with_derivatives) const override;
  // The union of the materials' columns, then "material" and "weight" (see above).
  std::vector<ContactFeatureInfo> featureInfo() const override { return feature_info_; }
  void features(const std::vector<ContactFrame>& frames, const Terrain& terrain,
                Eigen::Ref<Eigen::MatrixXd> out) const override;

  const MaterialLayout& layout() const { return *layout_; }
  const ContactModel& material(int m) const { return *models_[static_cast<size_t>(m)]; }
  int columnOffset(int m) const { return offsets_[static_cast<size_t>(m)]; }

 private:
  std::shared_ptr<const MaterialLayout> layout_;
  std::vector<std::unique_ptr<ContactModel>> models_;
  std::vector<int> offsets_;  // first column of each material
  int vertex_count_ = 0;
  // Scratch, sized by the number of contacts and materials: weights and gradients (contact-major,
  // M per contact) and each material's wrenches of the whole batch.
  mutable std::vector<double> w_, wx_, wy_;
  mutable std::vector<std::vector<ContactWrenches>> parts_;
  // Features: the column layout, material m's column j going to column feature_column_[m][j], and
  // scratch sized in the constructor (features() takes one contact at a time, so it never allocates):
  // the weights at one point and one contact's frame and features per material.
  std::vector<ContactFeatureInfo> feature_info_;
  std::vector<std::vector<Eigen::Index>> feature_column_;
  mutable std::vector<double> point_w_, point_wx_, point_wy_;
  mutable std::vector<ContactFrame> one_frame_;
  mutable std::vector<Eigen::MatrixXd> one_row_;
};

}  // namespace nmdp
