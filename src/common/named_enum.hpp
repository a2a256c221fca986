// The one pattern for enums that have names in configuration files: a table of {value, name}
// pairs, and lookups both ways over it. Used by every enum a user writes by name (methods, gait
// types, terrain kinds, ...), so that messages list the valid names the same way everywhere.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nmdp {

template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value` in `table` ("?" if the table lacks it, which is a programming error).
template <class Enum, std::size_t N>
const char* nameOf(const EnumName<Enum> (&table)[N], Enum value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

template <class Enum, std::size_t N>
std::optional<Enum> enumFromName(const EnumName<Enum> (&table)[N], const std::string& name) {
  for (const auto& entry : table)
    if (name == entry.name) return entry.value;
  return std::nullopt;
}

// For parsers that report "unknown" themselves: sets *value and returns true when `name` is in the table.
template <class Enum, std::size_t N>
bool assignIfNamed(const EnumName<Enum> (&table)[N], const std::string& name, Enum* value) {
  const std::optional<Enum> found = enumFromName(table, name);
  if (found) *value = *found;
  return found.has_value();
}

// Every name in the table's order, for messages and schemas.
template <class Enum, std::size_t N>
std::vector<std::string> namesOf(const EnumName<Enum> (&table)[N]) {
  std::vector<std::string> names;
  names.reserve(N);
  for (const auto& entry : table) names.emplace_back(entry.name);
  return names;
}

}  // namespace nmdp
