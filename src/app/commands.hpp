// Subcommands of the nmdp executable. Each takes the arguments after its name and returns the
// process exit code; bad input is reported by the caller from the InputError it throws.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace nmdp::app {

using Args = std::vector<std::string>;

// The value after the option args[i], advancing i to it; InputError "<option> needs a value (see
// nmdp <command> --help)" when the option is last.
const std::string& optionValue(const Args& args, size_t& i, const char* command);

int runInspect(const Args& args);
extern const char* const kInspectHelp;
int runWrench(const Args& args);
extern const char* const kWrenchHelp;
int runSimulate(const Args& args);
extern const char* const kSimulateHelp;
int runFit(const Args& args);
extern const char* const kFitHelp;
int runGenRft(const Args& args);
extern const char* const kGenRftHelp;
int runSweep(const Args& args);
extern const char* const kSweepHelp;
int runView(const Args& args);
extern const char* const kViewHelp;

}  // namespace nmdp::app
