// scripts/evaluate.py, the step-size evaluation: its --help, the unit tests of its package
// (scripts/evaluation/test_*.py), that every case's scene file runs, and a smoke run of 0.2 s on the
// project's quadruped into a temporary folder. The Python parts are skipped without a python3 that
// has h5py, numpy and matplotlib, and the smoke run without nmdp's sweep package and Dask's distributed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_cli.hpp"
#include "test_temp_dir.hpp"

using nmdp::test::readText;
using nmdp::test::runNmdp;
using nmdp::test::shellQuote;
using nmdp::test::TempDir;

namespace {

const std::string kScript = std::string(NMDP_SOURCE_DIR) + "/scripts/evaluate.py";

// Debian's python3 (h5py, numpy, matplotlib), or "" if there is none.
std::string python() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (std::system((std::string(py) + " -c 'import h5py, numpy, matplotlib' >/dev/null 2>&1").c_str()) == 0) return py;
  return "";
}

// Runs `python3 ARGS` (no bytecode written into the source tree); stdout and stderr to `log`.
int runPython(const std::string& py, const std::string& args, const std::string& log) {
  const int status = std::system(("PYTHONDONTWRITEBYTECODE=1 " + py + " " + args + " >" + shellQuote(log) + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(EvaluationScript, HelpNamesTheOptions) {
  const std::string py = python();
  if (py.empty()) GTEST_SKIP() << "no python3 with h5py, numpy and matplotlib";
  TempDir dir;
  ASSERT_EQ(runPython(py, shellQuote(kScript) + " --help", dir.file("help.txt")), 0);
  const std::string help = readText(dir.file("help.txt"));
  for (const char* option : {"--duration", "--set", "--variant", "--cases", "--dts", "--report-only"})
    EXPECT_NE(help.find(option), std::string::npos) << option << " missing from --help:\n" << help;
}

TEST(EvaluationScript, PackagePassesItsUnitTests) {
  const std::string py = python();
  if (py.empty()) GTEST_SKIP() << "no python3 with h5py, numpy and matplotlib";
  TempDir dir;
  const std::string folder = std::string(NMDP_SOURCE_DIR) + "/scripts/evaluation";
  EXPECT_EQ(runPython(py, "-m unittest discover -s " + shellQuote(folder) + " -p 'test_*.py'", dir.file("log.txt")), 0)
      << readText(dir.file("log.txt"));
}

// Each case is a scene file under models/scenes/evaluation/ that `nmdp simulate` reads as it is (its
// paths relative to itself); those that read ../shared are skipped where it is absent.
TEST(EvaluationScript, EveryCaseSceneRuns) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(NMDP_SOURCE_DIR) / "models/scenes/evaluation";
  const bool shared = fs::is_directory(fs::path(NMDP_SOURCE_DIR) / "../shared");
  int ran = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".json") continue;
    if (!shared && readText(entry.path().string()).find("/shared/") != std::string::npos) continue;
    TempDir dir;
    const auto r = runNmdp({"simulate", entry.path().string(), "--set", "duration=0.1", "--out", dir.file("run.h5"), "--quiet"}, dir);
    EXPECT_TRUE(r.exited && r.exit_code == 0) << entry.path() << ": " << r.err;
    ++ran;
  }
  EXPECT_GE(ran, 2) << "the project's own cases (quadruped, flat and sand) run without ../shared";
}

TEST(EvaluationScript, SmokeRunWritesThePageWithTheSettingsPassedThrough) {
  const std::string py = python();
  if (py.empty()) GTEST_SKIP() << "no python3 with h5py, numpy and matplotlib";
  // The runs go through nmdp's sweep library (build/python/nmdp/sweep) on Dask's distributed.
  const std::filesystem::path sweep = std::filesystem::path(NMDP_BINARY).parent_path() / "python/nmdp/sweep";
  if (!std::filesystem::is_directory(sweep)) GTEST_SKIP() << sweep << " is absent (NMDP_BUILD_PYTHON=OFF)";
  if (std::system((py + " -c 'import distributed' >/dev/null 2>&1").c_str()) != 0)
    GTEST_SKIP() << "no Dask distributed for " << py << " (Debian: python3-distributed)";
  TempDir dir;
  const std::string args = shellQuote(kScript) + " --duration 0.2 --cases quadruped_trot_flat --dts 0.01,0.05 --jobs 1" +
                           " --no-variants --set integrator.max_outer_iterations=77 --nmdp " + shellQuote(NMDP_BINARY) +
                           " --out-dir " + shellQuote(dir.file("out")) + " --docs-dir " + shellQuote(dir.file("docs"));
  ASSERT_EQ(runPython(py, args, dir.file("log.txt")), 0) << readText(dir.file("log.txt"));
  const std::string page = readText(dir.file("docs/RESULTS.md"));
  EXPECT_NE(page.find("SHORT: a smoke run"), std::string::npos) << page;
  EXPECT_NE(page.find("`--set integrator.max_outer_iterations=77`"), std::string::npos) << page;
  EXPECT_NE(page.find("## Verdict"), std::string::npos) << page;
  // 2 methods × 2 dt, each row measured from its run file, which holds the setting.
  for (const char* method : {"ne-pgm", "pbd-pgm"})
    for (const char* dt : {"010", "050"}) {
      const std::string run = dir.file(std::string("out/runs/quadruped_trot_flat/default/") + method + "_dt" + dt + "ms.h5");
      EXPECT_TRUE(std::filesystem::exists(run)) << run;
      EXPECT_NE(page.find(std::string("| defaults | ") + method + " | " + (dt[1] == '1' ? "10" : "50") + " | yes |"),
                std::string::npos)
          << method << " " << dt << " ms row missing or not stable:\n" << page;
    }
  EXPECT_TRUE(std::filesystem::exists(dir.file("docs/figures/steps_quadruped_trot_flat.png")));
  const std::string manifest = readText(dir.file("out/manifest.json"));
  EXPECT_NE(manifest.find("integrator.max_outer_iterations=77"), std::string::npos) << manifest;
}
