// Reading parameters from JSON configuration objects with messages a user can act on: every error
// names where the object came from (e.g. "scene.json: contacts.model") and the key.
#pragma once
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nmdp {

// Where a configuration object came from, and the folder relative paths are resolved against.
struct ConfigContext {
  std::string where;     // e.g. "scene.json: contacts.model" or "--model"
  std::string base_dir;  // folder of the file that holds the object ("" = current directory)
  std::string resolve(const std::string& path) const;  // relative to base_dir
};

// Throws InputError if `object` has a key not in `valid` (the message lists the valid keys and the
// closest one) or is not a JSON object.
void requireKnownKeys(const nlohmann::json& object, const std::vector<std::string>& valid, const ConfigContext& ctx);

// A finite number in [lo, hi]; no parameter means anything beyond 1e12 in magnitude (in its SI unit),
// and below it products of two stay finite.
double readNumber(const nlohmann::json& object, const std::string& key, double fallback, const ConfigContext& ctx,
                  double lo = -1e12, double hi = 1e12);
int readInteger(const nlohmann::json& object, const std::string& key, int fallback, const ConfigContext& ctx, int lo,
                int hi);
std::string readString(const nlohmann::json& object, const std::string& key, const std::string& fallback,
                       const ConfigContext& ctx);
bool readBool(const nlohmann::json& object, const std::string& key, bool fallback, const ConfigContext& ctx);
Eigen::Vector3d readVec3(const nlohmann::json& object, const std::string& key, const Eigen::Vector3d& fallback,
                         const ConfigContext& ctx);
std::vector<double> readNumbers(const nlohmann::json& object, const std::string& key,
                                const std::vector<double>& fallback, const ConfigContext& ctx);

// Closest candidate by edit distance ("" when none is reasonably close).
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace nmdp
