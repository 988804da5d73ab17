#include <dem/lab/simple_shear_config.hpp>

#include <cmath>
#include <sstream>
#include <string>

#include <dem/core/errors.hpp>

namespace dem::lab {

using io::KeySpec;
using io::ValueType;

double SimpleShearConfig::total_strain() const {
  double total = 0.0;
  for (const ShearLeg& leg : legs) total += leg.strain;
  return total;
}

namespace {

void add_contact_keys(io::Schema& s, const std::string& section, const ContactTypeConfig& d, const std::string& what) {
  auto num = [](double v) {
    std::ostringstream out;
    out << v;
    return out.str();
  };
  s.add({.key = section + ".effective_modulus", .default_value = num(d.effective_modulus), .unit = "Pa",
         .help = "effective modulus E* of " + what + " contacts (deformability method)", .min = 0.0, .min_exclusive = true});
  s.add({.key = section + ".stiffness_ratio", .default_value = num(d.stiffness_ratio), .unit = "-",
         .help = "normal-to-shear stiffness ratio kappa*", .min = 0.0, .min_exclusive = true});
  s.add({.key = section + ".friction", .default_value = num(d.friction), .unit = "-", .help = "Coulomb friction coefficient",
         .min = 0.0});
  s.add({.key = section + ".rolling_friction", .default_value = num(d.rolling_friction), .unit = "-",
         .help = "rolling resistance coefficient mu_r", .min = 0.0});
  s.add({.key = section + ".normal_damping_ratio", .default_value = "0", .unit = "-",
         .help = "normal dashpot critical-damping ratio (the study does not state one)", .min = 0.0, .max = 1.0});
  s.add({.key = section + ".shear_damping_ratio", .default_value = "0", .unit = "-",
         .help = "shear dashpot critical-damping ratio", .min = 0.0, .max = 1.0});
}

ContactTypeConfig contact_from(const io::Config& c, const std::string& section) {
  return {c.real(section + ".effective_modulus"), c.real(section + ".stiffness_ratio"), c.real(section + ".friction"),
          c.real(section + ".rolling_friction"),  c.real(section + ".normal_damping_ratio"),
          c.real(section + ".shear_damping_ratio")};
}

std::string number_text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// "frictionless", "ball-ball" (the ball-ball contact's own value) or a number >= 0.
double friction_choice(const io::Config& c, const std::string& key, double ball_ball_value) {
  const std::string text = c.text(key);
  if (text == "frictionless") return 0.0;
  if (text == "ball-ball") return ball_ball_value;
  std::size_t used = 0;
  double value = -1.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  require(used == text.size() && std::isfinite(value) && value >= 0.0, key, text,
          "frictionless, ball-ball or a number >= 0");
  return value;
}

}  // namespace

io::Schema simple_shear_schema() {
  io::Schema s;
  const SimpleShearConfig d;
  s.add({.key = "specimen.diameter", .default_value = "0.07", .unit = "m", .help = "specimen diameter", .min = 0.0, .min_exclusive = true});
  s.add({.key = "specimen.height", .default_value = "0.022", .unit = "m", .help = "specimen height before consolidation", .min = 0.0, .min_exclusive = true});
  s.add({.key = "specimen.porosity", .default_value = "0.4", .unit = "-", .help = "target porosity of the generation; sets the ball count (the study's 0.37 is denser than spheres with friction pack at a low stress: docs/size-effect.md)", .min = 0.2, .max = 0.8});
  s.add({.key = "specimen.density", .default_value = "2650", .unit = "kg/m^3", .help = "particle density", .min = 0.0, .min_exclusive = true});
  s.add({.key = "specimen.seed", .type = ValueType::Integer, .default_value = "1", .unit = "-", .help = "random seed of the generation", .min = 0.0});
  s.add({.key = "grading.sampling", .type = ValueType::Text, .default_value = "number-uniform", .unit = "-",
         .help = "number-uniform: diameters uniform by number on [d_min, d_max]; mass: the sieve curve by mass",
         .choices = {"number-uniform", "mass"}});
  s.add({.key = "grading.d_min", .default_value = "0.0007", .unit = "m", .help = "smallest diameter before scaling (number-uniform; 0.0007 reproduces the study's ball counts)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "grading.d_max", .default_value = "0.0012", .unit = "m", .help = "largest diameter before scaling", .min = 0.0, .min_exclusive = true});
  s.add({.key = "grading.sieve_diameters", .type = ValueType::RealList, .default_value = "0.0006,0.00065,0.00082,0.000897,0.0012",
         .unit = "m", .help = "sieve sizes of the mass grading (Leighton Buzzard fraction B)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "grading.passing_fraction", .type = ValueType::RealList, .default_value = "0,0.1,0.5,0.6,1", .unit = "-",
         .help = "mass fraction passing each sieve", .min = 0.0, .max = 1.0});
  s.add({.key = "grading.scale", .default_value = "4", .unit = "-", .help = "particle size multiplier (1D, 2D, 4D = 1, 2, 4)", .min = 0.0, .min_exclusive = true});
  add_contact_keys(s, "ball_ball", d.ball_ball, "ball-ball");
  add_contact_keys(s, "ball_facet", d.ball_facet, "ball-facet (plates)");
  add_contact_keys(s, "ball_pebble", d.ball_pebble, "ball-pebble (rings)");
  s.add({.key = "rings.pebble_diameter", .default_value = "0", .unit = "m", .help = "ring pebble diameter, 0: the smallest ball diameter", .min = 0.0});
  s.add({.key = "rings.gap", .default_value = "0", .unit = "m", .help = "vertical gap between rings, 0: a tenth of the pebble radius", .min = 0.0});
  s.add({.key = "rings.density", .default_value = "2700", .unit = "kg/m^3", .help = "density of the solid ring the pebbles stand for", .min = 0.0, .min_exclusive = true});
  s.add({.key = "rings.vertical", .type = ValueType::Text, .default_value = "follow", .unit = "-",
         .help = "rings once the specimen is made: fixed (held at their heights), follow (each moves vertically with the specimen, its height interpolated between the plates), prescribed (follow, and the horizontal displacement prescribed linear in height: a diagnostic), free (free vertically too: each ring is carried by the sand beside it), sand (each ring moves vertically with the mean vertical velocity of the balls touching it)",
         .choices = {"fixed", "follow", "prescribed", "free", "sand"}});
  s.add({.key = "rings.stack_height", .default_value = "0", .unit = "m",
         .help = "height the ring stack covers; 0: the specimen height (1.1 x with rings.vertical = fixed, room for dilation)", .min = 0.0});
  s.add({.key = "engine.local_damping", .default_value = "0.7", .unit = "-", .help = "local non-viscous damping alpha", .min = 0.0, .max = 0.99});
  s.add({.key = "engine.time_step", .default_value = "0", .unit = "s", .help = "time step, 0: automatic from stiffness and mass", .min = 0.0});
  s.add({.key = "engine.time_step_safety", .default_value = "0.8", .unit = "-", .help = "automatic time step = safety x critical estimate", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "engine.max_overlap_ratio", .default_value = "1", .unit = "-",
         .help = "overlap / smaller radius that stops the run as unstable (also applied to a resumed restart file)", .min = 0.0, .max = 2.0, .min_exclusive = true});
  s.add({.key = "engine.threads", .type = ValueType::Integer, .default_value = "0", .unit = "-", .help = "OpenMP threads, 0: OMP_NUM_THREADS", .min = 0.0, .max = 256.0});
  s.add({.key = "generation.stages", .type = ValueType::Integer, .default_value = "8", .unit = "-", .help = "radius expansion stages from half to full size", .min = 1.0, .max = 100.0});
  s.add({.key = "generation.steps_per_stage", .type = ValueType::Integer, .default_value = "12000", .unit = "-", .help = "largest number of steps of one expansion stage's settling, and of each friction-schedule step's (too few leave the schedule's compaction from the top plate unfinished: a specimen looser at the bottom)", .min = 1.0});
  s.add({.key = "generation.equilibrium_ratio", .default_value = "0.01", .unit = "-", .help = "mean unbalanced over mean contact force that ends a stage early", .min = 0.0, .min_exclusive = true});
  s.add({.key = "generation.friction", .type = ValueType::Text, .default_value = "ball-ball", .unit = "-",
         .help = "ball-ball friction while the radii grow: frictionless, ball-ball (the ball_ball.friction value) or a number >= 0"});
  s.add({.key = "generation.rolling_friction", .type = ValueType::Text, .default_value = "ball-ball", .unit = "-",
         .help = "ball-ball rolling friction while the radii grow: frictionless, ball-ball (ball_ball.rolling_friction) or a number >= 0"});
  s.add({.key = "generation.plate", .type = ValueType::Text, .default_value = "servo", .unit = "-",
         .help = "top plate while the radii grow: fixed (a closed cavity of specimen.height) or servo (held at generation.stress, never below specimen.height; then the friction schedule brings the porosity to specimen.porosity)",
         .choices = {"fixed", "servo"}});
  s.add({.key = "generation.stress", .default_value = "5000", .unit = "Pa", .help = "servo stress of the top plate while the radii grow (generation.plate = servo)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "generation.servo_max_speed", .default_value = "1", .unit = "m/s", .help = "speed cap of the servo plate while the radii grow: it must rise as fast as the specimen grows (about 3 H x the radius growth rate)", .min = 0.0, .min_exclusive = true});
  s.add({.key = "generation.porosity_tolerance", .default_value = "0.005", .unit = "-", .help = "the friction schedule stops once the porosity is this close to specimen.porosity", .min = 0.0, .max = 0.1, .min_exclusive = true});
  s.add({.key = "generation.friction_reduction", .default_value = "0.5", .unit = "-", .help = "factor on the generation friction and rolling friction at each step of the friction schedule", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "consolidation.vertical_stress", .default_value = "200000", .unit = "Pa", .help = "consolidation stress of the top plate", .min = 0.0, .min_exclusive = true});
  s.add({.key = "consolidation.tolerance", .default_value = "0.01", .unit = "-", .help = "relative stress error that counts as on target", .min = 0.0, .max = 0.5, .min_exclusive = true});
  s.add({.key = "consolidation.servo_relaxation", .default_value = "0.5", .unit = "-", .help = "servo alpha_s: fraction of the stress error removed per step", .min = 0.0, .max = 1.0, .min_exclusive = true});
  s.add({.key = "consolidation.servo_max_speed", .default_value = "0.05", .unit = "m/s", .help = "speed cap of the servo plate", .min = 0.0, .min_exclusive = true});
  s.add({.key = "consolidation.settle_steps", .type = ValueType::Integer, .default_value = "500", .unit = "-", .help = "consecutive on-target steps that end consolidation", .min = 1.0});
  s.add({.key = "consolidation.max_steps", .type = ValueType::Integer, .default_value = "400000", .unit = "-", .help = "steps after which consolidation stops with a warning", .min = 1.0});
  s.add({.key = "shear.mode", .type = ValueType::Text, .default_value = "drained", .unit = "-",
         .help = "drained: constant vertical stress (servo); constant-volume: fixed height", .choices = {"drained", "constant-volume"}});
  s.add({.key = "shear.moving_plate", .type = ValueType::Text, .default_value = "bottom", .unit = "-",
         .help = "bottom: the bottom plate moves along the shear, the top is held (the study); both: each moves half the displacement, in opposite directions (the same relative motion, with the specimen's middle at rest)",
         .choices = {"bottom", "both"}});
  s.add({.key = "shear.directions_deg", .type = ValueType::RealList, .default_value = "0", .unit = "deg",
         .help = "direction of each shear leg in the horizontal plane, from +x towards +y", .min = -360.0, .max = 360.0});
  s.add({.key = "shear.leg_strains", .type = ValueType::RealList, .default_value = "", .unit = "-",
         .help = "shear strain of each leg; empty: one leg of shear.target_strain", .min = 0.0});
  s.add({.key = "shear.target_strain", .default_value = "0.4", .unit = "-", .help = "shear strain of a single-leg test", .min = 0.0, .min_exclusive = true});
  s.add({.key = "shear.servo_max_speed", .default_value = "0", .unit = "m/s",
         .help = "speed cap of the servo plate while shearing; 0: the larger of consolidation.servo_max_speed and the shear plate speed (a dilating specimen lifts the top plate at up to its dilatancy ratio times that speed)", .min = 0.0});
  s.add({.key = "shear.inertial_number", .default_value = "0.001", .unit = "-", .help = "quasi-static inertial number that sets the shear rate", .min = 0.0, .max = 0.1, .min_exclusive = true});
  s.add({.key = "shear.strain_rate", .default_value = "0", .unit = "1/s", .help = "shear strain rate, 0: from shear.inertial_number", .min = 0.0});
  s.add({.key = "measure.sphere_radius_ratio", .default_value = "0.8", .unit = "-", .help = "measurement sphere radius over half the height", .min = 0.05, .max = 1.0});
  s.add({.key = "measure.profile_bins", .type = ValueType::Integer, .default_value = "12", .unit = "-", .help = "height bins of the horizontal displacement profile (uniformity R^2, third strains)", .min = 6.0, .max = 1000.0});
  s.add({.key = "measure.detection_gap_ratio", .default_value = "0.05", .unit = "-", .help = "gap over the smallest ball diameter below which a ball-ball pair counts as a contact within detection (PFC lists such inactive contacts); at most the Verlet skin, 0.25", .min = 0.0, .max = 0.25});
  s.add({.key = "output.every_strain", .default_value = "0.005", .unit = "-", .help = "shear strain between history rows", .min = 0.0, .min_exclusive = true});
  s.add({.key = "output.fabric_strains", .type = ValueType::RealList, .default_value = "0,0.2,0.4", .unit = "-", .help = "shear strains of rose diagrams (0: after consolidation)", .min = 0.0});
  s.add({.key = "output.snapshot_strains", .type = ValueType::RealList, .default_value = "0,0.2,0.4", .unit = "-", .help = "shear strains of VTK snapshots (0: after consolidation)", .min = 0.0});
  s.add({.key = "output.restart_every_steps", .type = ValueType::Integer, .default_value = "20000", .unit = "-", .help = "steps between restart files", .min = 1.0});
  s.add({.key = "output.volumetric_strain_sign", .type = ValueType::Text, .default_value = "dilation-positive", .unit = "-",
         .help = "sign of volumetric_strain: dilation-positive (the study's plots) or contraction-positive (soil mechanics)",
         .choices = {"dilation-positive", "contraction-positive"}});
  s.add({.key = "output.progress_seconds", .default_value = "5", .unit = "s", .help = "wall-clock time between progress lines", .min = 0.0, .min_exclusive = true});
  return s;
}

std::vector<std::pair<std::string, std::string>> preset_values(const std::string& preset) {
  // The study's Table 1: ball-ball E*, mu, mu_r per size scale; plates and rings are the same in all.
  // The generation friction is the same number, not "ball-ball": a calibration that varies the
  // ball-ball friction must keep making the same specimen.
  auto scale = [](const char* s, const char* e, const char* mu, const char* mu_r) {
    return std::vector<std::pair<std::string, std::string>>{
        {"grading.scale", s},        {"ball_ball.effective_modulus", e}, {"ball_ball.friction", mu},
        {"ball_ball.rolling_friction", mu_r}, {"generation.friction", mu}, {"generation.rolling_friction", mu_r}};
  };
  if (preset == "1D") return scale("1", "5.3e7", "0.45", "0.18");
  if (preset == "2D") return scale("2", "4.4e7", "0.5", "0.17");
  if (preset == "4D") return scale("4", "1.2e7", "0.5", "0.4");
  throw InputError("--preset = " + preset + ": must be one of 1D, 2D, 4D");
}

SimpleShearConfig simple_shear_config(const io::Config& c) {
  SimpleShearConfig s;
  s.diameter = c.real("specimen.diameter");
  s.height = c.real("specimen.height");
  s.porosity = c.real("specimen.porosity");
  s.density = c.real("specimen.density");
  s.seed = static_cast<std::uint64_t>(c.integer("specimen.seed"));
  s.grading.sampling = c.text("grading.sampling") == "mass" ? Sampling::MassGrading : Sampling::NumberUniform;
  s.grading.d_min = c.real("grading.d_min");
  s.grading.d_max = c.real("grading.d_max");
  s.grading.sieve_diameters = c.real_list("grading.sieve_diameters");
  s.grading.passing_fraction = c.real_list("grading.passing_fraction");
  s.grading.scale = c.real("grading.scale");
  s.grading.validate("grading");
  s.ball_ball = contact_from(c, "ball_ball");
  s.ball_facet = contact_from(c, "ball_facet");
  s.ball_pebble = contact_from(c, "ball_pebble");
  s.pebble_diameter = c.real("rings.pebble_diameter");
  s.ring_gap = c.real("rings.gap");
  s.ring_density = c.real("rings.density");
  const std::string vertical = c.text("rings.vertical");
  s.ring_vertical = vertical == "fixed"    ? RingVertical::Fixed
                    : vertical == "follow" ? RingVertical::Follow
                    : vertical == "free"   ? RingVertical::Free
                    : vertical == "sand"   ? RingVertical::Sand
                                           : RingVertical::Prescribed;
  s.ring_stack_height = c.real("rings.stack_height");
  require(s.ring_stack_height == 0.0 || s.ring_stack_height >= c.real("specimen.height"), "rings.stack_height",
          s.ring_stack_height, "0 or at least specimen.height (" + number_text(c.real("specimen.height")) + " m)");
  s.local_damping = c.real("engine.local_damping");
  s.time_step = c.real("engine.time_step");
  s.time_step_safety = c.real("engine.time_step_safety");
  s.max_overlap_ratio = c.real("engine.max_overlap_ratio");
  s.threads = static_cast<int>(c.integer("engine.threads"));
  s.expansion_stages = static_cast<int>(c.integer("generation.stages"));
  s.expansion_steps = c.integer("generation.steps_per_stage");
  s.equilibrium_ratio = c.real("generation.equilibrium_ratio");
  s.generation_friction = friction_choice(c, "generation.friction", s.ball_ball.friction);
  s.generation_rolling_friction = friction_choice(c, "generation.rolling_friction", s.ball_ball.rolling_friction);
  s.generation_servo = c.text("generation.plate") == "servo";
  s.generation_stress = c.real("generation.stress");
  s.generation_servo_max_speed = c.real("generation.servo_max_speed");
  s.generation_porosity_tolerance = c.real("generation.porosity_tolerance");
  s.generation_friction_reduction = c.real("generation.friction_reduction");
  s.vertical_stress = c.real("consolidation.vertical_stress");
  s.stress_tolerance = c.real("consolidation.tolerance");
  s.servo_relaxation = c.real("consolidation.servo_relaxation");
  s.servo_max_speed = c.real("consolidation.servo_max_speed");
  s.settle_steps = c.integer("consolidation.settle_steps");
  s.consolidation_max_steps = c.integer("consolidation.max_steps");
  s.constant_volume = c.text("shear.mode") == "constant-volume";
  s.both_plates_move = c.text("shear.moving_plate") == "both";
  s.shear_servo_max_speed = c.real("shear.servo_max_speed");
  const auto directions = c.real_list("shear.directions_deg");
  const auto strains = c.real_list("shear.leg_strains");
  require(!directions.empty(), "shear.directions_deg", "(empty)", "at least one direction");
  s.legs.clear();
  if (strains.empty()) {
    require(directions.size() == 1, "shear.leg_strains", "(empty)",
            "one strain per direction when shear.directions_deg has " + std::to_string(directions.size()) + " entries");
    s.legs.push_back({directions[0], c.real("shear.target_strain")});
  } else {
    require(strains.size() == directions.size(), "shear.leg_strains", strains.size(),
            "as many entries as shear.directions_deg (" + std::to_string(directions.size()) + ")");
    for (std::size_t k = 0; k < strains.size(); ++k) s.legs.push_back({directions[k], strains[k]});
  }
  s.inertial_number = c.real("shear.inertial_number");
  s.strain_rate = c.real("shear.strain_rate");
  s.probe_radius_ratio = c.real("measure.sphere_radius_ratio");
  s.profile_bins = static_cast<int>(c.integer("measure.profile_bins"));
  s.detection_gap_ratio = c.real("measure.detection_gap_ratio");
  s.output_every_strain = c.real("output.every_strain");
  s.fabric_strains = c.real_list("output.fabric_strains");
  s.snapshot_strains = c.real_list("output.snapshot_strains");
  s.restart_every_steps = c.integer("output.restart_every_steps");
  s.dilation_positive = c.text("output.volumetric_strain_sign") == "dilation-positive";
  s.progress_seconds = c.real("output.progress_seconds");
  return s;
}

}  // namespace dem::lab
