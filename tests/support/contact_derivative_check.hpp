// The one finite-difference checker of the contact models' derivatives: dV/dξ (a contact frame moved
// along the six motions ξ of contact_model.hpp) and dW/df (a feature function's wrenches against its
// features φ, β), both by central differences with a step and a tolerance that each call states.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "contact_models/finite_difference_derivative.hpp"
#include "contact_models/planar_wrench_model.hpp"

namespace nmdp::test {

// Steps and tolerance of one dV/dξ check; the caller states why they fit its model.
struct VertexDerivativeCheck {
  double rotation_step = 1e-6;     // rad, ξ_0..2 (about the sphere centre)
  double translation_step = 1e-6;  // m, ξ_3..5
  double tolerance = 1e-6;         // bound on max |analytic − numeric| / scale, every contact and ξ_i
  // The scale of an error: the largest entry of all six dV/dξ of the contact (PerContact: a direction
  // whose derivative nearly vanishes is measured against the others) or of dV/dξ_i alone (PerMotion).
  // Taken on both sides and the smaller kept, so that neither side can inflate it; never below
  // scale_floor (N or N·m per m or rad; 0 allowed where a vanishing derivative is itself an error).
  enum class Scale { PerContact, PerMotion } scale = Scale::PerContact;
  double scale_floor = 1e-9;
};

// dV/dξ of every contact by central differences: out[c].V is V at the frames, out[c].dV[i] is
// (V(frame_c + h e_i) − V(frame_c − h e_i)) / 2h, with frame c moved inside the whole batch (the
// others as they are), which is how the solver evaluates a step.
inline std::vector<ContactWrenches> centralVertexDerivative(const ContactModel& model,
                                                            const std::vector<ContactFrame>& frames,
                                                            const Terrain& terrain, double rotation_step,
                                                            double translation_step) {
  const int K = model.vertexCount();
  std::vector<ContactWrenches> out(frames.size()), plus(frames.size()), minus(frames.size());
  for (std::vector<ContactWrenches>* v : {&out, &plus, &minus})
    for (ContactWrenches& w : *v) w.resize(K);
  model.evaluate(frames, terrain, out, false);
  for (size_t c = 0; c < frames.size(); ++c) {
    for (int i = 0; i < 6; ++i) {
      const double h = i < 3 ? rotation_step : translation_step;
      std::vector<ContactFrame> moved = frames;
      moved[c] = perturbedFrame(frames[c], i, h);
      model.evaluate(moved, terrain, plus, false);
      moved[c] = perturbedFrame(frames[c], i, -h);
      model.evaluate(moved, terrain, minus, false);
      out[c].dV[i] = (plus[c].V - minus[c].V) / (2 * h);
    }
  }
  return out;
}

// Largest |entry| of dV/dξ_i (PerMotion) or of all six (PerContact).
inline double largestDerivative(const ContactWrenches& w, int i, VertexDerivativeCheck::Scale scale) {
  if (scale == VertexDerivativeCheck::Scale::PerMotion) return w.dV[i].cwiseAbs().maxCoeff();
  double largest = 0.0;
  for (const Mat6X& d : w.dV) largest = std::max(largest, d.cwiseAbs().maxCoeff());
  return largest;
}

// Expects every analytic[c].dV[i] to match numeric[c].dV[i] within check.tolerance (and both to be
// finite); returns the worst error found. `label` names the case in a failure.
inline double expectVertexDerivativesMatch(const std::vector<ContactWrenches>& analytic,
                                           const std::vector<ContactWrenches>& numeric,
                                           const VertexDerivativeCheck& check, const std::string& label = "") {
  EXPECT_EQ(analytic.size(), numeric.size()) << label;
  double worst = 0.0;
  for (size_t c = 0; c < std::min(analytic.size(), numeric.size()); ++c) {
    for (int i = 0; i < 6; ++i) {
      const double scale = std::max(std::min(largestDerivative(analytic[c], i, check.scale),
                                             largestDerivative(numeric[c], i, check.scale)),
                                    check.scale_floor);
      const double error = (analytic[c].dV[i] - numeric[c].dV[i]).cwiseAbs().maxCoeff() / scale;
      EXPECT_TRUE(analytic[c].dV[i].allFinite() && numeric[c].dV[i].allFinite()) << label << ", contact " << c;
      EXPECT_LT(error, check.tolerance) << label << ", contact " << c << ", xi_" << i << "\nanalytic\n"
                                        << analytic[c].dV[i] << "\nnumeric\n" << numeric[c].dV[i];
      worst = std::max(worst, std::isnan(error) ? INFINITY : error);
    }
  }
  return worst;
}

struct VertexDerivativeResult {
  std::vector<ContactWrenches> analytic, numeric;  // V and dV/dξ of every contact, both ways
  double worst = 0.0;                              // the largest error, as the check measures it
};

// The model's own dV/dξ (all frames in one batch) against centralVertexDerivative.
inline VertexDerivativeResult checkVertexDerivative(const ContactModel& model, const std::vector<ContactFrame>& frames,
                                                    const Terrain& terrain, const VertexDerivativeCheck& check,
                                                    const std::string& label = "") {
  VertexDerivativeResult r;
  r.analytic.resize(frames.size());
  for (ContactWrenches& w : r.analytic) w.resize(model.vertexCount());
  model.evaluate(frames, terrain, r.analytic, true);
  r.numeric = centralVertexDerivative(model, frames, terrain, check.rotation_step, check.translation_step);
  r.worst = expectVertexDerivativesMatch(r.analytic, r.numeric, check, label);
  return r;
}

// dW/dφ (direction 0) or dW/dβ (direction 1) of every row of `points` by central differences of
// order 2 or 4 (the five-point stencil, for where the curvature spoils the three-point one). Rows are
// independent, so one shifted batch differentiates them all.
inline Eigen::MatrixXd centralFeatureDerivative(const FeatureWrenchFunction& f, const Eigen::MatrixX2d& points,
                                                int direction, double step, int order = 2) {
  const std::vector<std::pair<int, double>> stencil =
      order == 4 ? std::vector<std::pair<int, double>>{{2, -1.0}, {1, 8.0}, {-1, -8.0}, {-2, 1.0}}
                 : std::vector<std::pair<int, double>>{{1, 1.0}, {-1, -1.0}};
  const double denominator = order == 4 ? 12 * step : 2 * step;
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(points.rows(), 3 * f.vertexCount());
  for (const auto& [k, weight] : stencil) {
    Eigen::MatrixX2d shifted = points;
    shifted.col(direction).array() += k * step;
    Eigen::MatrixXd W;
    f.evaluate(shifted, W, nullptr, nullptr);
    sum += weight * W;
  }
  return sum / denominator;
}

}  // namespace nmdp::test
