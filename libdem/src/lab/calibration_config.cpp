// dem-calibrate's configuration: the [calibration] keys over the simple-shear schema, their typed
// settings, and the shear configuration of one trial.
#include <dem/lab/calibration.hpp>

#include <sstream>
#include <string>

#include <dem/core/errors.hpp>

namespace dem::lab {

io::Schema calibration_schema() {
  io::Schema s = simple_shear_schema();
  using io::ValueType;
  s.add({.key = "calibration.effective_modulus_min", .default_value = "1e6", .unit = "Pa", .help = "lower bound of E* (ball-ball)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "calibration.effective_modulus_max", .default_value = "1e10", .unit = "Pa", .help = "upper bound of E* (ball-ball)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "calibration.friction_min", .default_value = "0.01", .unit = "-", .help = "lower bound of mu (ball-ball)", .min = 0.0});
  s.add({.key = "calibration.friction_max", .default_value = "2", .unit = "-", .help = "upper bound of mu (ball-ball)", .min = 0.0});
  s.add({.key = "calibration.rolling_friction_min", .default_value = "0", .unit = "-", .help = "lower bound of mu_r (ball-ball)", .min = 0.0});
  s.add({.key = "calibration.rolling_friction_max", .default_value = "1", .unit = "-", .help = "upper bound of mu_r (ball-ball)", .min = 0.0});
  s.add({.key = "calibration.max_trials_per_stage", .type = ValueType::Integer, .default_value = "8", .unit = "-",
         .help = "largest number of trials of one stage (reused ones count)", .min = 1.0, .max = 1000.0});
  s.add({.key = "calibration.cycles", .type = ValueType::Integer, .default_value = "3", .unit = "-",
         .help = "passes of stages 1-3 before stage 4 (the study: 1); a pass that changes nothing ends them", .min = 1.0, .max = 10.0});
  s.add({.key = "calibration.batch_size", .type = ValueType::Integer, .default_value = "2", .unit = "-",
         .help = "trials per round of the stage 1-3 searches; the results do not depend on --parallel-trials, they do on this", .min = 1.0, .max = 64.0});
  s.add({.key = "calibration.tolerance", .default_value = "0.01", .unit = "-",
         .help = "relative mismatch of initial slope (stage 1) or peak (stages 2, 3) that ends the stage", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "calibration.slope_stress_fraction", .default_value = "0.3", .unit = "-",
         .help = "initial slope: least squares through the origin on the lab points up to the strain where the stress first reaches this fraction of the lab peak", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "calibration.polish_step", .default_value = "0.1", .unit = "-", .help = "first step of stage 4, relative to mu and mu_r", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "calibration.polish_min_step", .default_value = "0.02", .unit = "-", .help = "stage 4 ends when its relative step is below this", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "calibration.volumetric_weight", .default_value = "0.2", .unit = "-",
         .help = "stage 4 minimises mean RD(shear stress) + this x mean RD(volumetric strain); the study fits the stress curve first and the volumetric one as a minor factor (0: shear stress alone)", .min = 0.0});
  s.add({.key = "calibration.rolling_target", .type = ValueType::Text, .default_value = "auto", .unit = "-",
         .help = "what stage 3 matches with mu_r: peak (the study; stage 2 has matched it with mu already), dilatancy (late mean volumetric strain) or auto (dilatancy when the lab has volumetric strain)",
         .choices = {"auto", "peak", "dilatancy"}});
  s.add({.key = "calibration.dilatancy_from", .default_value = "0.8", .unit = "-",
         .help = "late dilatancy: mean volumetric strain over the lab points from this fraction of the largest lab strain", .min = 0.0, .max = 0.99});
  s.add({.key = "calibration.modulus_specimen", .type = ValueType::Text, .default_value = "reconsolidated", .unit = "-",
         .help = "specimen of an E* other than the starting one: reconsolidated (the starting E*'s consolidated specimen consolidated again at the new E*: same packing, so nearby E* give nearby curves) or generated (consolidated afresh from the generated state: a new packing per E*)",
         .choices = {"reconsolidated", "generated"}});
  s.add({.key = "calibration.eps_stress", .default_value = "1000", .unit = "Pa", .help = "lab shear stresses with |value| below this are skipped by the relative difference", .min = 0.0});
  s.add({.key = "calibration.eps_strain", .default_value = "1e-4", .unit = "-", .help = "lab volumetric strains with |value| below this are skipped by the relative difference", .min = 0.0});
  return s;
}

CalibrationSettings calibration_settings(const io::Config& c) {
  CalibrationSettings s;
  s.modulus_min = c.real("calibration.effective_modulus_min");
  s.modulus_max = c.real("calibration.effective_modulus_max");
  s.friction_min = c.real("calibration.friction_min");
  s.friction_max = c.real("calibration.friction_max");
  s.rolling_min = c.real("calibration.rolling_friction_min");
  s.rolling_max = c.real("calibration.rolling_friction_max");
  require(s.modulus_min < s.modulus_max, "calibration.effective_modulus_max", s.modulus_max, "> calibration.effective_modulus_min = " + detail::exact_text(s.modulus_min));
  require(s.friction_min < s.friction_max, "calibration.friction_max", s.friction_max, "> calibration.friction_min = " + detail::exact_text(s.friction_min));
  require(s.rolling_min < s.rolling_max, "calibration.rolling_friction_max", s.rolling_max, "> calibration.rolling_friction_min = " + detail::exact_text(s.rolling_min));
  s.max_trials_per_stage = static_cast<int>(c.integer("calibration.max_trials_per_stage"));
  s.batch_size = static_cast<int>(c.integer("calibration.batch_size"));
  s.cycles = static_cast<int>(c.integer("calibration.cycles"));
  s.tolerance = c.real("calibration.tolerance");
  s.slope_stress_fraction = c.real("calibration.slope_stress_fraction");
  s.polish_step = c.real("calibration.polish_step");
  s.polish_min_step = c.real("calibration.polish_min_step");
  require(s.polish_min_step <= s.polish_step, "calibration.polish_min_step", s.polish_min_step, "<= calibration.polish_step = " + detail::exact_text(s.polish_step));
  s.volumetric_weight = c.real("calibration.volumetric_weight");
  const std::string target = c.text("calibration.rolling_target");
  s.rolling_target = target == "peak"        ? CalibrationSettings::RollingTarget::Peak
                     : target == "dilatancy" ? CalibrationSettings::RollingTarget::Dilatancy
                                             : CalibrationSettings::RollingTarget::Auto;
  s.dilatancy_from = c.real("calibration.dilatancy_from");
  s.modulus_specimen = c.text("calibration.modulus_specimen") == "generated" ? ModulusSpecimen::Generated : ModulusSpecimen::Reconsolidated;
  s.comparison.eps_stress = c.real("calibration.eps_stress");
  s.comparison.eps_strain = c.real("calibration.eps_strain");
  return s;
}

void parse_fit_list(const std::string& list, CalibrationSettings& s) {
  s.fit_modulus = s.fit_friction = s.fit_rolling = false;
  std::istringstream in(list);
  for (std::string word; std::getline(in, word, ',');) {
    if (word == "emod") s.fit_modulus = true;
    else if (word == "friction") s.fit_friction = true;
    else if (word == "rolling") s.fit_rolling = true;
    else throw InputError("--fit = " + list + ": '" + word + "' is not a parameter: must be a comma-separated list of emod, friction, rolling");
  }
  require(s.fit_modulus || s.fit_friction || s.fit_rolling, "--fit", "\"" + list + "\"", "at least one of emod, friction, rolling");
}

io::Config shear_config_with(const io::Config& config, const ContactFit& fit) {
  const io::Schema shear = simple_shear_schema();
  io::Config out(shear);
  for (const io::KeySpec& spec : shear.keys()) out.set(spec.key, config.exact_text(spec.key));
  out.set("ball_ball.effective_modulus", detail::exact_text(fit.effective_modulus));
  out.set("ball_ball.friction", detail::exact_text(fit.friction));
  out.set("ball_ball.rolling_friction", detail::exact_text(fit.rolling_friction));
  return out;
}

}  // namespace dem::lab
