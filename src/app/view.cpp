// nmdp view RUN.h5 [RUN2.h5 ...] [--out PAGE.html] [--serve PORT] [--quiet]
//
// Writes one self-contained HTML page that replays the runs in a browser (the payload of
// view_payload.hpp and the viewer's script, view_page.hpp), atomically and only where an output may
// go (io/output_path.hpp); with --serve it then answers GET / with the page on 127.0.0.1 until
// SIGINT or SIGTERM.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "app/commands.hpp"
#include "app/http_serve.hpp"
#include "app/stop_signals.hpp"
#include "app/view_page.hpp"
#include "app/view_payload.hpp"
#include "common/input_error.hpp"
#include "io/output_path.hpp"

namespace nmdp::app {

const char* const kViewHelp =
    "usage: nmdp view RUN.h5 [RUN2.h5 ...] [--out PAGE.html] [--serve PORT] [--quiet]\n"
    "\n"
    "Writes one self-contained HTML page (no network needed) that replays the runs in a browser: the\n"
    "robot from its URDF (meshes inlined when found, else its collision or inertia-box shapes), the\n"
    "terrain with its sand patches, the contact points and force arrows, the trunk's path, and a plot\n"
    "panel; two or more runs are overlaid on one time cursor. Any run nmdp simulate wrote can be shown:\n"
    "complete, failed, interrupted or killed (its committed rows). What a file lacks is listed as a\n"
    "warning on the page and on stderr.\n"
    "\n"
    "  --out PAGE.html  the page (default: the first run's name with .html, beside it); it never\n"
    "                   replaces a run or a file nmdp did not write\n"
    "  --serve PORT     after writing, serve the page on http://127.0.0.1:PORT/ until SIGINT or\n"
    "                   SIGTERM (0 picks a free port)\n"
    "  --quiet          print nothing but errors\n"
    "\n"
    "The viewer's script is $NMDP_VIEWER_BUNDLE, else viewer/dist/nmdp-view.js of the source tree\n"
    "(scripts/build.sh builds it). Exit status: 0 written (and served until SIGINT or SIGTERM); 1 bad\n"
    "input; 2 no run given; 4 SIGINT or SIGTERM before the page was written (nothing written).\n";

namespace {

struct Options {
  std::vector<std::string> runs;
  std::string out;
  int port = -1;  // -1: do not serve
  bool quiet = false;
};

Options parseArgs(const Args& args) {
  Options o;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--out") {
      o.out = optionValue(args, i, "view");
    } else if (a.rfind("--out=", 0) == 0) {
      o.out = a.substr(6);
    } else if (a == "--serve" || a.rfind("--serve=", 0) == 0) {
      const std::string value = a == "--serve" ? optionValue(args, i, "view") : a.substr(8);
      size_t used = 0;
      long port = -1;
      try {
        port = std::stol(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value.size() || value.empty() || port < 0 || port > 65535)
        throw InputError("--serve: expected a port number from 0 to 65535, got '" + value + "'");
      o.port = static_cast<int>(port);
    } else if (a == "--quiet" || a == "-q") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw InputError("unknown option '" + a + "' (see nmdp view --help)");
    } else {
      o.runs.push_back(a);
    }
  }
  return o;
}

std::string defaultPage(const std::string& run) {
  std::filesystem::path page = std::filesystem::absolute(run).lexically_normal();
  return page.replace_extension(".html").string();
}

}  // namespace

int runView(const Args& args) {
  const Options opt = parseArgs(args);
  if (opt.runs.empty()) {
    std::cerr << kViewHelp;
    return 2;
  }
  const StopSignals stop;
  const std::string out = opt.out.empty() ? defaultPage(opt.runs.front()) : opt.out;
  std::vector<RunInput> inputs;
  for (const std::string& run : opt.runs) inputs.push_back({run, "a run to show"});
  checkOutputFile(out, inputs, opt.out.empty() ? "the default page name" : "--out");
  const std::string script = findViewerBundle();

  const ViewPayload payload = buildViewPayload(opt.runs);
  if (stop.received()) {
    std::cerr << "nmdp view: interrupted by " << StopSignals::name(stop.received()) << "; nothing was written\n";
    return 4;
  }
  if (!opt.quiet)
    for (const std::string& warning : payload.warnings) std::cerr << "nmdp view: warning: " << warning << "\n";
  const std::string page = viewPage(payload.json, script);
  writeFileAtomically(out, page);
  if (!opt.quiet)
    std::printf("wrote %s (%zu run%s, %ld frames): open it in a browser, e.g. chromium %s\n", out.c_str(), opt.runs.size(),
                opt.runs.size() == 1 ? "" : "s", payload.frames, out.c_str());
  if (opt.port < 0) return 0;

  PageServer server(opt.port);
  // The address is printed even with --quiet: a caller that asked for port 0 needs it.
  std::printf("serving %s on http://127.0.0.1:%d/ (Ctrl-C stops)\n", out.c_str(), server.port());
  std::fflush(stdout);
  server.serve(page, stop.flag());
  return 0;
}

}  // namespace nmdp::app
