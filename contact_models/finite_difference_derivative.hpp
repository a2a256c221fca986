// dV/dξ from values of V only: central differences along the six frame perturbations ξ of
// contact_model.hpp. This is how the zeroth-order methods learn how the wrench polytope changes
// with the pose without ever asking the model for a derivative (a model may have none, or a costly
// one), at the price of 12 extra evaluations per contact, done as one batch.
#pragma once
#include <vector>

#include "contact_models/contact_model.hpp"

namespace nmdp {

// The frame moved along ξ_i by `step`: for i < 3 a rotation by `step` rad about world axis i
// around the sphere centre (the link-fixed axes turn), for i ≥ 3 a translation by `step` m along
// world axis i − 3.
ContactFrame perturbedFrame(const ContactFrame& frame, int i, double step);

class FiniteDifferenceDerivative {
 public:
  // Steps of 1e-6 m and 1e-6 rad: for the stiff cubic Coulomb contact (V ∝ d³ at d of a few mm) the
  // truncation error is about 1e-7 relative and the round-off 1e-8.
  static constexpr double kTranslationStep = 1e-6;
  static constexpr double kRotationStep = 1e-6;

  // Buffers for up to `contacts` contacts of `vertices` vertices each; evaluate() then allocates
  // nothing of its own.
  FiniteDifferenceDerivative(int contacts, int vertices);

  // out[c].dV[i] ← (V(frame_c + δ e_i) − V(frame_c − δ e_i)) / 2δ for every contact; out[c].V is left
  // untouched. One batched evaluation of the model, without derivatives.
  void evaluate(const ContactModel& model, const std::vector<ContactFrame>& frames, const Terrain& terrain,
                std::vector<ContactWrenches>& out);

 private:
  void resize(size_t contacts);
  int vertices_ = 0;
  std::vector<ContactFrame> shifted_;      // 12 per contact: ξ_0+, ξ_0−, …, ξ_5−
  std::vector<ContactWrenches> shifted_V_;
};

}  // namespace nmdp
