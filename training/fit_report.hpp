// What the RBF and MLP fit reports (rbf_fit.hpp, mlp/mlp_fit.hpp) share: their opening lines and
// the count of points by origin.
#pragma once
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "training/augmentation.hpp"

namespace nmdp {

// "<kind> fit of <data>", the settings used and each setting decided from the data, one a line.
std::string fitReportOpening(const std::string& kind, const std::string& data, const nlohmann::ordered_json& settings,
                             const std::vector<std::string>& from_data);

// The points per origin (measured, mirrored, above the surface); only those with selected[i] when
// `selected` is given.
std::array<int, 3> countByOrigin(const PlanarPoints& points, const std::vector<bool>* selected = nullptr);

}  // namespace nmdp
