// The integrator's options declared once (config/integrator_options.hpp): the declaration's defaults
// are the struct's, parsing and dumping go through the same keys, the ranges give the scene's
// messages, and validateIntegratorOptions refuses what the declarations refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/input_error.hpp"
#include "config/integrator_options.hpp"

namespace nmdp {
namespace {

using json = nlohmann::json;

std::string readError(const json& object) {
  try {
    readIntegratorSettings(object, KeyPath{"scene.json", "integrator"});
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted " << object.dump();
  return "";
}

std::string validateError(const IntegratorOptions& options) {
  try {
    validateIntegratorOptions(options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "validateIntegratorOptions accepted the options";
  return "";
}

TEST(IntegratorFields, SchemaDefaultsAreTheStructsDefaults) {
  const IntegratorSettings defaults;
  const nlohmann::ordered_json schema = integratorFields().schema();
  ASSERT_EQ(schema.size(), integratorFields().keys().size());
  const json dumped = integratorFields().dump(defaults);
  for (const auto& row : schema) {
    const std::string key = row.at("key");
    EXPECT_EQ(json::parse(row.at("default").dump()), dumped.at(key)) << key;
    EXPECT_FALSE(row.at("doc").get<std::string>().empty()) << key;
  }
  EXPECT_EQ(dumped.at("epsilon"), defaults.options.epsilon);
  EXPECT_EQ(dumped.at("method"), "ne-pgm");
  EXPECT_EQ(dumped.at("kinetic_energy"), "full-body-pd");
  EXPECT_EQ(dumped.at("dt"), 0.05);
  // Set by programs only: not a key of a file.
  EXPECT_FALSE(dumped.contains("energy_tolerance"));
  EXPECT_NE(readError({{"energy_tolerance", 1.0}}).find("integrator.energy_tolerance: unknown key"), std::string::npos);
}

TEST(IntegratorFields, DumpParsesBackToTheSameSettings) {
  const json given = {{"method", "pbd-zopgm"}, {"order", 2},          {"dt", 0.01},         {"eta", 2.5},
                      {"beta_min", 1e-3},      {"adaptive", false},   {"accuracy", 0.0},    {"max_outer_iterations", 7},
                      {"zeroth_order_jacobian", "dropped"}};
  const IntegratorSettings s = readIntegratorSettings(given, KeyPath{"scene.json", "integrator"});
  EXPECT_EQ(s.options.method, Method::PbdZopgm);
  EXPECT_EQ(s.options.order, 2);
  EXPECT_EQ(s.options.max_outer_iterations, 7);
  EXPECT_EQ(s.options.zeroth_order_jacobian, ZerothOrderJacobian::Dropped);
  const json dumped = integratorFields().dump(s);
  for (const auto& [key, value] : given.items()) EXPECT_EQ(dumped.at(key), value) << key;
  const IntegratorSettings again = readIntegratorSettings(dumped, KeyPath{"scene.json", "integrator"});
  EXPECT_EQ(integratorFields().dump(again), dumped);
}

TEST(IntegratorFields, DefaultsFollowTheBoundsTheyDependOn) {
  // min_substep's default 1e-5 s is above a 1e-6 s step: it becomes dt; beta_initial follows beta_min.
  const IntegratorSettings s =
      readIntegratorSettings({{"dt", 1e-6}, {"beta_min", 1e-2}}, KeyPath{"scene.json", "integrator"});
  EXPECT_EQ(s.options.min_substep, 1e-6);
  EXPECT_EQ(s.options.beta_initial, 1e-2);
}

TEST(IntegratorFields, RangesGiveTheScenesMessages) {
  EXPECT_EQ(readError({{"dt", 2}}), "scene.json: integrator.dt: must be in [1e-06, 1], got 2");
  EXPECT_EQ(readError({{"min_substep", 0.1}}), "scene.json: integrator.min_substep: must be in (0, 0.05], got 0.1");
  EXPECT_EQ(readError({{"beta_min", 1.0}, {"beta_max", 0.5}}),
            "scene.json: integrator.beta_max: must be in (1, 1e+12], got 0.5");
  EXPECT_EQ(readError({{"order", 3}}), "scene.json: integrator.order: expected 1 (backward Euler, the paper's) or 2 (BDF2), got 3");
  EXPECT_NE(readError({{"method", "ne-mdp"}, {"order", 2}}).find("integrator.order: ne-mdp is first order only"),
            std::string::npos);
  EXPECT_NE(readError({{"method", "ne-pgn"}}).find("unknown method 'ne-pgn' (did you mean 'ne-pgm'?); valid: ne-pgm,"),
            std::string::npos);
  EXPECT_NE(readError({{"max_outer_iterations", 0}}).find("integrator.max_outer_iterations: must be in [1, 100000], got 0"),
            std::string::npos);
  EXPECT_NE(readError({{"min_substep", 1e-12}}).find("must be at least dt / 2^20"), std::string::npos);
  EXPECT_NE(readError({{"adaptive", 1}}).find("integrator.adaptive: expected true or false"), std::string::npos);
}

TEST(IntegratorFields, ValidationRefusesWhatTheDeclarationsRefuse) {
  EXPECT_NO_THROW(validateIntegratorOptions(IntegratorOptions()));
  IntegratorOptions o;
  o.energy_tolerance = std::numeric_limits<double>::infinity();  // disables the check: allowed
  o.min_substep = 2.0;                                            // no dt to bound it
  EXPECT_NO_THROW(validateIntegratorOptions(o));
  for (double bad : {-1e-3, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    o = IntegratorOptions();
    o.accuracy = bad;
    EXPECT_NE(validateError(o).find("integrator: options out of range: accuracy"), std::string::npos) << bad;
  }
  o = IntegratorOptions();
  o.eta = 1.0;
  EXPECT_EQ(validateError(o), "integrator: options out of range: eta must be in (1, 1000], got 1");
  o = IntegratorOptions();
  o.beta_max = o.beta_min / 2;
  EXPECT_NE(validateError(o).find("beta_max must be in (0.0001, 1e+12], got 5e-05"), std::string::npos);
  o = IntegratorOptions();
  o.order = 3;
  EXPECT_NE(validateError(o).find("integrator: order 3 is not available"), std::string::npos);
  o.order = 2;
  o.method = Method::NeMdp;
  EXPECT_NE(validateError(o).find("ne-mdp is first order only"), std::string::npos);
}

}  // namespace
}  // namespace nmdp
