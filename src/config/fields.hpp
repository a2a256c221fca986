// One declaration per configuration field: name, default (read from a default-constructed struct),
// range or choices, unit and one line of documentation. The list of a struct's fields drives its
// parsing and validation (json_reader.hpp's messages), the resolved-config dump and the schema text
// that `--schema` prints. A struct declares its fields in one function, e.g.
//   fields.number("epsilon", &IntegratorOptions::epsilon, above(0), atMost(1), "J", "stop threshold")
#pragma once
#include <algorithm>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/json_text.hpp"
#include "common/named_enum.hpp"
#include "common/text.hpp"
#include "config/json_reader.hpp"

namespace nmdp {

// A bound that is either a number or the value of another number of the same configuration
// ("beta_min"), named as the schema shows it.
template <class S>
struct Limit {
  Bound bound;
  std::function<double(const S&)> of;  // empty: the constant bound
  std::string name;                    // of the field or quantity `of` reads
  Limit(Bound b) : bound(b) {}         // NOLINT: a constant bound reads as one
  Limit(bool open, std::function<double(const S&)> value, std::string what)
      : bound{0.0, open}, of(std::move(value)), name(std::move(what)) {}
  Bound at(const S& s) const { return of ? Bound{of(s), bound.open} : bound; }
  std::string text() const { return of ? name : numberText(bound.value); }
};

template <class S>
struct Field {
  std::string name;
  std::string type;   // "number", "integer", "boolean", "string", "[number]", ...
  std::string range;  // "(0, 1]", "tanh | softplus | silu"; "" if any value of the type
  std::string unit;   // "s", "m", "" for none
  std::string doc;    // one line
  bool in_files = true;  // false: set by programs only (a key no file may hold)
  std::function<nlohmann::json(const S&)> value;                                      // as dumped
  std::function<void(const nlohmann::json& object, S& s, const KeyPath& w)> read;     // object[name] if present
  std::function<std::string(const S& s)> check;  // what is wrong with s's value ("" if nothing)
};

// The declarations of one struct, in the order they are read (a bound may name an earlier field).
template <class S>
class Fields {
 public:
  std::vector<Field<S>> list;

  // A field with its description only; the caller sets value, read and check.
  static Field<S> make(const std::string& name, const std::string& type, const std::string& range,
                       const std::string& unit, const std::string& doc) {
    Field<S> f;
    f.name = name;
    f.type = type;
    f.range = range;
    f.unit = unit;
    f.doc = doc;
    return f;
  }

  // A number in [lo, hi] (each bound open or closed). A default outside a bound that names another
  // field is moved onto it (beta_initial's default follows beta_min).
  template <class M>
  Fields& number(const std::string& name, M member, Limit<S> lo, Limit<S> hi, const std::string& unit,
                 const std::string& doc) {
    Field<S> f = make(name, "number", intervalOf(lo, hi), unit, doc);
    f.value = [member](const S& s) { return nlohmann::json(get(s, member)); };
    f.read = [name, member, lo, hi, legacy = out_of_range_messages_](const nlohmann::json& object, S& s, const KeyPath& w) {
      const Bound l = lo.at(s), h = hi.at(s);
      double fallback = get(s, member);
      if (lo.of && !l.open && fallback < l.value) fallback = l.value;
      if (hi.of && !h.open && h.value < fallback) fallback = h.value;
      if (legacy && object.contains(name)) {
        const double x = read::finiteNumber(object.at(name), w / name);
        if (!inRange(x, l, h))
          (w / name).fail("value " + jsonForMessage(object.at(name)) + " is out of range " + intervalText(l, h));
      }
      ref(s, member) = read::number(object, name, fallback, w, l, h);
    };
    f.check = [member, lo, hi](const S& s) {
      const double x = get(s, member);
      return inRange(x, lo.at(s), hi.at(s)) ? std::string() : rangeText(lo.at(s), hi.at(s)) + ", got " + numberText(x);
    };
    list.push_back(std::move(f));
    return *this;
  }

  // An integer in [lo, hi]; `expected` (if given) replaces the message of any bad value.
  template <class M>
  Fields& integer(const std::string& name, M member, int lo, int hi, const std::string& unit, const std::string& doc,
                  const std::string& expected = "") {
    const std::string range = hi >= read::kNoIntegerLimit ? "[" + std::to_string(lo) + ", inf)"
                                                          : "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    Field<S> f = make(name, "integer", range, unit, doc);
    f.value = [member](const S& s) { return nlohmann::json(get(s, member)); };
    f.read = [name, member, lo, hi, expected](const nlohmann::json& object, S& s, const KeyPath& w) {
      if (!expected.empty() && object.contains(name)) {
        const nlohmann::json& v = object.at(name);
        if (!v.is_number_integer() || v < lo || v > hi) (w / name).fail("expected " + expected + ", got " + jsonForMessage(v));
      }
      ref(s, member) = read::integer(object, name, get(s, member), w, lo, hi);
    };
    f.check = [member, lo, hi, range](const S& s) {
      const int x = get(s, member);
      return x >= lo && x <= hi ? std::string() : "must be in " + range + ", got " + std::to_string(x);
    };
    list.push_back(std::move(f));
    return *this;
  }

  template <class M>
  Fields& boolean(const std::string& name, M member, const std::string& doc) {
    Field<S> f = make(name, "boolean", "", "", doc);
    f.value = [member](const S& s) { return nlohmann::json(get(s, member)); };
    f.read = [name, member](const nlohmann::json& object, S& s, const KeyPath& w) {
      ref(s, member) = read::boolean(object, name, get(s, member), w);
    };
    list.push_back(std::move(f));
    return *this;
  }

  // A name from an EnumName table; a bad name fails with "unknown <what> 'x'; valid: a, b" (or
  // with "<expected>, got "x"" if `expected` is given).
  template <class M, class E, std::size_t N>
  Fields& choice(const std::string& name, M member, const EnumName<E> (&table)[N], const std::string& what,
                 const std::string& doc, const std::string& expected = "") {
    const std::vector<std::string> names = namesOf(table);
    Field<S> f = make(name, "string", join(names, " | "), "", doc);
    f.value = [member, &table](const S& s) { return nlohmann::json(nameOf(table, get(s, member))); };
    f.read = [name, member, &table, what, expected](const nlohmann::json& object, S& s, const KeyPath& w) {
      if (!expected.empty()) {
        const std::string given = read::string(object, name, nameOf(table, get(s, member)), w);
        if (!enumFromName(table, given)) (w / name).fail(expected + ", got \"" + given + "\"");
      }
      ref(s, member) = read::named(object, name, get(s, member), table, what, w);
    };
    list.push_back(std::move(f));
    return *this;
  }

  // Any field read and dumped by the caller's functions (lists, optional values, "data").
  Fields& custom(Field<S> f) {
    list.push_back(std::move(f));
    return *this;
  }

  // Range messages of the fields declared after this say "value x is out of range [lo, hi]" (the
  // phrase of contact-model and training configurations) instead of "must be in [lo, hi], got x".
  Fields& outOfRangeMessages() {
    out_of_range_messages_ = true;
    return *this;
  }

  // The last field declared is set by programs only: no file may hold it.
  Fields& programOnly() {
    list.back().in_files = false;
    return *this;
  }

  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    for (const Field<S>& f : list)
      if (f.in_files) out.push_back(f.name);
    return out;
  }
  const Field<S>* find(const std::string& name) const {
    for (const Field<S>& f : list)
      if (f.name == name) return &f;
    return nullptr;
  }

  // Reads every field the object holds (unknown keys are errors) over s's current values.
  void readInto(const nlohmann::json& object, S& s, const KeyPath& w) const {
    checkKeys(object, w, keys());
    for (const Field<S>& f : list)
      if (f.in_files) f.read(object, s, w);
  }
  // Every field in files, with s's values.
  template <class Json = nlohmann::json>
  Json dump(const S& s) const {
    Json out = Json::object();
    for (const Field<S>& f : list)
      if (f.in_files) out[f.name] = f.value(s);
    return out;
  }
  // The first field whose value is out of its range, as "name must be ..., got x" ("" if none).
  std::string firstViolation(const S& s) const {
    for (const Field<S>& f : list)
      if (f.check)
        if (std::string what = f.check(s); !what.empty()) return f.name + " " + what;
    return "";
  }
  // One row per field a file may hold: key, type, default, range or choices, unit, doc.
  nlohmann::ordered_json schema(const S& defaults = S()) const {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const Field<S>& f : list) {
      if (!f.in_files) continue;
      nlohmann::ordered_json row;
      row["key"] = f.name;
      row["type"] = f.type;
      row["default"] = nlohmann::ordered_json::parse(f.value(defaults).dump());
      if (!f.range.empty()) row["range"] = f.range;
      if (!f.unit.empty()) row["unit"] = f.unit;
      row["doc"] = f.doc;
      out.push_back(row);
    }
    return out;
  }

 private:
  bool out_of_range_messages_ = false;

  static std::string intervalOf(const Limit<S>& lo, const Limit<S>& hi) {
    const bool no_lo = !lo.of && lo.bound.value == kNoLow.value;
    const bool no_hi = !hi.of && hi.bound.value == kNoHigh.value;
    return std::string(lo.bound.open || no_lo ? "(" : "[") + (no_lo ? "-inf" : lo.text()) + ", " +
           (no_hi ? "inf" : hi.text()) + (hi.bound.open || no_hi ? ")" : "]");
  }
  // A member is a pointer to member of S or a function S& -> T& (a field of a nested struct).
  template <class M>
  static auto& ref(S& s, M member) {
    if constexpr (std::is_member_object_pointer_v<M>) return s.*member;
    else return member(s);
  }
  template <class M>
  static auto get(const S& s, M member) {
    return ref(const_cast<S&>(s), member);
  }
};

}  // namespace nmdp
