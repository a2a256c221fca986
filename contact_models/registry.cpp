#include "contact_models/registry.hpp"

#include "common/input_error.hpp"
#include "common/text.hpp"

namespace nmdp {

void ContactModelRegistry::add(const std::string& type, std::vector<std::string> parameters, ContactModelFactory factory) {
  entries_[type] = Entry{std::move(parameters), std::move(factory)};
}

std::vector<std::string> ContactModelRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& [type, entry] : entries_) out.push_back(type);
  return out;
}

const std::vector<std::string>& ContactModelRegistry::parameters(const std::string& type) const {
  auto it = entries_.find(type);
  if (it == entries_.end()) throw InputError("unknown contact model type '" + type + "' (valid: " + join(types()) + ")");
  return it->second.parameters;
}

std::unique_ptr<ContactModel> ContactModelRegistry::build(const nlohmann::json& config, const ConfigContext& ctx) const {
  if (!config.is_object()) throw InputError(ctx.where + ": expected an object such as {\"type\": \"coulomb\"}, got " + config.dump());
  if (!config.contains("type") || !config.at("type").is_string())
    throw InputError(ctx.where + ".type: missing; valid types: " + join(types()));
  const std::string type = config.at("type").get<std::string>();
  auto it = entries_.find(type);
  if (it == entries_.end()) {
    const std::string near = closestMatch(type, types());
    throw InputError(ctx.where + ".type: unknown contact model '" + type + "'" +
                     (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; valid types: " + join(types()));
  }
  std::vector<std::string> keys = it->second.parameters;
  keys.insert(keys.begin(), "type");
  requireKnownKeys(config, keys, ctx);
  nlohmann::json params = config;
  params.erase("type");
  return it->second.factory(params, ctx);
}

}  // namespace nmdp
