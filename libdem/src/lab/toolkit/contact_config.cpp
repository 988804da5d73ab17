#include <dem/lab/toolkit/contact_config.hpp>

#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>

namespace dem::lab {

namespace {

// Every law's parameters once, in the registry's order (a name shared by two laws is one key).
std::vector<LawParameter> all_parameters() {
  std::vector<LawParameter> all;
  for (const LawEntry& law : contact_laws())
    for (const LawParameter& p : law.parameters) {
      bool known = false;
      for (const LawParameter& q : all) known = known || q.name == p.name;
      if (!known) all.push_back(p);
    }
  return all;
}

// The laws that read parameter `name`, for its help: "(rrlinear, linear)".
std::string laws_using(const std::string& name) {
  std::string laws;
  for (const LawEntry& law : contact_laws())
    for (const LawParameter& p : law.parameters)
      if (p.name == name) laws += (laws.empty() ? "" : ", ") + law.keyword;
  return "(" + laws + ")";
}

// A key of a law the section does not choose, set to other than its declared default, is refused
// by name: the run would otherwise ignore it in silence (a Young's modulus given to rrlinear). A key
// at its default passes, so that a printed configuration (every law's keys) reads back.
void refuse_other_laws_keys(const io::Config& config, const std::string& section, const LawEntry& law) {
  std::string own;
  for (const LawParameter& p : law.parameters) own += (own.empty() ? "" : ", ") + p.name;
  for (const LawParameter& p : all_parameters()) {
    bool of_law = false;
    for (const LawParameter& q : law.parameters) of_law = of_law || q.name == p.name;
    const std::string key = section + "." + p.name;
    const io::KeySpec* spec = config.schema().find(key);
    if (of_law || spec == nullptr) continue;
    const bool changed = p.choices.empty() ? config.real(key) != std::stod(spec->default_value)
                                           : config.text(key) != spec->default_value;
    if (!changed) continue;
    const std::string laws = laws_using(p.name);  // "(a, b)"
    throw InputError(key + " = " + config.exact_text(key) + ": a key of " + laws.substr(1, laws.size() - 2) +
                     ", not of the chosen law " + section + ".law = " + law.keyword + ", whose keys are " + own +
                     " (remove it, or choose a law that has it)");
  }
}

}  // namespace

ContactTypeConfig ContactTypeConfig::rolling_linear(double effective_modulus, double stiffness_ratio, double friction,
                                                    double rolling_friction) {
  ContactTypeConfig c;
  c.law = "rrlinear";
  c.parameters = LawValues(contact_law(c.law).parameters);
  c.parameters.set("effective_modulus", effective_modulus);
  c.parameters.set("stiffness_ratio", stiffness_ratio);
  c.parameters.set("friction", friction);
  c.parameters.set("rolling_friction", rolling_friction);
  c.parameters.set("normal_damping_ratio", 0.0);
  c.parameters.set("shear_damping_ratio", 0.0);
  return c;
}

void ContactTypeConfig::set_role(const std::string& name, const char* role, double value) {
  require(!name.empty(), std::string("the ") + role + " of contact law " + law, value,
          "not set: the law has no such parameter (core/law_registry.hpp)");
  parameters.set(name, value);
}

std::shared_ptr<const ContactModel> ContactTypeConfig::model(const std::string& where) const {
  return entry().bind(parameters, where);
}

std::shared_ptr<const ContactModel> ContactTypeConfig::model_with_friction(double friction, double rolling_friction,
                                                                           const std::string& where) const {
  const LawRoles& roles = entry().roles;
  LawValues values = parameters;
  if (!roles.friction.empty()) values.set(roles.friction, friction);
  if (!roles.rolling_friction.empty()) values.set(roles.rolling_friction, rolling_friction);
  return entry().bind(values, where);
}

// Whether parameter `name` plays the friction or rolling-friction role in some law.
static bool friction_role(const std::string& name) {
  for (const LawEntry& law : contact_laws())
    if (name == law.roles.friction || name == law.roles.rolling_friction) return true;
  return false;
}

void add_contact_keys(io::Schema& schema, const std::string& section, const std::string& what,
                      const ContactTypeConfig& defaults, const ContactKeyRules& rules) {
  std::string laws;
  for (const LawEntry& law : contact_laws()) laws += (laws.empty() ? "" : "; ") + law.keyword + ": " + law.summary;
  schema.add({.key = section + ".law", .type = io::ValueType::Text, .default_value = defaults.law, .unit = "-",
              .help = "contact law of " + what + " contacts, its parameters the keys below (" + laws + ")",
              .choices = contact_law_keywords(), .fixed = rules.law});
  for (const LawParameter& p : all_parameters()) {
    const std::optional<io::FixedAfter>& fixed = friction_role(p.name) ? rules.friction : rules.parameters;
    if (!p.choices.empty()) {  // a named choice: a text key
      schema.add({.key = section + "." + p.name, .type = io::ValueType::Text,
                  .default_value = p.choice_name(defaults.parameters.value_or(p.name, p.default_value)), .unit = p.unit,
                  .help = p.help + " " + laws_using(p.name), .choices = p.choices, .fixed = fixed});
      continue;
    }
    schema.add({.key = section + "." + p.name, .type = io::ValueType::Real,
                .default_value = io::real_text(defaults.parameters.value_or(p.name, p.default_value)), .unit = p.unit,
                .help = p.help + " " + laws_using(p.name), .min = p.min, .max = p.max, .min_exclusive = p.min_exclusive,
                .fixed = fixed});
  }
}

ContactTypeConfig read_contact_keys(const io::Config& config, const std::string& section) {
  ContactTypeConfig c;
  c.law = config.text(section + ".law");
  const LawEntry& law = contact_law(c.law, section + ".law");
  c.parameters = LawValues();
  for (const LawParameter& p : law.parameters) {
    const std::string key = section + "." + p.name;
    c.parameters.set(p.name, p.choices.empty() ? config.real(key) : p.choice_index(config.text(key), key));
  }
  refuse_other_laws_keys(config, section, law);
  return c;
}

void append_contact_values(std::vector<std::pair<std::string, std::string>>& out, const std::string& section,
                           const ContactTypeConfig& value, const ContactTypeConfig& defaults) {
  out.emplace_back(section + ".law", value.law);
  for (const LawParameter& p : all_parameters()) {
    const double v = value.parameters.value_or(p.name, defaults.parameters.value_or(p.name, p.default_value));
    out.emplace_back(section + "." + p.name, p.choices.empty() ? io::real_text(v) : p.choice_name(v));
  }
}

}  // namespace dem::lab
