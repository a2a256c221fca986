#include "app/commands.hpp"
#include "common/input_error.hpp"

namespace nmdp::app {

const std::string& optionValue(const Args& args, size_t& i, const char* command) {
  if (i + 1 >= args.size())
    throw InputError(args[i] + " needs a value (see nmdp " + std::string(command) + " --help)");
  return args[++i];
}

}  // namespace nmdp::app
