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

/// A text a message quotes, as a user can read it: control bytes (NUL, escapes, CR) and a UTF-8
/// byte-order mark written as \xNN, and at most `most` bytes of it followed by "... (N bytes)", so
/// that a binary or 100 KB value never lands whole in a terminal or a log.
inline std::string quoted_excerpt(const std::string& text, std::size_t most = 200) {
  static constexpr char hex[] = "0123456789abcdef";
  const auto escaped = [](unsigned char byte) { return std::string("\\x") + hex[byte >> 4] + hex[byte & 15]; };
  const std::size_t shown = text.size() > most ? most : text.size();
  std::string out;
  for (std::size_t k = 0; k < shown; ++k) {
    const auto byte = static_cast<unsigned char>(text[k]);
    if (text.compare(k, 3, "\xef\xbb\xbf") == 0) {  // a byte-order mark, invisible in a terminal
      out += escaped(0xef) + escaped(0xbb) + escaped(0xbf);
      k += 2;
    } else {
      out += byte < 0x20 || byte == 0x7f ? escaped(byte) : std::string(1, static_cast<char>(byte));
    }
  }
  if (shown < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

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
