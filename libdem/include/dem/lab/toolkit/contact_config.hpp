// A contact type's section of a configuration ([ball_ball], [ball_facet], [ball_pebble]): the law
// it uses, by keyword (core/law_registry.hpp), and that law's parameters as keys of the
// section. The section declares the keys of every registered law; a run reads the chosen law's.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <dem/core/law_registry.hpp>
#include <dem/io/config.hpp>

namespace dem::lab {

struct ContactTypeConfig {
  std::string law = contact_laws().front().keyword;
  LawValues parameters{contact_laws().front().parameters};  // SI, by parameter name

  /// The rolling-resistance linear law (rrlinear) by the deformability method, without dashpots:
  /// a row of the study's Table 1.
  static ContactTypeConfig rolling_linear(double effective_modulus, double stiffness_ratio, double friction,
                                          double rolling_friction);

  /// The registry's row of `law`.
  const LawEntry& entry() const { return contact_law(law); }
  /// The parameters in the roles protocols vary (LawRoles); 0 where the law has none.
  double stiffness() const { return role(entry().roles.stiffness); }
  double friction() const { return role(entry().roles.friction); }
  double rolling_friction() const { return role(entry().roles.rolling_friction); }
  /// Sets the parameter of that role; InputError naming the role for a law without it.
  void set_stiffness(double value) { set_role(entry().roles.stiffness, "stiffness", value); }
  void set_friction(double value) { set_role(entry().roles.friction, "friction", value); }
  void set_rolling_friction(double value) { set_role(entry().roles.rolling_friction, "rolling friction", value); }

  /// The law bound to these parameters; `where` names them in errors ("ball_ball").
  std::shared_ptr<const ContactModel> model(const std::string& where) const;
  /// The same with the friction and rolling friction replaced (a law without rolling friction
  /// ignores `rolling_friction`): a specimen's generation lowers them, walls grow frictionless.
  std::shared_ptr<const ContactModel> model_with_friction(double friction, double rolling_friction,
                                                          const std::string& where) const;
  bool operator==(const ContactTypeConfig&) const = default;

 private:
  double role(const std::string& name) const { return name.empty() ? 0.0 : parameters.at(name); }
  void set_role(const std::string& name, const char* role, double value);
};

/// When a resumed run may no longer change a contact section's keys (docs/restart.md): the law, the
/// parameters, and the parameters in the friction and rolling-friction roles (LawRoles).
struct ContactKeyRules {
  std::optional<io::FixedAfter> law, parameters, friction;
};

/// Declares `<section>.law` and the keys of every law's parameters, with the defaults of
/// `defaults`; `what` names the contact type in the help ("ball-ball").
void add_contact_keys(io::Schema& schema, const std::string& section, const std::string& what,
                      const ContactTypeConfig& defaults, const ContactKeyRules& rules = {});
/// Reads the law of `<section>.law` and its parameters.
ContactTypeConfig read_contact_keys(const io::Config& config, const std::string& section);
/// (key, text) of the section's keys for `value`, as add_contact_keys declares them: a parameter
/// the law does not have is written at `defaults`' value.
void append_contact_values(std::vector<std::pair<std::string, std::string>>& out, const std::string& section,
                           const ContactTypeConfig& value, const ContactTypeConfig& defaults);

}  // namespace dem::lab
