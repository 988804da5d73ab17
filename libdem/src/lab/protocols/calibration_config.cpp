// dem-calibrate's configuration: the [calibration] keys over the simple-shear schema, their typed
// settings, and the shear configuration of one trial.
#include <dem/lab/protocols/calibration.hpp>

#include <sstream>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>

namespace dem::lab {

namespace {

using io::Binding;
using io::BindingTable;
using S = CalibrationSettings;

// The [calibration] keys: one row per key, in the order of --help and --print-config.
const BindingTable<S>& calibration_keys() {
  static const BindingTable<S> table = {
      {"effective_modulus_min", &S::effective_modulus_min, "Pa", "lower bound of the fitted modulus, E* (rrlinear, linear) or E (hertz-mindlin, hertz-dmt) (ball-ball)", 0.0, {}, true},
      {"effective_modulus_max", &S::effective_modulus_max, "Pa", "upper bound of the fitted modulus, E* (rrlinear, linear) or E (hertz-mindlin, hertz-dmt) (ball-ball)", 0.0, {}, true},
      {"friction_min", &S::friction_min, "-", "lower bound of mu (ball-ball)", 0.0},
      {"friction_max", &S::friction_max, "-", "upper bound of mu (ball-ball)", 0.0},
      {"rolling_friction_min", &S::rolling_friction_min, "-", "lower bound of mu_r (ball-ball)", 0.0},
      {"rolling_friction_max", &S::rolling_friction_max, "-", "upper bound of mu_r (ball-ball)", 0.0},
      {"max_trials_per_stage", &S::max_trials_per_stage, "-", "largest number of trials of one stage (reused ones count)", 1.0, 1000.0},
      {"cycles", &S::cycles, "-", "passes of stages 1-3 before stage 4 (the study: 1); a pass that changes nothing ends them", 1.0, 10.0},
      {"batch_size", &S::batch_size, "-", "trials per round of the stage 1-3 searches; the results do not depend on --parallel-trials, they do on this", 1.0, 64.0},
      {"tolerance", &S::tolerance, "-", "relative mismatch of initial slope (stage 1) or peak (stages 2, 3) that ends the stage", 0.0, 1.0, true},
      {"slope_stress_fraction", &S::slope_stress_fraction, "-", "initial slope: least squares through the origin on the lab points up to the strain where the stress first reaches this fraction of the lab peak", 0.0, 1.0, true},
      {"polish_step", &S::polish_step, "-", "first step of stage 4, relative to mu and mu_r", 0.0, 1.0, true},
      {"polish_min_step", &S::polish_min_step, "-", "stage 4 ends when its relative step is below this", 0.0, 1.0, true},
      {"volumetric_weight", &S::volumetric_weight, "-", "stage 4 minimises mean RD(shear stress) + this x mean RD(volumetric strain); the study fits the stress curve first and the volumetric one as a minor factor (0: shear stress alone)", 0.0},
      {"rolling_target", io::enum_choice({"auto", "peak", "dilatancy"}, &S::rolling_target), "-",
       "what stage 3 matches with mu_r: peak (the study; stage 2 has matched it with mu already), dilatancy (late mean volumetric strain) or auto (dilatancy when the lab has volumetric strain)"},
      {"dilatancy_from", &S::dilatancy_from, "-", "late dilatancy: mean volumetric strain over the lab points from this fraction of the largest lab strain", 0.0, 0.99},
      {"modulus_specimen", io::enum_choice({"reconsolidated", "generated"}, &S::modulus_specimen), "-",
       "specimen of an E* other than the starting one: reconsolidated (the starting E*'s consolidated specimen consolidated again at the new E*: same packing, so nearby E* give nearby curves) or generated (consolidated afresh from the generated state: a new packing per E*)"},
      {"eps_stress", io::RealField<S>{[](const S& s) { return s.comparison.eps_stress; }, [](S& s, double v) { s.comparison.eps_stress = v; }},
       "Pa", "lab shear stresses with |value| below this are skipped by the relative difference", 0.0},
      {"eps_strain", io::RealField<S>{[](const S& s) { return s.comparison.eps_strain; }, [](S& s, double v) { s.comparison.eps_strain = v; }},
       "-", "lab volumetric strains with |value| below this are skipped by the relative difference", 0.0},
  };
  return table;
}

}  // namespace

io::Schema calibration_schema() {
  io::Schema s = simple_shear_schema();
  io::add_keys(s, "calibration", calibration_keys(), CalibrationSettings{}, io::FixedAfter::never());  // trials.csv resumes a calibration
  return s;
}

CalibrationSettings calibration_settings(const io::Config& c) {
  CalibrationSettings s;
  io::read_keys(c, "calibration", calibration_keys(), s);
  require(s.effective_modulus_min < s.effective_modulus_max, "calibration.effective_modulus_max", s.effective_modulus_max, "> calibration.effective_modulus_min = " + detail::exact_text(s.effective_modulus_min));
  require(s.friction_min < s.friction_max, "calibration.friction_max", s.friction_max, "> calibration.friction_min = " + detail::exact_text(s.friction_min));
  require(s.rolling_friction_min < s.rolling_friction_max, "calibration.rolling_friction_max", s.rolling_friction_max, "> calibration.rolling_friction_min = " + detail::exact_text(s.rolling_friction_min));
  require(s.polish_min_step <= s.polish_step, "calibration.polish_min_step", s.polish_min_step, "<= calibration.polish_step = " + detail::exact_text(s.polish_step));
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
  out.set("ball_ball." + detail::modulus_key(config.text("ball_ball.law")), detail::exact_text(fit.modulus));
  out.set("ball_ball.friction", detail::exact_text(fit.friction));
  out.set("ball_ball.rolling_friction", detail::exact_text(fit.rolling_friction));
  return out;
}

}  // namespace dem::lab
