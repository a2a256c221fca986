// nmdp sweep SWEEP.json --out DIR [--scheduler tcp://HOST:PORT] [--workers N] [--quiet]
//
// Hands over to the Python package nmdp.sweep (Dask's distributed does the scheduling, retries and
// the cluster): replaces this process with `PYTHON -m nmdp.sweep ARGS`, the package found in the
// build's python folder beside this executable, and NMDP_BINARY naming this executable, whose
// `nmdp simulate` makes every run. PYTHON is the interpreter the package was built for (its
// _build.py), else /usr/bin/python3.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"

namespace nmdp::app {

const char* const kSweepHelp =
    "usage: nmdp sweep SWEEP.json --out DIR [--scheduler tcp://HOST:PORT] [--workers N] [--quiet]\n"
    "\n"
    "Makes every run of a sweep file, each `nmdp simulate` as one Dask task writing DIR/runs/<id>.h5\n"
    "(renamed from a temporary name when complete), then DIR/index.csv and DIR/index.h5: one row per\n"
    "run with its overrides, status, file, final base position and yaw, wall time and mean outer\n"
    "iterations. A re-run skips the runs already complete. The sweep file (docs/SWEEPS.md):\n"
    "  {\"scene\": \"scene.json\", \"base\": {\"duration\": 2},\n"
    "   \"grid\": {\"integrator.dt\": [0.01, 0.02], \"controller.kd\": [1, 3]},\n"
    "   \"runs\": [{\"integrator.method\": \"pbd-pgm\"}]}\n"
    "every grid combination plus every listed run, each over the base; keys as --set takes them;\n"
    "the scene's path is relative to the sweep file.\n"
    "\n"
    "  --out DIR                  the results folder\n"
    "  --scheduler tcp://HOST:PORT  an existing Dask cluster (dask-scheduler, dask-worker)\n"
    "  --workers N                else a LocalCluster of N worker processes (default: the cores)\n"
    "  --quiet                    no progress bar and no summary\n"
    "\n"
    "Needs the Python package nmdp (the build's python folder) and Dask's distributed\n"
    "(Debian: python3-distributed).\n"
    "Exit status: 0 every run completed; 1 bad input (nothing ran); 4 some runs failed (the index\n"
    "says why); 130 interrupted (the completed runs are kept; a re-run continues).\n";

namespace {

// The interpreter named by `PYTHON = "..."` in the package's _build.py, or "" if there is none.
std::string builtPython(const std::filesystem::path& build_py) {
  if (!pathExists(build_py.string())) return "";
  const std::string text = readInputFile(build_py.string(), "build description");
  const std::string key = "\nPYTHON = \"";
  const size_t at = text.find(key);
  if (at == std::string::npos) return "";
  const size_t start = at + key.size(), end = text.find('"', start);
  return end == std::string::npos ? "" : text.substr(start, end - start);
}

void prependEnv(const char* name, const std::string& value) {
  const char* old = std::getenv(name);
  const std::string joined = old && *old ? value + ":" + old : value;
  ::setenv(name, joined.c_str(), 1);
}

}  // namespace

int runSweep(const Args& args) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) throw InputError("cannot find this executable (/proc/self/exe): " + error.message());
  const fs::path python_dir = self.parent_path() / "python";
  if (!pathExists((python_dir / "nmdp" / "sweep" / "__main__.py").string()))
    throw InputError("the Python package nmdp.sweep is not in " + python_dir.string() +
                     " (it is built with the executable unless NMDP_BUILD_PYTHON is OFF)");
  std::string python = builtPython(python_dir / "nmdp" / "_build.py");
  if (python.empty() || ::access(python.c_str(), X_OK) != 0) python = "/usr/bin/python3";

  prependEnv("PYTHONPATH", python_dir.string());
  ::setenv("NMDP_BINARY", self.c_str(), 1);
  std::vector<std::string> words = {python, "-m", "nmdp.sweep"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(python.c_str(), argv.data());
  throw InputError("cannot run " + python + ": " + std::strerror(errno));  // execv returns only on failure
}

}  // namespace nmdp::app
