// Builds a contact model from its JSON through the registry, as a scene does, and evaluates it with
// and without derivatives at feet above, at and below a level plane, upright and tilted, as the
// solver would; a non-finite vertex from a model that loaded is a finding (its file was accepted).
#pragma once
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "contact_models/registry.hpp"
#include "terrain/plane.hpp"

namespace nmdp::fuzz {

inline void probeContactModel(const nlohmann::json& config) {
  const std::unique_ptr<ContactModel> model = ContactModelRegistry::withBuiltins().build(config, ConfigContext{"fuzz", ""});
  const PlaneTerrain plane;
  std::vector<ContactFrame> frames;
  for (double depth : {0.05, 0.0, -0.01, -0.04, -0.2})
    for (double angle : {0.0, 0.5, -1.2}) {
      ContactFrame f;
      f.radius = 0.02;
      f.position = Eigen::Vector3d(0.1, 0.0, f.radius + depth);
      f.leg_axis = Eigen::Vector3d(std::sin(angle), 0.0, std::cos(angle));
      frames.push_back(f);
    }
  std::vector<ContactWrenches> out(frames.size());
  for (ContactWrenches& w : out) w.resize(model->vertexCount());
  const bool derivatives = model->derivative() != DerivativeSupport::None;
  model->evaluate(frames, plane, out, derivatives);
  for (const ContactWrenches& w : out)
    if (!w.V.allFinite()) throw std::logic_error("a loaded contact model returned a non-finite vertex");
}

}  // namespace nmdp::fuzz
