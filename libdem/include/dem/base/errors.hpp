// Error types. Every message names the quantity, the value and what is allowed, so that a user
// can fix the input without reading the source.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace dem {

/// Bad input: a parameter, a file or a geometry that cannot be used.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A run that went unstable (NaN, runaway overlap or speed). The message names the particle,
/// the step and the likely cause.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws InputError("<name> = <value>: must be <allowed>") unless ok.
template <class T>
void require(bool ok, const std::string& name, const T& value, const std::string& allowed) {
  if (ok) return;
  std::ostringstream msg;
  msg.precision(10);
  msg << name << " = " << value << ": must be " << allowed;
  throw InputError(msg.str());
}

inline void require_positive(const std::string& name, double value) {
  require(value > 0.0 && value == value, name, value, "> 0");
}
inline void require_non_negative(const std::string& name, double value) {
  require(value >= 0.0, name, value, ">= 0");
}

}  // namespace dem
