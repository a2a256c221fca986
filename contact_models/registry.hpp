// Builds contact models from JSON objects ({"type": "coulomb", ...}, {"type": "rbf", "file": ...},
// {"type": "mlp", "file": ...}). An explicit object, no global state: withBuiltins() registers the
// three built-in types; applications may add their own.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "contact_models/contact_model.hpp"
#include "config/json_params.hpp"

namespace nmdp {

using ContactModelFactory = std::function<std::unique_ptr<ContactModel>(const nlohmann::json&, const ConfigContext&)>;

class ContactModelRegistry {
 public:
  static ContactModelRegistry withBuiltins();

  // `parameters`: every key the type accepts besides "type"; others are rejected before the factory runs.
  void add(const std::string& type, std::vector<std::string> parameters, ContactModelFactory factory);
  std::unique_ptr<ContactModel> build(const nlohmann::json& config, const ConfigContext& ctx) const;
  std::vector<std::string> types() const;
  const std::vector<std::string>& parameters(const std::string& type) const;

 private:
  struct Entry {
    std::vector<std::string> parameters;
    ContactModelFactory factory;
  };
  std::map<std::string, Entry> entries_;
};

}  // namespace nmdp
