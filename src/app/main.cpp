#include <cstdio>
#include <cstring>
#include <string>
#include <filesystem>
#include <iostream>

#include "app/build_version.hpp"
#include "app/commands.hpp"
#include "common/input_error.hpp"
#include "common/input_file.hpp"

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const nmdp::app::Args&);
  const char* const* help;
};

const Command kCommands[] = {
    {"simulate", "simulate a scene (robot, contacts, terrain, method, gait) and write the run to HDF5",
     nmdp::app::runSimulate, &nmdp::app::kSimulateHelp},
    {"fit", "fit a wrench-space contact model (RBF or MLP) to force data and report its error",
     nmdp::app::runFit, &nmdp::app::kFitHelp},
    {"inspect", "summarize a robot description (dof, joints, mass, links, feet) as JSON", nmdp::app::runInspect,
     &nmdp::app::kInspectHelp},
    {"wrench", "evaluate a contact model for one foot and print its wrench-space vertices", nmdp::app::runWrench,
     &nmdp::app::kWrenchHelp},
    {"gen-rft", "wrench samples from resistive force theory over a foot shape, for nmdp fit", nmdp::app::runGenRft,
     &nmdp::app::kGenRftHelp},
    {"view", "write an HTML page that replays runs in a browser (robot, terrain, contact forces, plots)",
     nmdp::app::runView, &nmdp::app::kViewHelp},
    {"sweep", "make many runs of a scene on a Dask cluster and index them (docs/SWEEPS.md)", nmdp::app::runSweep,
     &nmdp::app::kSweepHelp},
};

// A message as one line of readable length: control characters (a newline in a JSON key, a byte of
// a binary file echoed back) are escaped and a message longer than 4000 characters is cut in the middle.
std::string oneLine(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", u);
      out += escaped;
    }
  }
  constexpr size_t kMost = 4000;
  if (out.size() > kMost) out = out.substr(0, kMost / 2) + " ... " + out.substr(out.size() - kMost / 2);
  return out;
}

void printUsage(std::ostream& out) {
  out << "nmdp - legged robots on rigid and granular ground with learned contact models\n\n"
         "usage: nmdp <command> [options]\n\ncommands:\n";
  for (const Command& c : kCommands) out << "  " << c.name << std::string(10 - std::strlen(c.name), ' ') << c.summary << "\n";
  out << "\nnmdp <command> --help shows the options of a command; nmdp --version the version and commit.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && !std::strcmp(argv[1], "--version")) {
    const nmdp::BuildVersion v = nmdp::buildVersion();
    std::cout << "nmdp " << v.version << " (commit " << v.commit << ")\n";
    return 0;
  }
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    printUsage(std::cout);
    return argc < 2 ? 2 : 0;
  }
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[1], c.name) != 0) continue;
    nmdp::app::Args args(argv + 2, argv + argc);
    for (const std::string& a : args)
      if (a == "--help" || a == "-h") {
        std::cout << *c.help;
        return 0;
      }
    try {
      return c.run(args);
    } catch (const nmdp::InputError& e) {
      std::cerr << "nmdp " << c.name << ": error: " << oneLine(e.what()) << "\n";
      return 1;
    } catch (const std::filesystem::filesystem_error& e) {  // a path the system refused (readers check theirs first)
      std::cerr << "nmdp " << c.name << ": error: " << oneLine(nmdp::displayPath(e.path1().string()) + ": " + e.code().message()) << "\n";
      return 1;
    } catch (const std::bad_alloc&) {
      std::cerr << "nmdp " << c.name << ": internal error: out of memory\n";
      return 3;
    } catch (const std::exception& e) {
      std::cerr << "nmdp " << c.name << ": internal error: " << oneLine(e.what()) << "\n";
      return 3;
    }
  }
  std::cerr << "nmdp: unknown command '" << oneLine(argv[1]) << "'\n\n";
  printUsage(std::cerr);
  return 2;
}
