// Bad input reaches Python as ValueError carrying the CLI's message ("<file>: <key>: <what>"), never
// as a crash of the interpreter.
#include <stdexcept>

#include "bindings.hpp"
#include "common/input_error.hpp"

namespace nmdp::python {

void bindErrors(pybind11::module_& m) {
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace nmdp::python
