// nmdp.Scene: Scene.load(path, overrides) is `nmdp simulate path --set key=value ...` up to the
// simulation (app/simulate.cpp's loadScene): the same file reading, the same overrides in the same
// order and the same checks, so the same messages.
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "common/json_text.hpp"
#include "py_json.hpp"
#include "py_scene.hpp"

namespace py = pybind11;

namespace nmdp::python {

namespace {

// One override as the command line would spell it: a str that is not JSON goes in as typed (so
// {"integrator.method": "ne-zopgm"} reads "--set integrator.method=ne-zopgm" in messages), any
// other value as its JSON text (a str that looks like JSON is quoted: it stays a string).
std::string assignmentText(const std::string& key, py::handle value, const std::string& scene_path) {
  if (py::isinstance<py::str>(value)) {
    const std::string text = value.cast<std::string>();
    if (!isJson(text)) return key + "=" + text;
  }
  return key + "=" + toJson(value, scene_path + ": --set " + key).dump();
}

// The overrides as "key=value" texts: a dict {key: value}, or a list of "key=value" strings as
// given to --set.
std::vector<std::string> assignments(py::handle overrides, const std::string& scene_path) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (auto [key, value] : overrides.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw std::invalid_argument("overrides: keys are scene key paths such as \"integrator.dt\", got " +
                                    py::repr(key).cast<std::string>());
      out.push_back(assignmentText(key.cast<std::string>(), value, scene_path));
    }
    return out;
  }
  if (py::isinstance<py::str>(overrides) || !py::isinstance<py::iterable>(overrides))
    throw std::invalid_argument("overrides: expected a dict {\"key.path\": value} or a list of \"key.path=value\" strings, got " +
                                py::repr(overrides).cast<std::string>());
  for (py::handle item : overrides) {
    if (!py::isinstance<py::str>(item))
      throw std::invalid_argument("overrides: expected \"key.path=value\" strings, got " + py::repr(item).cast<std::string>());
    out.push_back(item.cast<std::string>());
  }
  return out;
}

PyScene loadScene(py::handle path_argument, py::handle overrides) {
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_argument)).cast<std::string>();
  const std::vector<std::string> texts = assignments(overrides, path);
  nlohmann::json scene = loadSceneJson(path);
  for (const std::string& assignment : texts) applyOverride(scene, assignment, path + ": --set");
  return PyScene{std::make_shared<const SceneConfig>(parseScene(scene, path))};
}

const char* const kLoadDoc = R"(Loads a scene file as `nmdp simulate PATH --set key=value ...` does.

overrides: {"integrator.dt": 0.02, "integrator.method": "ne-zopgm", ...} (keys as --set; values are
Python values turned into JSON: numbers, strings, lists, dicts, True/False/None), applied in order;
or a list of "key=value" strings, exactly as given to --set. Raises ValueError with the CLI's
message for a missing or malformed file, an unknown key or a bad value. The robot (URDF) is loaded
by Simulation(scene), which reports its errors.)";

}  // namespace

void bindScene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A scene file with its overrides, checked and with every default filled in.")
      .def_static("load", &loadScene, py::arg("path"), py::arg("overrides") = py::none(), kLoadDoc)
      .def_property_readonly("path", [](const PyScene& s) { return s.config->path; }, "The scene file as given to load().")
      .def_property_readonly("dt", [](const PyScene& s) { return s.config->dt; }, "integrator.dt: one step, s.")
      .def_property_readonly("duration", [](const PyScene& s) { return s.config->duration; }, "duration, s.")
      .def("to_dict", [](const PyScene& s) { return toPython(s.config->resolved); },
           "The scene with the overrides applied, every default that needs no robot filled in and paths made\n"
           "absolute: a dict that, saved as JSON, is the same scene (Simulation.config adds the robot's defaults).")
      .def("__repr__", [](const PyScene& s) { return "nmdp.Scene.load(" + py::repr(py::str(s.config->path)).cast<std::string>() + ", ...)"; });
}

}  // namespace nmdp::python
