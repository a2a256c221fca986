// Scene files (src/sim/scene.hpp): defaults, --set overrides, one actionable message per bad input,
// paths relative to the scene file, and the builders the app uses (contacts, gains, gait, start pose).
#include <filesystem>
#include <fstream>
#include <functional>

#include "control/default_gains.hpp"
#include "control/hermite_spline.hpp"
#include "sim/scene.hpp"
#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "test_support.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// The complete scene of DESIGN.md 11, with the robot copied to robots/my_quadruped.urdf.
struct SceneFixture {
  TempDir dir;
  std::string scene_path;
  json scene;
  SceneFixture() {
    fs::create_directories(dir.path() / "robots");
    fs::copy_file(quadrupedUrdf(), dir.path() / "robots" / "my_quadruped.urdf");
    scene = json::parse(R"({
      "robot": {"urdf": "robots/my_quadruped.urdf", "base": "floating"},
      "contacts": {"points": "auto", "model": {"type": "coulomb"}},
      "terrain": {"type": "plane"},
      "integrator": {"method": "ne-pgm", "dt": 0.05},
      "controller": {"gait": {"type": "trot"}},
      "duration": 10.0
    })");
    scene_path = dir.write("scene.json", scene.dump(2));
  }
  std::string urdf() const { return (dir.path() / "robots" / "my_quadruped.urdf").lexically_normal().string(); }
  SceneConfig parse(const json& s) const { return parseScene(s, scene_path); }
  SceneConfig parse() const { return parse(scene); }
  Model model(const SceneConfig& c) const { return loadUrdf(c.urdf, urdfOptionsFor(c)); }
};

bool containsAll(const std::string& text, const std::vector<std::string>& parts) {
  for (const std::string& p : parts)
    if (text.find(p) == std::string::npos) return false;
  return true;
}

// ---- the minimal scene -----------------------------------------------------------------------------

TEST(Scene, MinimalSceneParsesWithEveryDefault) {
  SceneFixture f;
  const SceneConfig c = parseScene(loadSceneJson(f.scene_path), f.scene_path);
  EXPECT_EQ(c.urdf, f.urdf());
  EXPECT_EQ(c.base, BaseType::Floating);
  EXPECT_TRUE(c.locked_joints.empty());
  EXPECT_EQ(c.default_armature, 0.0);
  EXPECT_FALSE(c.initial_height.has_value());
  EXPECT_TRUE(c.auto_contacts);
  EXPECT_EQ(c.contact_model, json({{"type", "coulomb"}}));
  EXPECT_EQ(c.terrain.at("type"), "plane");
  EXPECT_EQ(c.dt, 0.05);
  const IntegratorOptions defaults;
  EXPECT_EQ(c.integrator.method, Method::NePgm);
  EXPECT_EQ(c.integrator.kinetic_energy, defaults.kinetic_energy);
  EXPECT_EQ(c.integrator.adaptive, true);
  EXPECT_EQ(c.integrator.min_substep, 1e-5);
  EXPECT_EQ(c.integrator.epsilon, defaults.epsilon);
  EXPECT_EQ(c.integrator.max_outer_iterations, defaults.max_outer_iterations);
  EXPECT_EQ(c.integrator.projection_backtracking, defaults.projection_backtracking);
  EXPECT_EQ(c.gait_type, SceneGaitType::Trot);
  EXPECT_EQ(c.gait.type, GaitType::Trot);
  EXPECT_EQ(c.gait.trot.period, 0.5);
  EXPECT_EQ(c.gait.trot.duty_factor, 0.5);
  EXPECT_EQ(c.gait.trot.swing_profile, SwingProfile::Cosine);
  EXPECT_TRUE(c.kp.empty() && c.kd.empty() && c.tau_ff.empty());
  EXPECT_EQ(c.duration, 10.0);
  EXPECT_EQ(c.output_file, (fs::current_path() / "scene.h5").lexically_normal().string());
  EXPECT_EQ(c.output_every, 1);

  const json& r = c.resolved;
  EXPECT_EQ(r.at("robot").at("urdf"), f.urdf());
  EXPECT_EQ(r.at("robot").at("base"), "floating");
  EXPECT_EQ(r.at("robot").at("initial").at("base_rpy"), json::array({0.0, 0.0, 0.0}));
  EXPECT_EQ(r.at("contacts").at("points"), "auto");
  EXPECT_EQ(r.at("contacts").at("model").at("type"), "coulomb");
  EXPECT_EQ(r.at("terrain").at("type"), "plane");
  for (const char* key : {"method", "dt", "adaptive", "min_substep", "kinetic_energy", "epsilon", "tol_w", "eta",
                          "eta_reject", "eta_limited", "beta_min", "beta_max", "beta_initial", "adapt_start_penalty",
                          "max_outer_iterations", "projection_tolerance",
                          "projection_max_iterations", "projection_backtracking", "warm_start_weights",
                          "predict_first_iterate", "zeroth_order_jacobian"})
    EXPECT_TRUE(r.at("integrator").contains(key)) << key;
  EXPECT_EQ(r.at("integrator").at("method"), "ne-pgm");
  EXPECT_EQ(r.at("controller").at("gait").at("period"), 0.5);
  EXPECT_EQ(r.at("controller").at("gait").at("duty_factor"), 0.5);
  EXPECT_EQ(r.at("controller").at("gait").at("swing_profile"), "cosine");
  EXPECT_EQ(r.at("controller").at("gait").at("ground_speed_share"), 0.15);
  EXPECT_EQ(r.at("duration"), 10.0);
  EXPECT_EQ(r.at("output").at("every"), 1);
  EXPECT_EQ(r.at("output").at("file"), c.output_file);

  // With the model: gains, start pose, gait sizes and contact points, and it parses again to the same run.
  const Model model = f.model(c);
  const json full = resolvedWithModel(c, model);
  EXPECT_EQ(full.at("controller").at("kp").size(), 12u);
  EXPECT_EQ(full.at("robot").at("initial").at("joints").size(), 12u);
  EXPECT_TRUE(full.at("robot").at("initial").contains("height"));
  EXPECT_TRUE(full.at("controller").at("gait").contains("stride_length"));
  EXPECT_TRUE(full.at("controller").at("gait").contains("step_height"));
  EXPECT_EQ(full.at("contacts").at("points").size(), 4u);
  const SceneConfig again = parseScene(full, f.scene_path);
  EXPECT_TRUE(initialConfiguration(again, model).isApprox(initialConfiguration(c, model), 1e-12));
  EXPECT_TRUE(gainsFor(again, model).kp.isApprox(gainsFor(c, model).kp));
  EXPECT_EQ(resolvedWithModel(again, model), full);
  PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)}, again_target = target;
  for (double t : {0.0, 0.13, 0.4}) {
    gaitFor(c, model)->evaluate(t, target);
    gaitFor(again, model)->evaluate(t, again_target);
    EXPECT_EQ(again_target.position, target.position) << "the same gait, t = " << t;
    EXPECT_EQ(again_target.velocity, target.velocity) << "the same gait, t = " << t;
  }
}

// ---- --set -----------------------------------------------------------------------------------------

TEST(Scene, TrotSwingProfileParsesAndResolves) {
  SceneFixture f;
  json s = f.scene;
  applyOverride(s, "controller.gait.swing_profile=ground_speed", f.scene_path);
  applyOverride(s, "controller.gait.ground_speed_share=0.25", f.scene_path);
  const SceneConfig c = f.parse(s);
  EXPECT_EQ(c.gait.trot.swing_profile, SwingProfile::GroundSpeed);
  EXPECT_EQ(c.gait.trot.ground_speed_share, 0.25);
  EXPECT_EQ(c.resolved.at("controller").at("gait").at("swing_profile"), "ground_speed");
  EXPECT_EQ(c.resolved.at("controller").at("gait").at("ground_speed_share"), 0.25);
  // The resolved scene parses again to the same run.
  const SceneConfig again = f.parse(c.resolved);
  EXPECT_EQ(again.gait.trot.swing_profile, SwingProfile::GroundSpeed);
  EXPECT_EQ(again.gait.trot.ground_speed_share, 0.25);
}

TEST(Scene, TrotStartRampParsesAndResolves) {
  SceneFixture f;
  EXPECT_EQ(f.parse(f.scene).resolved.at("controller").at("gait").at("start_ramp"), 0.0);
  json s = f.scene;
  applyOverride(s, "controller.gait.start_ramp=0.5", f.scene_path);
  const SceneConfig c = f.parse(s);
  EXPECT_EQ(c.gait.trot.start_ramp, 0.5);
  EXPECT_EQ(c.resolved.at("controller").at("gait").at("start_ramp"), 0.5);
  EXPECT_EQ(f.parse(c.resolved).gait.trot.start_ramp, 0.5);
  // The robot starts in its standing pose, and so do the ramped targets.
  const Model model = f.model(c);
  PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  gaitFor(c, model)->evaluate(0.0, target);
  const Eigen::VectorXd q0 = initialConfiguration(c, model);
  for (int i = 0; i < model.nq; ++i) {
    if (!model.bodies[i].is_base) {
      EXPECT_NEAR(target.position[i], q0[i], 1e-12) << model.bodies[i].name;
    }
  }
  EXPECT_LT(target.velocity.norm(), 1e-12);
}

TEST(Scene, OverridesNumbersBoolsStringsNewKeysArrays) {
  SceneFixture f;
  f.dir.write("sand.h5", "");  // only its existence is checked here
  json s = f.scene;
  applyOverride(s, "integrator.dt=0.01", f.scene_path);
  applyOverride(s, "integrator.adaptive=false", f.scene_path);
  applyOverride(s, "integrator.method=ne-zopgm", f.scene_path);
  applyOverride(s, "integrator.eta_limited=1.5", f.scene_path);
  applyOverride(s, "controller.gait.type=jump", f.scene_path);
  applyOverride(s, "contacts.model.type=rbf", f.scene_path);
  applyOverride(s, "contacts.model.file=sand.h5", f.scene_path);
  applyOverride(s, "robot.initial.base_rpy=[0, 0.1, 0]", f.scene_path);
  applyOverride(s, "output.every=5", f.scene_path);  // a new object
  applyOverride(s, "controller.kp={\"FL_knee_joint\": 50}", f.scene_path);
  applyOverride(s, "robot.locked_joints.FL_hip_joint=0.1", f.scene_path);
  EXPECT_EQ(s.at("integrator").at("dt"), 0.01);
  EXPECT_EQ(s.at("integrator").at("adaptive"), false);
  EXPECT_EQ(s.at("integrator").at("method"), "ne-zopgm");
  EXPECT_EQ(s.at("output").at("every"), 5);
  EXPECT_EQ(s.at("robot").at("initial").at("base_rpy"), json::array({0, 0.1, 0}));

  const SceneConfig c = f.parse(s);
  EXPECT_EQ(c.dt, 0.01);
  EXPECT_FALSE(c.integrator.adaptive);
  EXPECT_EQ(c.integrator.method, Method::NeZopgm);
  EXPECT_EQ(c.integrator.eta_limited, 1.5);
  EXPECT_EQ(c.gait_type, SceneGaitType::Jump);
  EXPECT_EQ(c.contact_model.at("type"), "rbf");
  EXPECT_EQ(c.contact_model.at("file"), (f.dir.path() / "sand.h5").string());  // relative to the scene
  EXPECT_DOUBLE_EQ(c.initial_rpy.y(), 0.1);
  EXPECT_EQ(c.output_every, 5);
  EXPECT_EQ(c.kp.joints.at("FL_knee_joint"), 50.0);
  EXPECT_EQ(c.locked_joints.at("FL_hip_joint"), 0.1);

  json quoted = f.scene;
  applyOverride(quoted, "controller.gait.type=\"stand\"", f.scene_path);
  EXPECT_EQ(quoted.at("controller").at("gait").at("type"), "stand");
}

TEST(Scene, MalformedOverridesAreErrors) {
  SceneFixture f;
  json s = f.scene;
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { applyOverride(s, "integrator.dt", f.scene_path); }),
                          {"--set integrator.dt", "key.path=value"}));
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { applyOverride(s, "=3", f.scene_path); }), {"--set =3", "empty key"}));
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { applyOverride(s, "integrator..dt=3", f.scene_path); }), {"empty key"}));
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { applyOverride(s, "duration.x=3", f.scene_path); }),
                          {"'duration'", "not an object"}));
}

// ---- bad input: one message per case ---------------------------------------------------------------

struct BadScene {
  std::string name;
  std::function<void(json&)> edit;
  std::vector<std::string> expect;  // substrings of the one message
};

TEST(Scene, EveryBadInputHasAnActionableMessage) {
  SceneFixture f;
  f.dir.write("k.csv", "time,FL_knee_joint\n0,-1.2\n");
  const std::vector<BadScene> cases = {
      {"unknown top-level key", [](json& s) { s["durration"] = 3; }, {"scene.json: durration: unknown key", "did you mean 'duration'"}},
      {"unknown nested key", [](json& s) { s["integrator"]["dtt"] = 0.1; }, {"integrator.dtt: unknown key", "did you mean 'dt'"}},
      {"unknown deep key", [](json& s) { s["robot"]["initial"]["hieght"] = 0.3; }, {"robot.initial.hieght", "did you mean 'height'"}},
      {"wrong type", [](json& s) { s["integrator"]["dt"] = "fast"; }, {"integrator.dt: expected a number", "\"fast\""}},
      {"wrong type bool", [](json& s) { s["integrator"]["adaptive"] = "yes"; }, {"integrator.adaptive: expected true or false"}},
      {"wrong type integer", [](json& s) { s["output"]["every"] = 1.5; }, {"output.every: expected an integer"}},
      {"negative dt", [](json& s) { s["integrator"]["dt"] = -1; }, {"scene.json: integrator.dt: must be in [1e-06, 1], got -1"}},
      {"too large dt", [](json& s) { s["integrator"]["dt"] = 2; }, {"integrator.dt: must be in [1e-06, 1], got 2"}},
      {"duration zero", [](json& s) { s["duration"] = 0; }, {"duration: must be > 0, got 0"}},
      {"duty factor", [](json& s) { s["controller"]["gait"]["duty_factor"] = 1; }, {"controller.gait.duty_factor: must be in (0, 1)"}},
      {"swing profile", [](json& s) { s["controller"]["gait"]["swing_profile"] = "ground"; },
       {"controller.gait.swing_profile: unknown swing profile 'ground'", "valid: cosine, ground_speed"}},
      {"ground speed share", [](json& s) { s["controller"]["gait"]["ground_speed_share"] = 1; },
       {"controller.gait.ground_speed_share: must be in [0, 1)"}},
      {"start ramp", [](json& s) { s["controller"]["gait"]["start_ramp"] = -0.5; },
       {"controller.gait.start_ramp: must be in [0, 10000], got -0.5"}},
      {"missing urdf key", [](json& s) { s["robot"].erase("urdf"); }, {"scene.json: robot: missing required key 'urdf'"}},
      {"missing robot", [](json& s) { s.erase("robot"); }, {"missing required key 'robot'"}},
      {"missing urdf file", [](json& s) { s["robot"]["urdf"] = "robots/nope.urdf"; }, {"robot.urdf: file not found", "robots/nope.urdf"}},
      {"unknown method", [](json& s) { s["integrator"]["method"] = "ne-pgn"; },
       {"integrator.method: unknown method 'ne-pgn'", "ne-pgm, ne-zopgm, pbd-pgm, pbd-zopgm, ne-mdp"}},
      {"unknown base", [](json& s) { s["robot"]["base"] = "floting"; }, {"robot.base", "did you mean 'floating'"}},
      {"unknown gait type", [](json& s) { s["controller"]["gait"]["type"] = "gallop"; },
       {"controller.gait.type: unknown gait type 'gallop'", "stand, trot, jump, keyframes"}},
      {"gait key invalid for the type", [](json& s) { s["controller"]["gait"] = {{"type", "jump"}, {"stride_length", 0.1}}; },
       {"controller.gait.stride_length: not a parameter of gait type 'jump'", "crouch_depth, push_off_height, period, pause"}},
      {"missing keyframe file", [](json& s) { s["controller"]["gait"] = {{"type", "keyframes"}, {"file", "walk.csv"}}; },
       {"controller.gait.file: file not found", "walk.csv"}},
      {"keyframes without file", [](json& s) { s["controller"]["gait"] = {{"type", "keyframes"}}; }, {"controller.gait: missing required key 'file'"}},
      {"bad contact points", [](json& s) { s["contacts"]["points"] = "all"; }, {"contacts.points: expected \"auto\" or a list"}},
      {"contact point without link", [](json& s) { s["contacts"]["points"] = json::parse(R"([{"radius": 0.02}])"); },
       {"contacts.points.0: missing required key 'link'"}},
      {"contact model not an object", [](json& s) { s["contacts"]["model"] = "coulomb"; }, {"contacts.model: expected a JSON object"}},
      {"contact model without type", [](json& s) { s["contacts"]["model"] = {{"mu", 0.5}}; }, {"contacts.model: missing required key 'type'"}},
      {"missing contact model file", [](json& s) { s["contacts"]["model"] = {{"type", "rbf"}, {"file", "models/sand.h5"}}; },
       {"contacts.model.file: file not found", "models/sand.h5"}},
      {"terrain key", [](json& s) { s["terrain"]["ofset"] = 0.1; }, {"terrain", "ofset", "offset"}},
      {"missing terrain file", [](json& s) { s["terrain"] = {{"type", "heightfield"}, {"file", "nope.csv"}, {"spacing", 0.1}}; },
       {"terrain.file: file not found", "nope.csv"}},
      {"negative kp", [](json& s) { s["controller"]["kp"] = -3; }, {"controller.kp: must be in [0, 1000000000], got -3"}},
      {"kp of wrong type", [](json& s) { s["controller"]["kp"] = "stiff"; }, {"controller.kp: expected a number (every actuated joint) or an object"}},
      {"base position size", [](json& s) { s["robot"]["initial"]["base_position"] = {1}; }, {"robot.initial.base_position: expected [x, y] or [x, y, z]"}},
      {"fixed base with a pose", [](json& s) { s["robot"]["base"] = "fixed"; s["robot"]["initial"]["height"] = 0.3; },
       {"robot.initial.height: a fixed base has no base pose"}},
      {"planar base with roll", [](json& s) { s["robot"]["base"] = "planar"; s["robot"]["initial"]["base_rpy"] = {0.1, 0, 0}; },
       {"robot.initial.base_rpy: a planar base only pitches"}},
      {"penalty relaxation of 1", [](json& s) { s["integrator"]["eta_limited"] = 1; }, {"integrator.eta_limited: must be", "got 1"}},
      {"min substep above dt", [](json& s) { s["integrator"]["min_substep"] = 0.1; }, {"integrator.min_substep: must be in (0, 0.05], got 0.1"}},
      {"keyframe period without cyclic", [](json& s) { s["controller"]["gait"] = {{"type", "keyframes"}, {"file", "k.csv"}, {"period", 2}}; },
       {"controller.gait.period: only used with \"cyclic\": true"}},
  };
  for (const BadScene& bad : cases) {
    json s = f.scene;
    bad.edit(s);
    const std::string message = inputErrorMessage([&] { f.parse(s); });
    EXPECT_TRUE(containsAll(message, bad.expect)) << bad.name << ": " << message;
  }
}

// integrator.order: 1 (default) or 2, resolved into the dump; anything else, and ne-mdp at order 2,
// is one message naming the file and the key.
TEST(Scene, IntegratorOrderParsesResolvesAndRefusesBadValues) {
  SceneFixture f;
  EXPECT_EQ(f.parse().integrator.order, 1);
  EXPECT_EQ(f.parse().resolved.at("integrator").at("order"), 1);
  json s = f.scene;
  s["integrator"]["order"] = 2;
  const SceneConfig c = f.parse(s);
  EXPECT_EQ(c.integrator.order, 2);
  EXPECT_EQ(c.resolved.at("integrator").at("order"), 2);
  EXPECT_EQ(f.parse(c.resolved).integrator.order, 2);  // the dump parses back
  for (const json& bad : {json(3), json(0), json(1.5), json("2"), json(nullptr)}) {
    s["integrator"]["order"] = bad;
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { f.parse(s); }),
                            {"scene.json: integrator.order: expected 1 (backward Euler, the paper's) or 2 (BDF2), got"}))
        << bad.dump();
  }
  s["integrator"]["order"] = 2;
  s["integrator"]["method"] = "ne-mdp";
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { f.parse(s); }), {"integrator.order: ne-mdp is first order only"}));
}

TEST(Scene, LoadErrorsNameTheFileAndPosition) {
  TempDir dir;
  const std::string bad = dir.write("bad.json", "{\n  \"robot\": {\"urdf\": \"x.urdf\",}\n}\n");
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { loadSceneJson(bad); }), {bad + ":2:", "invalid JSON"}));
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { loadSceneJson(dir.file("missing.json")); }),
                          {"missing.json", "cannot read the scene file: no such file"}));
  const std::string list = dir.write("list.json", "[1, 2]");
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { loadSceneJson(list); }), {"list.json", "expected a JSON object"}));
}

// ---- checks against the model ----------------------------------------------------------------------

TEST(Scene, ModelChecksSuggestClosestNames) {
  SceneFixture f;
  {
    json s = f.scene;
    s["contacts"]["points"] = json::parse(R"([{"link": "FL_fot", "radius": 0.02}])");
    const SceneConfig c = f.parse(s);
    const Model model = f.model(c);
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { validateAgainstModel(c, model); }),
                            {"contacts.points.0.link", "no link 'FL_fot'", "did you mean 'FL_foot'"}));
  }
  {
    json s = f.scene;
    s["controller"]["kp"] = {{"FL_kne_joint", 10}};
    const SceneConfig c = f.parse(s);
    const Model model = f.model(c);
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { validateAgainstModel(c, model); }),
                            {"controller.kp.FL_kne_joint", "no actuated joint", "did you mean 'FL_knee_joint'"}));
  }
  {
    json s = f.scene;
    s["robot"]["locked_joints"] = {{"FL_hip_joint", 0.0}};
    s["robot"]["initial"]["joints"] = {{"FL_hip_joint", 0.1}};
    const SceneConfig c = f.parse(s);
    const Model model = f.model(c);
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { validateAgainstModel(c, model); }),
                            {"robot.initial.joints.FL_hip_joint", "is locked"}));
  }
  {
    const SceneConfig c = f.parse();
    EXPECT_NO_THROW(validateAgainstModel(c, f.model(c)));
  }
}

// ---- paths -------------------------------------------------------------------------------------------

// ---- the schema ----------------------------------------------------------------------------------

// Puts an unknown key into the section of `scene` the schema names (creating what it needs).
void addUnknownKey(json& scene, const std::string& section) {
  const json marker = 1;
  if (section.empty()) scene["zz_unknown"] = marker;
  else if (section == "robot") scene["robot"]["zz_unknown"] = marker;
  else if (section == "robot.initial") scene["robot"]["initial"]["zz_unknown"] = marker;
  else if (section == "robot.initial.velocity") scene["robot"]["initial"]["velocity"]["zz_unknown"] = marker;
  else if (section == "contacts") scene["contacts"]["zz_unknown"] = marker;
  else if (section == "contacts.points[]") scene["contacts"]["points"] = json::array({{{"link", "trunk"}, {"zz_unknown", 1}}});
  else if (section == "integrator") scene["integrator"]["zz_unknown"] = marker;
  else if (section == "controller") scene["controller"]["zz_unknown"] = marker;
  else if (section == "output") scene["output"]["zz_unknown"] = marker;
  else if (section.rfind("controller.gait:", 0) == 0)
    scene["controller"]["gait"] = {{"type", section.substr(16)}, {"zz_unknown", 1}};
  else ADD_FAILURE() << "no place for section " << section;
}

// The parser's key lists are the schema's: an unknown key in each section lists as valid exactly the
// keys `nmdp simulate --schema` prints for it, in its order.
TEST(SceneSchema, TheParserAcceptsExactlyTheSchemasKeys) {
  SceneFixture f;
  const nlohmann::ordered_json schema = sceneSchema();
  ASSERT_EQ(schema.size(), sceneSections().size());
  for (auto it = schema.begin(); it != schema.end(); ++it) {
    std::vector<std::string> keys;
    for (const auto& row : it.value()) keys.push_back(row.at("key"));
    EXPECT_EQ(keys, sceneSectionKeys(it.key())) << it.key();
    json scene = f.scene;
    addUnknownKey(scene, it.key());
    std::string listed;
    for (const std::string& k : keys) listed += (listed.empty() ? "" : ", ") + k;
    const std::string message = inputErrorMessage([&] { f.parse(scene); });
    EXPECT_TRUE(containsAll(message, {"zz_unknown", ": " + listed})) << it.key() << ": " << message;
    EXPECT_EQ(message.substr(message.size() - listed.size()), listed) << it.key() << ": " << message;
  }
  const std::string text = sceneSchemaText();
  EXPECT_TRUE(containsAll(text, {"integrator\n", "  epsilon: number = 1e-06  in (0, 1]  [J]", "  method: string = \"ne-pgm\"",
                                 "  dt: number = 0.05  in [1e-06, 1]  [s]", "controller.gait:trot\n"}))
      << text;
}

// The resolved scene of a default scene parses back to the same scene, with and without the robot's
// defaults filled in.
TEST(SceneSchema, TheDumpOfADefaultSceneParsesBackToTheSameConfig) {
  SceneFixture f;
  const json minimal = {{"robot", {{"urdf", "robots/my_quadruped.urdf"}}}};
  const SceneConfig c = f.parse(minimal);
  const SceneConfig again = f.parse(c.resolved);
  EXPECT_EQ(again.resolved, c.resolved);
  EXPECT_EQ(again.dt, c.dt);
  EXPECT_EQ(again.integrator.epsilon, IntegratorOptions().epsilon);
  const Model model = f.model(c);
  const json with_model = resolvedWithModel(c, model);
  EXPECT_EQ(resolvedWithModel(f.parse(with_model), model), with_model);
}

TEST(Scene, PathsAreRelativeToTheSceneFile) {
  SceneFixture f;
  const std::string csv = f.dir.write("terrain/hills.csv", "0,0,0\n0,0.01,0\n0,0,0\n");
  f.dir.write("gaits/pose.csv", "time,FL_knee_joint\n0,-1.2\n1,-1.4\n");
  json s = f.scene;
  s["terrain"] = {{"type", "heightfield"}, {"file", "terrain/hills.csv"}, {"spacing", 0.5}};
  s["controller"]["gait"] = {{"type", "keyframes"}, {"file", "gaits/pose.csv"}};
  s["output"] = {{"file", "out/run.h5"}};
  // Parsed from another working directory's point of view: only the scene's folder matters.
  const SceneConfig c = f.parse(s);
  EXPECT_EQ(c.urdf, f.urdf());
  EXPECT_EQ(c.terrain.at("file"), csv);
  EXPECT_EQ(c.keyframe_file, (f.dir.path() / "gaits" / "pose.csv").string());
  EXPECT_EQ(c.output_file, (f.dir.path() / "out" / "run.h5").string());
  EXPECT_EQ(c.resolved.at("terrain").at("file"), csv);
  EXPECT_EQ(c.resolved.at("controller").at("gait").at("file"), c.keyframe_file);
  EXPECT_EQ(c.resolved.at("output").at("file"), c.output_file);
  EXPECT_EQ(c.resolved.at("robot").at("urdf"), f.urdf());
}

// ---- builders ----------------------------------------------------------------------------------------

TEST(Scene, AutoContactsAreTheFourFeet) {
  SceneFixture f;
  const SceneConfig c = f.parse();
  const Model model = f.model(c);
  const std::vector<ContactPoint> points = contactPointsFor(c, model);
  ASSERT_EQ(points.size(), 4u);
  std::vector<std::string> names;
  for (const ContactPoint& p : points) {
    names.push_back(p.name);
    EXPECT_EQ(model.links[p.link].name, p.name);
    EXPECT_GT(p.radius, 0.0);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"FL_foot", "FR_foot", "RL_foot", "RR_foot"}));

  json s = f.scene;
  s["contacts"]["points"] = json::parse(R"([{"link": "FL_calf", "offset": [0, 0, -0.2], "radius": 0.01},
                                            {"link": "FL_calf"}])");
  const SceneConfig listed = f.parse(s);
  const std::vector<ContactPoint> two = contactPointsFor(listed, model);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].name, "FL_calf");
  EXPECT_EQ(two[1].name, "FL_calf#2");
  EXPECT_EQ(two[0].link, model.linkIndex("FL_calf"));
  EXPECT_TRUE(two[0].offset.isApprox(Vec3(0, 0, -0.2)));
  EXPECT_EQ(two[0].radius, 0.01);
  EXPECT_EQ(two[1].radius, 0.0);
}

// The leg axis the planar granular models read their angle off points up the leg. The quadruped
// stands with straight legs at q = 0: every leg axis is then the world's +z, whether the sphere
// sits at a foot link's origin (auto: toward the knee), below the knee on the shank (toward its
// origin) or at the shank's origin itself (toward the hip).
TEST(Scene, LegAxesPointUpTheLeg) {
  SceneFixture f;
  json s = f.scene;
  s["contacts"]["points"] = json::parse(R"([{"link": "FL_calf", "offset": [0, 0, -0.2], "radius": 0.01},
                                            {"link": "FL_calf"},
                                            {"link": "FL_calf", "leg_axis": [2, 0, 0]}])");
  const SceneConfig listed = f.parse(s);
  const Model model = f.model(listed);
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(model.nq));
  const auto worldAxis = [&](const ContactPoint& p) {
    Mat3 R;
    Vec3 x;
    linkPose(model, data, p.link, R, x);
    return Vec3(R * p.leg_axis);
  };
  for (const ContactPoint& p : contactPointsFor(f.parse(), model))
    EXPECT_LT((worldAxis(p) - Vec3::UnitZ()).norm(), 1e-9) << p.name << ": " << worldAxis(p).transpose();
  const std::vector<ContactPoint> three = contactPointsFor(listed, model);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_LT((worldAxis(three[0]) - Vec3::UnitZ()).norm(), 1e-9) << worldAxis(three[0]).transpose();
  EXPECT_LT((worldAxis(three[1]) - Vec3::UnitZ()).norm(), 1e-9) << worldAxis(three[1]).transpose();
  // Given: normalized, kept and echoed.
  EXPECT_TRUE(three[2].leg_axis.isApprox(Vec3::UnitX()));
  EXPECT_EQ(listed.resolved.at("contacts").at("points").at(2).at("leg_axis"), json::parse("[1.0, 0.0, 0.0]"));
  EXPECT_FALSE(listed.resolved.at("contacts").at("points").at(0).contains("leg_axis"));
  s["contacts"]["points"] = json::parse(R"([{"link": "FL_calf", "leg_axis": [0, 0, 0]}])");
  EXPECT_TRUE(containsAll(inputErrorMessage([&] { f.parse(s); }), {"contacts.points.0.leg_axis", "non-zero"}));
}

// RoboSimian's foot sphere sits 0.1 m along the x axis of link7 (the foot's roll joint turns about
// x): its leg axis is −x, and in the paper's standing pose every foot's angle feature is ~0, the
// middle of the published sand model's range (−0.9..0.9). With the link's z axis, as before, it was
// ±π/2, far outside it.
TEST(Scene, RoboSimianLegAxisIsAlongTheFoot) {
  NMDP_REQUIRE_SHARED("robots/robosimian");
  const std::string path = sourcePath("models/scenes/robosimian_walk_planar.json");
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  const SceneConfig c = parseScene(json::parse(in), path);
  const Model model = loadUrdf(c.urdf, urdfOptionsFor(c));
  Data data(model);
  forwardKinematics(model, data, initialConfiguration(c, model));
  const std::vector<ContactPoint> feet = contactPointsFor(c, model);
  ASSERT_EQ(feet.size(), 4u);
  for (const ContactPoint& p : feet) {
    // (The sphere found from the foot's mesh is centred 2.3 µm off the link's x axis: 2.3e-5 rad.)
    EXPECT_LT((p.leg_axis + Vec3::UnitX()).norm(), 1e-4) << p.name << ": " << p.leg_axis.transpose();
    ContactFrame frame;
    contactFrame(model, data, p, frame);
    const double beta = std::atan2(frame.leg_axis.x(), frame.leg_axis.z());
    EXPECT_LT(std::abs(beta), 0.05) << p.name;
    EXPECT_NEAR(frame.leg_axis.z(), 1.0, 1e-3) << p.name;  // up
  }
}

TEST(Scene, GainsDefaultToDefaultPdGainsAndOverride) {
  SceneFixture f;
  const SceneConfig c = f.parse();
  const Model model = f.model(c);
  // The default gains are evaluated at the pose the robot starts in.
  const PdGains g = gainsFor(c, model), ref = defaultPdGains(model, initialConfiguration(c, model));
  EXPECT_NE(g.kp, defaultPdGains(model, Eigen::VectorXd::Zero(model.nq)).kp);
  EXPECT_EQ(g.kp, ref.kp);
  EXPECT_EQ(g.kd, ref.kd);
  EXPECT_EQ(g.tau_ff, ref.tau_ff);

  json s = f.scene;
  s["controller"]["kp"] = 80;
  s["controller"]["kd"] = {{"FL_knee_joint", 2.5}};
  s["controller"]["tau_ff"] = {{"RR_hip_joint", -1.0}};
  const SceneConfig o = f.parse(s);
  const PdGains h = gainsFor(o, model);
  for (int i = 0; i < model.nq; ++i) {
    EXPECT_EQ(h.kp[i], model.bodies[i].is_base ? 0.0 : 80.0) << model.dof_names[i];
    const double kd = model.dof_names[i] == "FL_knee_joint" ? 2.5 : ref.kd[i];
    EXPECT_EQ(h.kd[i], kd) << model.dof_names[i];
  }
  EXPECT_EQ(h.tau_ff[model.dofIndex("RR_hip_joint")], -1.0);
  EXPECT_NO_THROW(validatePdGains(model, h));
}

// Lowest point of the contact spheres in the world at q.
double lowestFootBottom(const Model& model, const std::vector<ContactPoint>& contacts, const Eigen::VectorXd& q) {
  Data data(model);
  forwardKinematics(model, data, q);
  double lowest = 1e300;
  for (const ContactPoint& p : contacts) lowest = std::min(lowest, linkPoint(model, data, p.link, p.offset).z() - p.radius);
  return lowest;
}

TEST(Scene, InitialConfigurationStandsOnTheGround) {
  SceneFixture f;
  const SceneConfig c = f.parse();
  const Model model = f.model(c);
  const Eigen::VectorXd q = initialConfiguration(c, model);
  ASSERT_EQ(q.size(), model.nq);
  EXPECT_NEAR(lowestFootBottom(model, contactPointsFor(c, model), q), 0.0, 1e-9);

  // The joints are the gait's standing pose, and the height its standing height.
  PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  json stand_scene = f.scene;
  stand_scene["controller"]["gait"] = {{"type", "stand"}};
  const SceneConfig stand = f.parse(stand_scene);
  gaitFor(stand, model)->evaluate(0.0, target);
  EXPECT_LT((target.position - q).cwiseAbs().maxCoeff(), 1e-9);

  // Every foot touches (all four on flat ground), and the trunk is level at the origin.
  Data data(model);
  forwardKinematics(model, data, q);
  for (const ContactPoint& p : contactPointsFor(c, model))
    EXPECT_NEAR(linkPoint(model, data, p.link, p.offset).z() - p.radius, 0.0, 1e-9) << p.name;

  // A raised plane lifts the robot with it; an explicit height wins; a tilted start still touches.
  json s = f.scene;
  s["terrain"] = {{"type", "plane"}, {"offset", 0.1}};
  s["robot"]["initial"] = {{"base_rpy", {0.05, -0.1, 0.3}}, {"base_position", {0.2, -0.1}}};
  const SceneConfig raised = f.parse(s);
  const Eigen::VectorXd qr = initialConfiguration(raised, model);
  EXPECT_NEAR(lowestFootBottom(model, contactPointsFor(raised, model), qr), 0.1, 1e-9);
  forwardKinematics(model, data, qr);
  Vec3 position, rpy;
  basePose(model, data, position, rpy);
  EXPECT_LT((rpy - Vec3(0.05, -0.1, 0.3)).norm(), 1e-12);
  EXPECT_NEAR(position.x(), 0.2, 1e-12);
  EXPECT_NEAR(position.y(), -0.1, 1e-12);

  // An explicit height wins. robot.initial.joints is the gait's nominal pose (unlisted joints as in
  // the default standing pose): the start is the standing pose solved from it, with the front left
  // foot where the nominal pose puts it horizontally and all four feet level with the lowest.
  json h = f.scene;
  h["robot"]["initial"] = {{"base_position", {0, 0, 0.6}}, {"joints", {{"FL_knee_joint", -1.0}}}};
  const SceneConfig high = f.parse(h);
  const Eigen::VectorXd qh = initialConfiguration(high, model);
  forwardKinematics(model, data, qh);
  basePose(model, data, position, rpy);
  EXPECT_NEAR(position.z(), 0.6, 1e-12);
  Eigen::VectorXd nominal = q;
  nominal[model.dofIndex("FL_knee_joint")] = -1.0;
  Data nominal_data(model);
  forwardKinematics(model, nominal_data, nominal);
  const std::vector<ContactPoint> feet = contactPointsFor(high, model);
  const Vec3 trunk = linkPoint(model, data, model.root_link, Vec3::Zero());
  const Vec3 nominal_trunk = linkPoint(model, nominal_data, model.root_link, Vec3::Zero());
  double nominal_mean_depth = 0;
  for (const ContactPoint& p : feet) {
    const Vec3 foot = linkPoint(model, data, p.link, p.offset) - trunk;
    const Vec3 nominal_foot = linkPoint(model, nominal_data, p.link, p.offset) - nominal_trunk;
    EXPECT_NEAR(foot.x(), nominal_foot.x(), 1e-9) << p.name;
    EXPECT_NEAR(foot.y(), nominal_foot.y(), 1e-9) << p.name;
    nominal_mean_depth += nominal_foot.z() / feet.size();
  }
  for (const ContactPoint& p : feet)
    EXPECT_NEAR(linkPoint(model, data, p.link, p.offset).z() - trunk.z(), nominal_mean_depth, 1e-9) << p.name;
  EXPECT_GT(std::abs(qh[model.dofIndex("FL_knee_joint")] + 1.0), 1e-3) << "the knee was solved for, not copied";
}

TEST(Scene, InitialVelocityIsTheWorldBaseTwist) {
  SceneFixture f;
  json s = f.scene;
  s["robot"]["initial"] = {{"base_rpy", {0.2, -0.3, 0.5}},
                           {"velocity", {{"base_linear", {0.5, -0.2, 0.1}}, {"base_angular", {0.3, -0.4, 0.7}}}}};
  const SceneConfig c = f.parse(s);
  const Model model = f.model(c);
  const Eigen::VectorXd q = initialConfiguration(c, model), qd = initialVelocity(c, model);
  // Finite difference of the root link pose along q̇.
  const double eps = 1e-7;
  Data d0(model), d1(model);
  forwardKinematics(model, d0, q - eps * qd);
  forwardKinematics(model, d1, q + eps * qd);
  Mat3 R0, R1;
  Vec3 p0, p1;
  linkPose(model, d0, model.root_link, R0, p0);
  linkPose(model, d1, model.root_link, R1, p1);
  const Vec3 v = (p1 - p0) / (2 * eps);
  const Mat3 W = (R1 - R0) / (2 * eps) * (0.5 * (R0 + R1)).transpose();
  const Vec3 w(W(2, 1), W(0, 2), W(1, 0));
  EXPECT_LT((v - Vec3(0.5, -0.2, 0.1)).norm(), 1e-6);
  EXPECT_LT((w - Vec3(0.3, -0.4, 0.7)).norm(), 1e-6);
}

TEST(Scene, BuiltInGaitsBuild) {
  SceneFixture f;
  for (const char* type : {"stand", "trot", "jump"}) {
    json s = f.scene;
    s["controller"]["gait"] = {{"type", type}};
    const SceneConfig c = f.parse(s);
    const Model model = f.model(c);
    PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
    std::unique_ptr<PdTargetSource> gait = gaitFor(c, model);
    ASSERT_TRUE(gait) << type;
    gait->evaluate(0.3, target);
    EXPECT_TRUE(target.position.allFinite()) << type;
  }
}

TEST(Scene, KeyframeFilesCsvAndJson) {
  SceneFixture f;
  f.dir.write("walk.csv", "time, FL_knee_joint, RR_hip_joint\n0, -1.2, 0.0\n0.5, -1.5, 0.1\n1.0, -1.2, 0.0\n");
  f.dir.write("walk.json", R"({"times": [0, 0.5, 1.0], "joints": {"FL_knee_joint": [-1.2, -1.5, -1.2], "RR_hip_joint": [0, 0.1, 0]}})");
  json base = f.scene;
  Model model = f.model(f.parse());
  json stand_scene = f.scene;
  stand_scene["controller"]["gait"] = {{"type", "stand"}};
  PdTarget standing{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
  gaitFor(f.parse(stand_scene), model)->evaluate(0.0, standing);

  const int knee = model.dofIndex("FL_knee_joint"), hip = model.dofIndex("RR_hip_joint"), other = model.dofIndex("FR_knee_joint");
  for (const char* file : {"walk.csv", "walk.json"}) {
    for (bool cyclic : {false, true}) {
      json s = f.scene;
      s["controller"]["gait"] = {{"type", "keyframes"}, {"file", file}, {"cyclic", cyclic}};
      const SceneConfig c = f.parse(s);
      EXPECT_NO_THROW(validateAgainstModel(c, model));
      std::unique_ptr<PdTargetSource> gait = gaitFor(c, model);
      PdTarget t{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
      gait->evaluate(0.5, t);
      EXPECT_NEAR(t.position[knee], -1.5, 1e-12) << file;
      EXPECT_NEAR(t.position[hip], 0.1, 1e-12) << file;
      EXPECT_NEAR(t.position[other], standing.position[other], 1e-12) << file;  // unlisted: standing pose
      gait->evaluate(1.5, t);  // cyclic: half a period in again; holding: the last keyframe
      EXPECT_NEAR(t.position[knee], cyclic ? -1.5 : -1.2, 1e-12) << file;
      // The start pose is the first keyframe, on the ground.
      const Eigen::VectorXd q = initialConfiguration(c, model);
      EXPECT_EQ(q[knee], -1.2);
      EXPECT_NEAR(lowestFootBottom(model, contactPointsFor(c, model), q), 0.0, 1e-9);
    }
  }

  f.dir.write("typo.csv", "time,FL_kne_joint\n0,-1.2\n");
  f.dir.write("bad.csv", "time,FL_knee_joint\n0,-1.2\n1,abc\n");
  f.dir.write("open.csv", "time,FL_knee_joint\n0,-1.2\n1,-1.4\n2,-1.3\n");
  struct Case {
    std::string file;
    bool cyclic;
    std::vector<std::string> expect;
  };
  for (const Case& k : std::vector<Case>{
           {"typo.csv", false, {"controller.gait.file", "typo.csv", "no actuated joint 'FL_kne_joint'", "did you mean 'FL_knee_joint'"}},
           {"bad.csv", false, {"controller.gait.file", "bad.csv", "line 3, column 2", "'abc' is not a number"}},
           {"open.csv", true, {"controller.gait.file", "the last keyframe must repeat the first"}}}) {
    json s = f.scene;
    s["controller"]["gait"] = {{"type", "keyframes"}, {"file", k.file}, {"cyclic", k.cyclic}};
    const SceneConfig c = f.parse(s);
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { gaitFor(c, model); }), k.expect)) << k.file;
  }
}

TEST(Scene, UrdfOptionsFollowTheScene) {
  SceneFixture f;
  json s = f.scene;
  s["robot"]["base"] = "planar";
  s["robot"]["locked_joints"] = {{"FL_hip_joint", 0.0}};
  s["robot"]["armature"] = 0.01;
  const SceneConfig c = f.parse(s);
  const UrdfOptions o = urdfOptionsFor(c);
  EXPECT_EQ(o.base, BaseType::Planar);
  EXPECT_EQ(o.locked_joints.at("FL_hip_joint"), 0.0);
  EXPECT_EQ(o.default_armature, 0.01);
  const Model model = f.model(c);
  EXPECT_EQ(model.dofIndex("FL_hip_joint"), -1);
  const Eigen::VectorXd q = initialConfiguration(c, model);
  EXPECT_NEAR(lowestFootBottom(model, contactPointsFor(c, model), q), 0.0, 1e-9);
}

// ---- RoboSimian (../shared): standing from the bent pose of robot.initial.joints --------------------

// The RoboSimian scenes of models/scenes, read in place: their limbs stretch out level at q = 0,
// so the gaits stand from robot.initial.joints, and every foot starts on the ground.
TEST(Scene, RoboSimianStandsFromTheBentPoseOfInitialJoints) {
  NMDP_REQUIRE_SHARED("robots/robosimian/robosimian_caesar_new_all_active.urdf");
  for (const char* name : {"robosimian_walk_planar.json", "robosimian_jump_planar.json"}) {
    SCOPED_TRACE(name);
    const std::string path = sourcePath(std::string("models/scenes/") + name);
    const json scene = loadSceneJson(path);
    const SceneConfig c = parseScene(scene, path);
    const Model model = loadUrdf(c.urdf, urdfOptionsFor(c));
    ASSERT_EQ(model.nq, 15) << "planar base and joints 2, 4, 6 of each limb";
    ASSERT_NO_THROW(validateAgainstModel(c, model));

    // Every foot touches the ground, the trunk level and high: a table, not a robot lying flat.
    const Eigen::VectorXd q = initialConfiguration(c, model);
    const std::vector<ContactPoint> feet = contactPointsFor(c, model);
    ASSERT_EQ(feet.size(), 4u);
    Data data(model);
    forwardKinematics(model, data, q);
    for (const ContactPoint& p : feet) EXPECT_NEAR(linkPoint(model, data, p.link, p.offset).z() - p.radius, 0.0, 1e-9) << p.name;
    EXPECT_EQ(q[model.dofIndex("base_pitch")], 0.0);
    EXPECT_GT(q[model.dofIndex("base_z")], 0.5);
    // The start pose is the standing pose (the stand gait's target): the scene's bent pose, its
    // feet made level (to µm: limbs 1 and 2 are yawed 0.01 rad in the URDF).
    json stand_scene = scene;
    stand_scene["controller"]["gait"] = {{"type", "stand"}};
    PdTarget target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
    gaitFor(parseScene(stand_scene, path), model)->evaluate(0.0, target);
    for (const auto& [joint, value] : c.initial_joints) {
      const int i = model.dofIndex(joint);
      EXPECT_NEAR(target.position[i], q[i], 1e-12) << joint;
      EXPECT_NEAR(q[i], value, 1e-3) << joint;
    }

    // The resolved scene parses again to the same start, gait and resolved scene.
    const json resolved = resolvedWithModel(c, model);
    const SceneConfig again = parseScene(resolved, path);
    EXPECT_EQ(initialConfiguration(again, model), q);
    PdTarget again_target{Eigen::VectorXd::Zero(model.nq), Eigen::VectorXd::Zero(model.nq)};
    for (double t : {0.3, 0.77, 1.4}) {
      gaitFor(c, model)->evaluate(t, target);
      gaitFor(again, model)->evaluate(t, again_target);
      EXPECT_EQ(again_target.position, target.position) << "t = " << t;
    }
    EXPECT_EQ(resolvedWithModel(again, model), resolved);

    // Without the bent pose the gait cannot stand, and the message says what to give.
    json flat = scene;
    flat["robot"]["initial"].erase("joints");
    const SceneConfig without = parseScene(flat, path);
    EXPECT_TRUE(containsAll(inputErrorMessage([&] { validateAgainstModel(without, model); }),
                            {path, "controller.gait", "cannot reach", "robot.initial.joints"}));
  }
}

}  // namespace
}  // namespace nmdp::test
