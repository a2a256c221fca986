// The one exception type for bad input: its message names the file and the element or key, and
// says what to do. Thrown only where input enters the program.
#pragma once
#include <stdexcept>
#include <string>

namespace nmdp {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace nmdp
