// The schema of scene files: every key of every section with its type, default, range and one line
// of documentation. The parser takes its key lists from here and the integrator section from
// integratorFields(), so `nmdp simulate --schema` lists exactly the keys a scene may hold.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nmdp {

// The sections of a scene by key path ("" for the top level, "robot.initial",
// "contacts.points[]", "controller.gait:trot" for the keys of one gait type).
std::vector<std::string> sceneSections();
// The keys of one section, in the order messages list them.
const std::vector<std::string>& sceneSectionKeys(const std::string& section);

// {"section": [{"key", "type", "default", "range", "unit", "doc"}, ...], ...}.
nlohmann::ordered_json sceneSchema();
// The schema as text, one key a line, as `nmdp simulate --schema` prints it.
std::string sceneSchemaText();

}  // namespace nmdp
