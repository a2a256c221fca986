#include "training/fit_report.hpp"

namespace nmdp {

std::string fitReportOpening(const std::string& kind, const std::string& data, const nlohmann::ordered_json& settings,
                             const std::vector<std::string>& from_data) {
  std::string s = kind + " fit of " + data + "\n";
  s += "settings: " + settings.dump() + "\n";
  for (const std::string& d : from_data) s += "decided from the data: " + d + "\n";
  return s;
}

std::array<int, 3> countByOrigin(const PlanarPoints& points, const std::vector<bool>* selected) {
  std::array<int, 3> counts{0, 0, 0};
  for (size_t i = 0; i < points.origin.size(); ++i)
    if (!selected || (*selected)[i]) ++counts[static_cast<int>(points.origin[i])];
  return counts;
}

}  // namespace nmdp
