// The contact laws by keyword: what a configuration's `<contact type>.law` key names, with the
// parameters each law reads from the keys of that section. Apps, protocols and Python choose a law
// here; the engine only ever sees the ContactModel a row makes (contact_model.hpp). The laws
// themselves are plain types in contact/; the registry binds each to the engine's loops, so it sits
// on core's floor, the first that knows both.
//
// Adding a law:
//   1. Write its header in contact/, a plain type like the laws of linear_law.hpp: Params (SI,
//      validate(where)), State (its per-contact history), name, force and stiffness (the
//      ContactLaw concept of contact/contact_law.hpp), and a physics test in tests/physics/ against an
//      analytic result.
//   2. Add one row to contact_laws() in src/core/law_registry.cpp: its keyword, one line of
//      help, its parameters (each one a key of the contact type's section: name, SI unit, range,
//      help, default), the parameters that play the roles protocols vary (LawRoles), and the
//      function that turns the values into its ContactModel.
//   Nothing else: the apps' configuration (keys, --help, --print-config), restart records and the
//   Python module list the laws from this table.
//
// One parameter name means one quantity in every law (friction is Coulomb's mu, in every row that
// has it), so a configuration section holds the union of the laws' keys without conflict.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <dem/core/contact_model.hpp>

namespace dem {

/// One parameter of a law: a key `<section>.<name>` of the configuration, real-valued, or one of
/// named choices (the value is the choice's index, the key's text its name).
struct LawParameter {
  std::string name;             // key name, e.g. "effective_modulus"
  std::string unit;             // SI unit, "-" if dimensionless
  std::string help;             // one line
  double default_value = 0.0;   // in the unit above (for choices: the index of the default)
  std::optional<double> min{}, max{};  // allowed range, inclusive unless min_exclusive
  bool min_exclusive = false;
  std::vector<std::string> choices{};  // named choices, e.g. {"liggghts", "tsuji"}; empty: a real

  /// The name of choice `value`, and the index of choice `text` (InputError naming `key`, the
  /// text and the choices).
  std::string choice_name(double value) const;
  double choice_index(const std::string& text, const std::string& key) const;
};

/// A law's parameter values by name, in SI units.
class LawValues {
 public:
  LawValues() = default;
  /// Every parameter of `parameters` at its default.
  explicit LawValues(const std::vector<LawParameter>& parameters);
  /// The value of `name`; std::logic_error if it has none (a program that asks a law for a
  /// parameter it does not declare).
  double at(const std::string& name) const;
  double value_or(const std::string& name, double fallback) const;
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  void set(const std::string& name, double value) { values_[name] = value; }
  const std::map<std::string, double>& all() const { return values_; }
  bool operator==(const LawValues&) const = default;

 private:
  std::map<std::string, double> values_;
};

/// Which parameter of a law plays each part that protocols vary: a specimen's generation lowers
/// the friction, a calibration fits the stiffness, the friction and the rolling friction. Empty:
/// the law has no such parameter.
struct LawRoles {
  std::string stiffness;         // e.g. "effective_modulus" (the linear laws' E*)
  std::string friction;          // Coulomb's mu
  std::string rolling_friction;  // mu_r
};

/// One row of the registry.
struct LawEntry {
  std::string keyword;                   // as the configuration names it, e.g. "rrlinear"
  std::string summary;                   // one line for --help
  std::vector<LawParameter> parameters;  // in the order of --help and --print-config
  LawRoles roles;
  /// The law bound to `values` (every parameter of the row), checked: InputError naming
  /// `where`.name and the value for a value the law cannot use.
  std::shared_ptr<const ContactModel> (*bind)(const LawValues& values, const std::string& where);
};

/// Every built-in law, in the order --help lists them; the first is the default.
const std::vector<LawEntry>& contact_laws();

/// The row of `keyword`; InputError naming `key` (e.g. "ball_ball.law"), the keyword and the
/// keywords there are.
const LawEntry& contact_law(const std::string& keyword, const std::string& key = "law");

/// The keywords of contact_laws(), in order.
std::vector<std::string> contact_law_keywords();

}  // namespace dem
