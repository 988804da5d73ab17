// Run configuration shared by all apps: a Schema declares every key (type, default, SI unit,
// allowed range, help); a Config holds one validated value per key, filled from defaults, then a
// .ini or .json file, then command-line --set overrides, in that order of precedence.
//
// Values are checked when they are set, not when they are read, so a typo or a negative
// stiffness stops the run before any time step, with a message that names the key, the value and
// what is allowed. Unknown keys are errors (with a "did you mean" suggestion): silently ignoring
// a misspelled "contact.fricton" would run the wrong experiment. Reading a key the schema does not
// have, or with the wrong type, is a programming error and throws std::logic_error.
//
// Keys have exactly the form "section.name" (letters, digits, '_' and '-'), which maps one to one
// onto INI sections and two-level JSON objects. to_ini()/to_json() print the resolved
// configuration, every key, in a form that load_file() reads back to identical values.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace dem::io {

/// Limits of a configuration file that Config::load_file reads: larger or more deeply nested
/// files are refused before parsing (a configuration is a few KB of section.key entries; the
/// JSON reader recurses once per level).
inline constexpr std::size_t max_config_file_bytes = std::size_t{1} << 20;  // 1 MiB
inline constexpr std::size_t max_config_depth = 64;                          // objects and arrays

enum class ValueType { Real, Integer, Boolean, Text, RealList };

/// "real", "integer", "boolean", "text" or "real list".
std::string to_string(ValueType type);

/// When a run resumed from a restart file may no longer change a key (docs/restart.md): from the
/// protocol's stage `from` on (a protocol numbers its stages in the order a run goes through them;
/// never_fixed: the key may always change), with `why` ending the refusal. A reconsolidation of a
/// consolidated specimen may change the key anyway when `reconsolidation` is set.
struct FixedAfter {
  int from = 0;
  std::string why{};
  bool reconsolidation = false;
  static constexpr int never_fixed = 1 << 30;
  static FixedAfter never() { return {never_fixed, "", true}; }
  bool is_never() const { return from == never_fixed; }
};

/// Declaration of one configuration key. Field order allows designated initializers:
/// {.key = "contact.kn", .type = ValueType::Real, .default_value = "1e6", .unit = "N/m",
///  .help = "normal stiffness", .min = 0.0, .min_exclusive = true}
struct KeySpec {
  // Every member has an initializer, so designated initializers may omit any of them
  // without -Wmissing-field-initializers.
  std::string key{};                   // "section.name"
  ValueType type = ValueType::Real;
  std::string default_value{};         // written as in a file; must itself be valid
  std::string unit{};                  // SI unit of the value, "" or "-" if dimensionless
  std::string help{};                  // one line
  std::optional<double> min{}, max{};  // allowed range (inclusive); RealList: every element
  bool min_exclusive = false;          // min itself is not allowed (e.g. stiffness > 0)
  std::vector<std::string> choices{};  // Text only: the allowed values, if not empty
  std::optional<FixedAfter> fixed{};   // the resume rule; none: the protocol declares none
};

/// The set of keys an app accepts.
class Schema {
 public:
  /// Adds a key. Throws std::logic_error for a malformed or duplicate key, bounds on a boolean or
  /// text key, choices on a non-text key, min > max, or a default that fails its own rules.
  Schema& add(KeySpec spec);

  /// The key's declaration, or nullptr if there is none.
  const KeySpec* find(const std::string& key) const;

  const std::vector<KeySpec>& keys() const { return keys_; }

  /// One aligned line per key: key, type, default, unit, allowed values, help.
  std::string help_text() const;

 private:
  std::vector<KeySpec> keys_;
  std::map<std::string, std::size_t> index_;
};

/// Validated values for every key of a Schema.
class Config {
 public:
  /// Every key at its default. The schema is copied.
  explicit Config(const Schema& schema);

  /// Sets every key found in an .ini or .json file (chosen by extension). On any error the
  /// Config is left as before and dem::InputError names the file and the problem. In JSON a real
  /// list may be an array of numbers or a comma-separated string. A key or section given twice,
  /// a file over max_config_file_bytes and JSON nested deeper than max_config_depth are refused.
  void load_file(const std::filesystem::path& path);

  /// Applies "section.key=value", as given to --set on the command line.
  void set(const std::string& assignment);

  /// Sets one key from its text form (surrounding spaces ignored). Throws dem::InputError for an
  /// unknown key or an invalid value. Booleans accept true/false, 1/0, yes/no, on/off; real lists
  /// are comma separated; reals must be finite.
  void set(const std::string& key, const std::string& value);

  double real(const std::string& key) const;
  long integer(const std::string& key) const;
  bool boolean(const std::string& key) const;
  std::string text(const std::string& key) const;
  /// The value of any key as text that set() reads back to the same value (reals in the
  /// shortest form that round-trips, lists comma separated).
  std::string exact_text(const std::string& key) const;
  std::vector<double> real_list(const std::string& key) const;

  /// The resolved configuration as INI, every key, with help and unit as comments.
  std::string to_ini() const;
  /// The resolved configuration as JSON: one object per section, numbers and booleans unquoted.
  std::string to_json() const;

  const Schema& schema() const { return schema_; }

 private:
  using Value = std::variant<double, long, bool, std::string, std::vector<double>>;
  template <class T>
  const T& get(const std::string& key, ValueType type) const;

  Schema schema_;
  std::vector<Value> values_;  // parallel to schema_.keys()
};

}  // namespace dem::io
