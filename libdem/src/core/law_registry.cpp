// The built-in laws' rows (the recipe for a new one is atop core/law_registry.hpp).
#include <dem/core/law_registry.hpp>

#include <stdexcept>

#include <dem/contact/hertz_dmt_law.hpp>
#include <dem/contact/hertz_mindlin_law.hpp>
#include <dem/contact/linear_law.hpp>
#include <dem/core/errors.hpp>

namespace dem {

// Compiled once in hertz_dmt_loops.cpp. Declared here, not in core/contact_model.hpp beside the
// other built-in laws, so that a program that never sets it does not see it.
extern template std::shared_ptr<const ContactModel> make_contact_model<HertzDmtLaw>(const HertzDmtLaw::Params&,
                                                                                   const std::string&);

LawValues::LawValues(const std::vector<LawParameter>& parameters) {
  for (const LawParameter& p : parameters) values_[p.name] = p.default_value;
}

double LawValues::at(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error("contact law parameter '" + name + "': the law has none of that name");
  return it->second;
}

std::string LawParameter::choice_name(double value) const {
  const auto index = static_cast<std::size_t>(value);
  if (value < 0.0 || index >= choices.size() || static_cast<double>(index) != value)
    throw std::logic_error("contact law parameter '" + name + "': no choice of index " + std::to_string(value));
  return choices[index];
}

double LawParameter::choice_index(const std::string& text, const std::string& key) const {
  std::string known;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (choices[i] == text) return static_cast<double>(i);
    known += (known.empty() ? "" : ", ") + choices[i];
  }
  throw InputError(key + " = " + text + ": must be one of " + known);
}

double LawValues::value_or(const std::string& name, double fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

namespace {

// Upper bounds that catch a value in the wrong unit or a typo, far above any real grain: diamond's
// Young's modulus is 1.2e12 Pa; friction coefficients above 100 make no slip as well as any.
constexpr double max_modulus = 1e13;  // Pa
constexpr double max_friction = 100.0;

// The linear family's keys: the deformability method (docs/model.md 1.3) and optional dashpots.
std::vector<LawParameter> linear_parameters() {
  return {
      {"effective_modulus", "Pa", "effective modulus E* (deformability method: kn = pi rbar^2 E* / L)", 1e8, 0.0, max_modulus, true},
      {"stiffness_ratio", "-", "normal-to-shear stiffness ratio kappa*", 1.0, 0.0, 100.0, true},
      {"friction", "-", "Coulomb friction coefficient", 0.5, 0.0, max_friction},
      {"normal_damping_ratio", "-", "normal dashpot critical-damping ratio (the study does not state one)", 0.0, 0.0, 1.0},
      {"shear_damping_ratio", "-", "shear dashpot critical-damping ratio", 0.0, 0.0, 1.0},
  };
}

LinearParams linear_params(const LawValues& v) {
  LinearParams p = LinearParams::deformable(v.at("effective_modulus"), v.at("stiffness_ratio"), v.at("friction"));
  p.normal_damping_ratio = v.at("normal_damping_ratio");
  p.shear_damping_ratio = v.at("shear_damping_ratio");
  return p;
}

std::shared_ptr<const ContactModel> bind_linear(const LawValues& v, const std::string& where) {
  return make_contact_model<LinearLaw>(linear_params(v), where);
}

std::shared_ptr<const ContactModel> bind_rolling_linear(const LawValues& v, const std::string& where) {
  RollingLinearLaw::Params p;
  static_cast<LinearParams&>(p) = linear_params(v);
  p.rolling_friction = v.at("rolling_friction");
  return make_contact_model<RollingLinearLaw>(p, where);
}

std::vector<LawParameter> rolling_linear_parameters() {
  std::vector<LawParameter> parameters = linear_parameters();
  parameters.insert(parameters.begin() + 3, {"rolling_friction", "-", "rolling resistance coefficient mu_r", 0.0, 0.0, max_friction});
  return parameters;
}

// Hertz-Mindlin's keys: the material as LIGGGHTS users give it (docs/model.md 1.4).
std::vector<LawParameter> hertz_mindlin_parameters() {
  return {
      {"youngs_modulus", "Pa", "Young's modulus E of the material (E* = E / (2 (1 - nu^2)))", 1e8, 0.0, max_modulus, true},
      {"poissons_ratio", "-", "Poisson's ratio nu (G* = E / (4 (2 - nu)(1 + nu)))", 0.25, 0.0, 0.5},
      {"restitution", "-", "coefficient of restitution e of a head-on impact, sets the dashpots", 0.5, 0.0, 1.0, true},
      {"friction", "-", "Coulomb friction coefficient", 0.5, 0.0, max_friction},
      {"rolling_friction", "-", "rolling resistance coefficient mu_r", 0.0, 0.0, max_friction},
      {"damping_model", "-", "dashpots from e as LIGGGHTS's hertz model (liggghts) or LAMMPS's damping tsuji (tsuji)",
       0.0, {}, {}, false, {"liggghts", "tsuji"}},
      {"rolling", "-",
       "rolling resistance model: epsd (spring k_t R*^2 capped at mu_r R* |F_n|, LIGGGHTS's epsd2), cdt (constant "
       "torque mu_r R* F_ne against the relative spin, LIGGGHTS's cdt), sds (spring rolling_stiffness R*^2 capped as "
       "epsd, LAMMPS's rolling sds) or none (no rolling resistance, whatever rolling_friction says)",
       0.0, {}, {}, false, {"epsd", "cdt", "none", "sds"}},
      {"rolling_stiffness", "N/m",
       "k_roll of rolling = sds: the rolling spring k_roll R*^2 (LAMMPS's rolling sds k_roll); 0 with the other models",
       0.0, 0.0, 1e13},
  };
}

HertzMindlinParams hertz_mindlin_params(const LawValues& v, const std::string& where) {
  const double model = v.at("damping_model");
  require(model == 0.0 || model == 1.0, where + ".damping_model", model, "liggghts (0) or tsuji (1)");
  HertzMindlinParams p;
  p.youngs_modulus = v.at("youngs_modulus");
  p.poissons_ratio = v.at("poissons_ratio");
  p.restitution = v.at("restitution");
  p.friction = v.at("friction");
  p.rolling_friction = v.at("rolling_friction");
  p.damping_model = model == 1.0 ? HertzDamping::tsuji : HertzDamping::liggghts;
  const double rolling = v.at("rolling");  // 0 epsd, 1 cdt, 2 none, 3 sds
  require(rolling == 0.0 || rolling == 1.0 || rolling == 2.0 || rolling == 3.0, where + ".rolling", rolling,
          "epsd (0), cdt (1), none (2) or sds (3)");
  p.rolling = rolling == 1.0 ? HertzRolling::cdt : rolling == 3.0 ? HertzRolling::sds : HertzRolling::epsd;
  if (rolling == 2.0) p.rolling_friction = 0.0;
  p.rolling_stiffness = v.at("rolling_stiffness");
  p.derive();  // a restitution out of range gives NaN constants here, refused by name in validate()
  return p;
}

std::shared_ptr<const ContactModel> bind_hertz_mindlin(const LawValues& v, const std::string& where) {
  return make_contact_model<HertzMindlinLaw>(hertz_mindlin_params(v, where), where);
}

// Hertz-DMT's keys: Hertz-Mindlin's and the surface energy (contact/hertz_dmt_law.hpp).
std::vector<LawParameter> hertz_dmt_parameters() {
  std::vector<LawParameter> parameters = hertz_mindlin_parameters();
  parameters.push_back({"surface_energy", "J/m^2",
                        "surface energy gamma of DMT adhesion: pull-off force 4 pi gamma R*, the contact breaking as the "
                        "surfaces part (LAMMPS's dmt)",
                        0.0, 0.0, 1e3});  // J/m^2: water's is 0.07
  return parameters;
}

std::shared_ptr<const ContactModel> bind_hertz_dmt(const LawValues& v, const std::string& where) {
  HertzDmtParams p;
  p.hertz = hertz_mindlin_params(v, where);
  p.surface_energy = v.at("surface_energy");
  return make_contact_model<HertzDmtLaw>(p, where);
}

}  // namespace

const std::vector<LawEntry>& contact_laws() {
  static const std::vector<LawEntry> laws = {
      {"rrlinear",
       "rolling-resistance linear, PFC's rrlinear (docs/model.md 1.2)",
       rolling_linear_parameters(),
       {"effective_modulus", "friction", "rolling_friction"},
       &bind_rolling_linear},
      {"linear", "linear with Coulomb slip, PFC's linear (docs/model.md 1.1)",
       linear_parameters(),
       {"effective_modulus", "friction", ""},
       &bind_linear},
      {"hertz-mindlin",
       "Hertz normal, Mindlin tangential with Coulomb slip, dashpots from restitution as LIGGGHTS or LAMMPS, "
       "optional rolling resistance (docs/model.md 1.4)",
       hertz_mindlin_parameters(),
       {"youngs_modulus", "friction", "rolling_friction"},
       &bind_hertz_mindlin},
      {"hertz-dmt",
       "Hertz-Mindlin with DMT adhesion 4 pi gamma R* while the surfaces touch, as LAMMPS's dmt (docs/model.md 1.5)",
       hertz_dmt_parameters(),
       {"youngs_modulus", "friction", "rolling_friction"},
       &bind_hertz_dmt},
  };
  return laws;
}

const LawEntry& contact_law(const std::string& keyword, const std::string& key) {
  std::string known;
  for (const LawEntry& law : contact_laws()) {
    if (law.keyword == keyword) return law;
    known += (known.empty() ? "" : ", ") + law.keyword;
  }
  throw InputError(key + " = " + keyword + ": must be one of " + known);
}

std::vector<std::string> contact_law_keywords() {
  std::vector<std::string> keywords;
  for (const LawEntry& law : contact_laws()) keywords.push_back(law.keyword);
  return keywords;
}

}  // namespace dem
