#include "contact_models/file_attributes.hpp"

#include <cmath>

#include "common/input_error.hpp"

namespace nmdp {

void FileAttributes::fail(const std::string& what) const { throw InputError(path_ + ": " + what); }

void FileAttributes::checkFormatVersion(int newest) const {
  if (!file_.hasAttribute(group_, "format_version")) return;
  const double version = file_.readDoubleAttribute(group_, "format_version");
  if (!(version >= 1.0 && version <= newest))
    fail("attribute 'format_version' of '" + group_ + "' is " + std::to_string(version) + ", this program reads " +
         (newest == 1 ? "version 1" : "versions 1 to " + std::to_string(newest)));
}

double FileAttributes::finite(const std::string& name) const {
  const double x = file_.readDoubleAttribute(group_, name);
  if (!std::isfinite(x)) fail("attribute '" + name + "' of '" + group_ + "' must be a finite number");
  return x;
}

double FileAttributes::positive(const std::string& name, double fallback, bool required) const {
  if (!required && !file_.hasAttribute(group_, name)) return fallback;
  const double x = file_.readDoubleAttribute(group_, name);
  if (!(x > 0.0) || !std::isfinite(x)) fail("attribute '" + name + "' of '" + group_ + "' must be a positive number");
  return x;
}

int FileAttributes::integer(const std::string& name, double lo, double hi) const {
  const double x = file_.readDoubleAttribute(group_, name);
  if (!(x >= lo && x <= hi) || x != std::floor(x))
    fail("attribute '" + name + "' of '" + group_ + "' must be an integer in [" + std::to_string(static_cast<long>(lo)) +
         ", " + std::to_string(static_cast<long>(hi)) + "], got " + std::to_string(x));
  return static_cast<int>(x);
}

}  // namespace nmdp
