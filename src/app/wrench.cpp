#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/json_argument.hpp"
#include "contact_models/foot_frame.hpp"
#include "contact_models/registry.hpp"
#include "common/input_error.hpp"
#include "terrain/terrain_factory.hpp"

namespace nmdp::app {

const char* const kWrenchHelp =
    "usage: nmdp wrench --model MODEL [--terrain TERRAIN] [--depth D] [--angle B] [--lateral-angle G]\n"
    "                   [--radius R] [--at X,Y] [--derivatives]\n\n"
    "Evaluates a contact model for one foot and prints its wrench-space vertices as JSON: V, 6×K,\n"
    "rows [torque about the sphere centre; force] in the world frame, and with --derivatives dV/dξ\n"
    "for ξ = [rotation about the sphere centre; translation].\n\n"
    "  --model MODEL      a JSON object ('{\"type\": \"coulomb\", \"mu\": 0.7}') or a .json file holding one;\n"
    "                     relative paths inside a file are relative to that file\n"
    "  --terrain TERRAIN  a JSON object or .json file (default: the plane z = 0)\n"
    "  --depth D          signed distance of the foot's lowest point to the terrain, m (default -0.02)\n"
    "  --angle B          leg tilt from the terrain normal in the x-z plane, rad (default 0)\n"
    "  --lateral-angle G  leg lean across that plane, toward y, rad (default 0): the 3-D models'\n"
    "                     lateral feature; |G| < pi/2\n"
    "  --radius R         foot sphere radius, m (default 0.02)\n"
    "  --at X,Y           horizontal position of the foot (default 0,0)\n"
    "  --derivatives      also print dV/dξ (models without a derivative refuse)\n";

namespace {
// A JSON object given inline or as a file; the context names where it came from, e.g. "foot.json:
// model" for a file, so that a key inside reads "foot.json: model.mu".
nlohmann::json readModelArgument(const std::string& option, const std::string& text, ConfigContext& ctx) {
  nlohmann::json value = readJsonArgument(option, text, ctx);
  if (ctx.where != option) ctx.where += ": " + option.substr(2);
  return value;
}

// A number of magnitude at most `most` (in the option's unit).
double parseNumber(const std::string& option, const std::string& text, double most) {
  const std::string shown = text.size() <= 40 ? text : text.substr(0, 40) + "...";
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) {
      if (std::abs(v) > most) throw InputError(option + ": '" + shown + "' is beyond " + std::to_string(most));
      return v;
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception&) {
  }
  throw InputError(option + ": '" + shown + "' is not a finite number");
}

nlohmann::json matrixJson(const Mat6X& M) {
  nlohmann::json cols = nlohmann::json::array();
  for (int j = 0; j < M.cols(); ++j) cols.push_back({M(0, j), M(1, j), M(2, j), M(3, j), M(4, j), M(5, j)});
  return cols;
}
}  // namespace

int runWrench(const Args& args) {
  nlohmann::json model_json, terrain_json = nlohmann::json::object();
  ConfigContext model_ctx, terrain_ctx{"--terrain", ""};
  bool have_model = false, derivatives = false;
  double depth = -0.02, angle = 0.0, lateral_angle = 0.0, radius = 0.02, x = 0.0, y = 0.0;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto next = [&]() -> const std::string& { return optionValue(args, i, "wrench"); };
    if (a == "--model") {
      model_json = readModelArgument(a, next(), model_ctx);
      have_model = true;
    } else if (a == "--terrain") {
      terrain_json = readModelArgument(a, next(), terrain_ctx);
    } else if (a == "--depth") {
      depth = parseNumber(a, next(), 1e3);
    } else if (a == "--angle") {
      angle = parseNumber(a, next(), 1e3);
    } else if (a == "--lateral-angle") {
      lateral_angle = parseNumber(a, next(), 1e3);
      if (!(std::abs(lateral_angle) < 0.5 * M_PI))
        throw InputError("--lateral-angle: must lie strictly between -pi/2 and pi/2 (the leg leaning sideways)");
    } else if (a == "--radius") {
      radius = parseNumber(a, next(), 10.0);
      if (radius < 0) throw InputError("--radius: must be >= 0");
    } else if (a == "--at") {
      const std::string& v = next();
      const auto comma = v.find(',');
      if (comma == std::string::npos) throw InputError("--at expects X,Y, got '" + v.substr(0, 40) + "'");
      x = parseNumber(a, v.substr(0, comma), 1e9);
      y = parseNumber(a, v.substr(comma + 1), 1e9);
    } else if (a == "--derivatives") {
      derivatives = true;
    } else {
      throw InputError("unknown argument '" + a + "' (see nmdp wrench --help)");
    }
  }
  if (!have_model) throw InputError("--model is required (see nmdp wrench --help)");

  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  const std::unique_ptr<ContactModel> model = registry.build(model_json, model_ctx);
  const std::unique_ptr<Terrain> terrain = makeTerrain(terrain_json, terrain_ctx);
  if (derivatives && model->derivative() == DerivativeSupport::None)
    throw InputError("--derivatives: this " + model->describe() + " model has no derivative (zeroth-order methods only)");

  // Place the sphere so that its lowest point is `depth` from the terrain below (x, y).
  const ContactFrame frame = footFrameAt(*terrain, x, y, depth, angle, lateral_angle, radius);

  std::vector<ContactFrame> frames{frame};
  std::vector<ContactWrenches> out(1);
  out[0].resize(model->vertexCount());
  model->evaluate(frames, *terrain, out, derivatives);

  nlohmann::ordered_json result;
  result["model"] = model->describe();
  result["derivative"] = derivativeSupportName(model->derivative());
  result["terrain"] = terrain->describe();
  result["foot"] = {{"centre", {frame.position.x(), frame.position.y(), frame.position.z()}},
                    {"radius", radius},
                    {"leg_axis", {frame.leg_axis.x(), frame.leg_axis.y(), frame.leg_axis.z()}}};
  result["vertices"] = model->vertexCount();
  result["V"] = matrixJson(out[0].V);
  if (derivatives) {
    nlohmann::json dV = nlohmann::json::array();
    for (const Mat6X& d : out[0].dV) dV.push_back(matrixJson(d));
    result["dV"] = dV;
  }
  std::cout << result.dump(1) << "\n";
  return 0;
}

}  // namespace nmdp::app
