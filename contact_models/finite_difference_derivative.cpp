#include "contact_models/finite_difference_derivative.hpp"

#include <Eigen/Geometry>

namespace nmdp {

ContactFrame perturbedFrame(const ContactFrame& frame, int i, double step) {
  ContactFrame out = frame;
  if (i < 3) {
    const Mat3 R = Eigen::AngleAxisd(step, Vec3::Unit(i)).toRotationMatrix();
    out.leg_axis = R * frame.leg_axis;
    if (frame.lateral_rotates) out.lateral = R * frame.lateral;
  } else {
    out.position[i - 3] += step;
  }
  return out;
}

FiniteDifferenceDerivative::FiniteDifferenceDerivative(int contacts, int vertices) : vertices_(vertices) {
  resize(contacts);
}

void FiniteDifferenceDerivative::resize(size_t contacts) {
  shifted_.resize(12 * contacts);
  shifted_V_.resize(12 * contacts);
  for (ContactWrenches& w : shifted_V_) w.V.setZero(6, vertices_);
}

void FiniteDifferenceDerivative::evaluate(const ContactModel& model, const std::vector<ContactFrame>& frames,
                                          const Terrain& terrain, std::vector<ContactWrenches>& out) {
  const size_t C = frames.size();
  if (shifted_.size() != 12 * C) resize(C);
  for (size_t c = 0; c < C; ++c)
    for (int i = 0; i < 6; ++i) {
      const double step = i < 3 ? kRotationStep : kTranslationStep;
      shifted_[12 * c + 2 * i] = perturbedFrame(frames[c], i, step);
      shifted_[12 * c + 2 * i + 1] = perturbedFrame(frames[c], i, -step);
    }
  model.evaluate(shifted_, terrain, shifted_V_, false);
  for (size_t c = 0; c < C; ++c)
    for (int i = 0; i < 6; ++i) {
      const double step = i < 3 ? kRotationStep : kTranslationStep;
      out[c].dV[i].noalias() = (shifted_V_[12 * c + 2 * i].V - shifted_V_[12 * c + 2 * i + 1].V) * (0.5 / step);
    }
}

}  // namespace nmdp
