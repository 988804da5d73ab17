#include <dem/lab/toolkit/simple_shear_config.hpp>

#include <cmath>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>

namespace dem::lab {

using io::Binding;
using io::BindingTable;
using io::TextChoice;
using P = RunProgress;

namespace {
const io::FixedAfter ring_built = fixed_after(P::Generating, "the ring stack was built with it");
}  // namespace

std::vector<ShearLeg> ShearConfig::legs() const {
  require(!directions_deg.empty(), "shear.directions_deg", "(empty)", "at least one direction");
  if (leg_strains.empty()) {
    require(directions_deg.size() == 1, "shear.leg_strains", "(empty)",
            "one strain per direction when shear.directions_deg has " + std::to_string(directions_deg.size()) +
                " entries");
    return {{directions_deg[0], target_strain}};
  }
  require(leg_strains.size() == directions_deg.size(), "shear.leg_strains", leg_strains.size(),
          "as many entries as shear.directions_deg (" + std::to_string(directions_deg.size()) + ")");
  std::vector<ShearLeg> legs;
  for (std::size_t k = 0; k < leg_strains.size(); ++k) legs.push_back({directions_deg[k], leg_strains[k]});
  return legs;
}

double ShearConfig::total_strain() const {
  double total = 0.0;
  for (const ShearLeg& leg : legs()) total += leg.strain;
  return total;
}

Grading study_grading() {
  Grading g = leighton_buzzard_b_by_mass();
  g.sampling = Sampling::NumberUniform;
  g.d_min = 0.7e-3;
  g.d_max = 1.2e-3;
  g.scale = 4.0;
  return g;
}

double SimpleShearConfig::generation_friction() const { return generation.friction.value_or(ball_ball.friction()); }
double SimpleShearConfig::generation_rolling_friction() const {
  return generation.rolling_friction.value_or(ball_ball.rolling_friction());
}

void SimpleShearConfig::validate() const {
  grading.validate("grading");
  require(rings.stack_height == 0.0 || rings.stack_height >= specimen.height, "rings.stack_height", rings.stack_height,
          "0 or at least specimen.height (" + io::real_text(specimen.height) + " m)");
  // A ring wall is a stack of rings around the specimen: a pebble as tall as the specimen is no wall.
  const double widest_pebble = std::min(specimen.height, specimen.diameter) / 4;
  require(rings.pebble_diameter <= widest_pebble, "rings.pebble_diameter", rings.pebble_diameter,
          "0 (the smallest ball) or at most a quarter of specimen.height and specimen.diameter (" +
              io::real_text(widest_pebble) + " m): a stack of at least four rings");
  (void)shear.legs();
}

namespace {

// engine.threads: "auto" (0) or a count from 1 to 256; "0", as earlier files wrote auto, reads as auto.
TextChoice<EngineConfig> thread_count_choice() {
  return {{},
          [](const EngineConfig& e) { return e.threads == 0 ? std::string("auto") : std::to_string(e.threads); },
          [](EngineConfig& e, const std::string& text, const std::string& key) {
            e.threads = thread_count(text, key);
          }};
}

}  // namespace

int thread_count(const std::string& text, const std::string& key) {
  if (text == "auto" || text == "0") return 0;
  std::size_t used = 0;
  int n = -1;
  try {
    n = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || n < 1 || n > 256)
    throw InputError(key + " = '" + text + "': expected auto or a whole number of threads from 1 to 256");
  return n;
}

const BindingTable<EngineConfig>& engine_keys() {
  using S = EngineConfig;
  static const BindingTable<S> table = {
      {"local_damping", &S::local_damping, "-", "local non-viscous damping alpha", 0.0, 0.99, false, fixed_after(P::Generating, "every step so far was damped with it")},
      {"time_step", &S::time_step, "s", "time step, 0: automatic from stiffness and mass", 0.0, 1.0, false, fixed_after(P::Generating, "every step so far used it", true)},
      {"time_step_safety", &S::time_step_safety, "-", "automatic time step = safety x critical estimate", 0.0, 1.0, true, fixed_after(P::Generating, "the time step so far was set with it", true)},
      {"max_overlap_ratio", &S::max_overlap_ratio, "-", "overlap / smaller radius that stops the run as unstable (also applied to a resumed restart file)", 0.0, 2.0, true, io::FixedAfter::never()},
      {"threads", thread_count_choice(), "-", "threads of the team: auto (the cores this process may run on: OMP_NUM_THREADS where set, else its affinity mask) or 1 to 256; results do not depend on it", {}, {}, false, io::FixedAfter::never()},
      {"adapt_threads", &S::adapt_threads, "-", "a step runs on fewer threads while that is faster (a busy machine); false: always the whole team", {}, {}, false, io::FixedAfter::never()},
  };
  return table;
}

const BindingTable<OutputConfig>& run_output_keys() {
  using S = OutputConfig;
  static const BindingTable<S> table = {
      {"restart_every_steps", &S::restart_every_steps, "-", "steps between restart files", 1.0},
      {"progress_seconds", &S::progress_seconds, "s", "wall-clock time between progress lines", 0.0, {}, true},
  };
  return table;
}

namespace {

// The binding tables: one row per key, in the order of --help and --print-config.

const BindingTable<SpecimenConfig>& specimen_keys() {
  using S = SpecimenConfig;
  static const BindingTable<S> table = {
      {"diameter", &S::diameter, "m", "specimen diameter", 0.0, 10.0, true},
      {"height", &S::height, "m", "specimen height before consolidation", 0.0, 10.0, true},
      {"porosity", &S::porosity, "-", "target porosity of the generation; sets the ball count (0.46 gives about the study's 3.3-3.6 contacts a ball after consolidation and its principal stress rotation; its 0.37 is denser than spheres with friction pack at a low stress: docs/size-effect.md)", 0.2, 0.8},
      {"density", &S::density, "kg/m^3", "particle density", 1.0, 1e5},
      {"seed", &S::seed, "-", "random seed of the generation", 0.0},
  };
  return table;
}

const BindingTable<Grading>& grading_keys() {
  using S = Grading;
  static const BindingTable<S> table = {
      {"sampling", io::enum_choice({"number-uniform", "mass"}, &S::sampling), "-",
       "number-uniform: diameters uniform by number on [d_min, d_max]; mass: the sieve curve by mass"},
      {"d_min", &S::d_min, "m", "smallest diameter before scaling (number-uniform; 0.0007 reproduces the study's ball counts)", 0.0, 1.0, true},
      {"d_max", &S::d_max, "m", "largest diameter before scaling", 0.0, 1.0, true},
      {"sieve_diameters", &S::sieve_diameters, "m", "sieve sizes of the mass grading (Leighton Buzzard fraction B)", 0.0, 1.0, true},
      {"passing_fraction", &S::passing_fraction, "-", "mass fraction passing each sieve", 0.0, 1.0},
      {"scale", &S::scale, "-", "particle size multiplier (1D, 2D, 4D = 1, 2, 4)", 0.0, 1000.0, true},
  };
  return table;
}

const BindingTable<RingsConfig>& rings_keys() {
  using S = RingsConfig;
  static const BindingTable<S> table = {
      {"pebble_diameter", &S::pebble_diameter, "m", "ring pebble diameter, 0: the smallest ball diameter", 0.0, 1.0, false, ring_built},
      {"gap", &S::gap, "m", "vertical gap between rings, 0: a tenth of the pebble radius", 0.0, 0.1, false, ring_built},
      {"density", &S::density, "kg/m^3", "density of the solid ring the pebbles stand for", 1.0, 1e5, false, ring_built},
      {"vertical", io::enum_choice({"fixed", "follow", "prescribed", "free", "sand"}, &S::vertical), "-",
       "rings once the specimen is made: fixed (held at their heights), follow (each moves vertically with the specimen, its height interpolated between the plates), prescribed (follow, and the horizontal displacement prescribed linear in height: a diagnostic), free (free vertically too: each ring is carried by the sand beside it), sand (each ring moves vertically with the mean vertical velocity of the balls touching it)", {}, {}, false, fixed_after(P::Shearing, "the shear so far moved the rings this way")},
      {"stack_height", &S::stack_height, "m", "height the ring stack covers; 0: the specimen height (1.1 x with rings.vertical = fixed, room for dilation)", 0.0, 10.0, false, ring_built},
  };
  return table;
}

// generation.friction and generation.rolling_friction: "frictionless", "ball-ball" (no value of
// their own: the ball-ball contact's) or a number >= 0.
TextChoice<GenerationConfig> generation_friction_choice(std::optional<double> GenerationConfig::*field) {
  return {{},
          [field](const GenerationConfig& g) { return (g.*field) ? io::real_text(*(g.*field)) : "ball-ball"; },
          [field](GenerationConfig& g, const std::string& text, const std::string& key) {
            if (text == "ball-ball") {
              g.*field = std::nullopt;
              return;
            }
            if (text == "frictionless") {
              g.*field = 0.0;
              return;
            }
            std::size_t used = 0;
            double value = -1.0;
            try {
              value = std::stod(text, &used);
            } catch (const std::exception&) {
              used = 0;
            }
            require(used == text.size() && std::isfinite(value) && value >= 0.0, key, text,
                    "frictionless, ball-ball or a number >= 0");
            g.*field = value;
          }};
}

const BindingTable<GenerationConfig>& generation_keys() {
  using S = GenerationConfig;
  static const BindingTable<S> table = {
      {"stages", &S::stages, "-", "radius expansion stages from half to full size", 1.0, 100.0},
      {"steps_per_stage", &S::steps_per_stage, "-", "largest number of steps of one expansion stage's settling, and of each friction-schedule step's (too few leave the schedule's compaction from the top plate unfinished: a specimen looser at the bottom; the 1D preset takes 26000, as long in seconds as 2D's 12000)", 1.0},
      {"equilibrium_ratio", &S::equilibrium_ratio, "-", "mean unbalanced over mean contact force that ends a stage early", 0.0, {}, true},
      {"friction", generation_friction_choice(&S::friction), "-",
       "ball-ball friction while the radii grow: frictionless, ball-ball (the ball_ball.friction value) or a number >= 0"},
      {"rolling_friction", generation_friction_choice(&S::rolling_friction), "-",
       "ball-ball rolling friction while the radii grow: frictionless, ball-ball (ball_ball.rolling_friction) or a number >= 0"},
      {"plate", io::enum_choice({"fixed", "servo"}, &S::plate), "-",
       "top plate while the radii grow: fixed (a closed cavity of specimen.height) or servo (held at generation.stress, never below specimen.height; then the friction schedule brings the porosity to specimen.porosity)"},
      {"stress", &S::stress, "Pa", "servo stress of the top plate while the radii grow (generation.plate = servo)", 0.0, 1e9, true},
      {"servo_max_speed", &S::servo_max_speed, "m/s", "speed cap of the servo plate while the radii grow: it must rise as fast as the specimen grows (about 3 H x the radius growth rate)", 0.0, 100.0, true},
      {"porosity_tolerance", &S::porosity_tolerance, "-", "the friction schedule stops once the porosity is this close to specimen.porosity", 0.0, 0.1, true},
      {"friction_reduction", &S::friction_reduction, "-", "factor on the generation friction and rolling friction at each step of the friction schedule", 0.0, 1.0, true},
  };
  return table;
}

const BindingTable<ConsolidationConfig>& consolidation_keys() {
  using S = ConsolidationConfig;
  static const BindingTable<S> table = {
      {"vertical_stress", &S::vertical_stress, "Pa", "consolidation stress of the top plate", 0.0, 1e9, true},
      {"tolerance", &S::tolerance, "-", "relative stress error that counts as on target", 0.0, 0.5, true},
      {"servo_relaxation", &S::servo_relaxation, "-", "servo alpha_s: fraction of the stress error removed per step", 0.0, 1.0, true},
      {"servo_max_speed", &S::servo_max_speed, "m/s", "speed cap of the servo plate", 0.0, 100.0, true},
      {"settle_steps", &S::settle_steps, "-", "consecutive on-target steps that end consolidation", 1.0},
      {"max_steps", &S::max_steps, "-", "steps after which consolidation stops with a warning", 1.0},
  };
  return table;
}

const BindingTable<ShearConfig>& shear_keys() {
  using S = ShearConfig;
  static const BindingTable<S> table = {
      {"mode", io::enum_choice({"drained", "constant-volume"}, &S::mode), "-",
       "drained: constant vertical stress (servo); constant-volume: fixed height"},
      {"moving_plate", io::enum_choice({"bottom", "both"}, &S::moving_plate), "-",
       "bottom: the bottom plate moves along the shear, the top is held (the study); both: each moves half the displacement, in opposite directions (the same relative motion, with the specimen's middle at rest)"},
      {"damping_frame", io::enum_choice({"fixed", "plates"}, &S::damping_frame), "-",
       "what local damping measures velocities against while shearing: plates: the plates' affine field, uniform simple shear between them; fixed: the fixed frame, PFC's, which brakes the layers that move with a plate and so loads the sand next to the moving plate more (docs/model.md 3.1)"},
      {"directions_deg", &S::directions_deg, "deg", "direction of each shear leg in the horizontal plane, from +x towards +y", -360.0, 360.0},
      {"leg_strains", &S::leg_strains, "-", "shear strain of each leg; empty: one leg of shear.target_strain", 0.0},
      {"target_strain", &S::target_strain, "-", "shear strain of a single-leg test", 0.0, 100.0, true, io::FixedAfter::never()},
      {"servo_max_speed", &S::servo_max_speed, "m/s", "speed cap of the servo plate while shearing; 0: the larger of consolidation.servo_max_speed and the shear plate speed (a dilating specimen lifts the top plate at up to its dilatancy ratio times that speed)", 0.0, 100.0},
      {"inertial_number", &S::inertial_number, "-", "quasi-static inertial number that sets the shear rate", 0.0, 0.1, true},
      {"strain_rate", &S::strain_rate, "1/s", "shear strain rate, 0: from shear.inertial_number", 0.0, 1e6},
  };
  return table;
}

const BindingTable<MeasureConfig>& measure_keys() {
  using S = MeasureConfig;
  static const BindingTable<S> table = {
      {"sphere_radius_ratio", &S::sphere_radius_ratio, "-", "measurement sphere radius over half the height", 0.05, 1.0},
      {"profile_bins", &S::profile_bins, "-", "height bins of the horizontal displacement profile (uniformity R^2, third strains)", 6.0, 1000.0},
      {"detection_gap_ratio", &S::detection_gap_ratio, "-", "gap over the smallest ball diameter below which a ball-ball pair counts as a contact within detection (PFC lists such inactive contacts); at most the Verlet skin, 0.25", 0.0, 0.25},
  };
  return table;
}

const BindingTable<OutputConfig>& output_keys() {
  using S = OutputConfig;
  static const BindingTable<S> table = [] {
    const BindingTable<S>& run = run_output_keys();
    return BindingTable<S>{
        {"every_strain", &S::every_strain, "-", "shear strain between history rows", 0.0, 100.0, true},
        {"fabric_strains", &S::fabric_strains, "-", "shear strains of rose diagrams (0: after consolidation)", 0.0},
        {"snapshot_strains", &S::snapshot_strains, "-", "shear strains of VTK snapshots (0: after consolidation)", 0.0},
        run[0],
        {"volumetric_strain_sign", io::enum_choice({"dilation-positive", "contraction-positive"}, &S::volumetric_strain_sign), "-",
         "sign of volumetric_strain: dilation-positive (the study's plots) or contraction-positive (soil mechanics)", {}, {}, false,
         fixed_after(P::Consolidated, "history.csv so far was written with it")},
        run[1],
    };
  }();
  return table;
}

// Calls visit(section, table, member) for every section of SimpleShearConfig, in file order, and
// contact(section, what, member) for the contact types' sections (lab/toolkit/contact_config.hpp).
template <class Config, class Visit, class Contact>
void for_each_section(Config& c, Visit&& visit, Contact&& contact) {
  visit("specimen", specimen_keys(), c.specimen);
  visit("grading", grading_keys(), c.grading);
  contact("ball_ball", "ball-ball", c.ball_ball);
  contact("ball_facet", "ball-facet (plates)", c.ball_facet);
  contact("ball_pebble", "ball-pebble (rings)", c.ball_pebble);
  visit("rings", rings_keys(), c.rings);
  visit("engine", engine_keys(), c.engine);
  visit("generation", generation_keys(), c.generation);
  visit("consolidation", consolidation_keys(), c.consolidation);
  visit("shear", shear_keys(), c.shear);
  visit("measure", measure_keys(), c.measure);
  visit("output", output_keys(), c.output);
  visit("cementation", cementation_keys(), c.cementation);  // the element test's keys (lab/toolkit/cementation.hpp)
}

// The rule of a section's keys that have none of their own (docs/restart.md).
std::optional<io::FixedAfter> section_rule(const std::string& section) {
  if (section == "specimen" || section == "grading" || section == "generation") return fixed_after(P::Generating, "the specimen was made with it");
  if (section == "consolidation") return fixed_after(P::Consolidating, "the consolidation ran with it", true);
  if (section == "shear") return fixed_after(P::Shearing, "the shear so far ran with it");
  if (section == "measure") return fixed_after(P::Consolidated, "history.csv so far was measured with it");
  if (section == "output") return io::FixedAfter::never();
  if (section == "cementation") return fixed_after(P::Shearing, "the bonds were installed with it");
  return std::nullopt;  // rings and engine: a rule per key
}

}  // namespace

io::Schema simple_shear_schema() {
  io::Schema schema;
  const SimpleShearConfig defaults;
  for_each_section(
      defaults, [&](const std::string& section, const auto& table, const auto& value) { io::add_keys(schema, section, table, value, section_rule(section)); },
      [&](const std::string& section, const std::string& what, const ContactTypeConfig& value) {
        // Stiffness and damping act from the first step; the friction of the final contacts from the
        // consolidation on (the generation uses generation.friction, with frictionless walls).
        add_contact_keys(schema, section, what, value,
                         {fixed_after(P::Generating, "the contacts so far had it"), fixed_after(P::Generating, "the contacts so far had it", true),
                          fixed_after(P::Consolidating, "the consolidation ran with it", true)});
      });
  return schema;
}

SimpleShearConfig simple_shear_preset(const std::string& preset) {
  // The study's Table 1: ball-ball E*, mu, mu_r per size scale; plates and rings are the same in all.
  auto scale = [](double size, double modulus, double friction, double rolling_friction) {
    SimpleShearConfig c;
    c.grading.scale = size;
    c.ball_ball.set_stiffness(modulus);
    c.ball_ball.set_friction(c.generation.friction.emplace(friction));
    c.ball_ball.set_rolling_friction(c.generation.rolling_friction.emplace(rolling_friction));
    return c;
  };
  if (preset == "1D") {
    // The friction schedule's compaction travels down from the top plate in about the same time
    // at every scale, and the 1D time step is 0.45 of the 2D one: 26000 steps settle as long as
    // 2D's 12000 (with 12000 the 1D specimen stayed looser at the bottom; docs/size-effect.md).
    SimpleShearConfig c = scale(1.0, 5.3e7, 0.45, 0.18);
    c.generation.steps_per_stage = 26000;
    return c;
  }
  if (preset == "2D") return scale(2.0, 4.4e7, 0.5, 0.17);
  if (preset == "4D") return scale(4.0, 1.2e7, 0.5, 0.4);
  throw InputError("--preset = " + preset + ": must be one of 1D, 2D, 4D");
}

std::vector<std::pair<std::string, std::string>> simple_shear_values(const SimpleShearConfig& config) {
  std::vector<std::pair<std::string, std::string>> values;
  const SimpleShearConfig defaults;
  for_each_section(
      config, [&](const std::string& section, const auto& table, const auto& value) { io::append_values(values, section, table, value); },
      [&](const std::string& section, const std::string&, const ContactTypeConfig& value) {
        const ContactTypeConfig& fallback = section == "ball_ball" ? defaults.ball_ball : section == "ball_facet" ? defaults.ball_facet : defaults.ball_pebble;
        append_contact_values(values, section, value, fallback);
      });
  return values;
}

std::vector<std::pair<std::string, std::string>> preset_values(const std::string& preset) {
  const auto defaults = simple_shear_values(SimpleShearConfig{});
  const auto values = simple_shear_values(simple_shear_preset(preset));
  std::vector<std::pair<std::string, std::string>> changed;
  for (std::size_t k = 0; k < values.size(); ++k)
    if (values[k] != defaults[k]) changed.push_back(values[k]);
  return changed;
}

SimpleShearConfig simple_shear_config(const io::Config& config) {
  SimpleShearConfig c;
  for_each_section(
      c, [&](const std::string& section, const auto& table, auto& value) { io::read_keys(config, section, table, value); },
      [&](const std::string& section, const std::string&, ContactTypeConfig& value) { value = read_contact_keys(config, section); });
  c.validate();
  return c;
}

}  // namespace dem::lab
