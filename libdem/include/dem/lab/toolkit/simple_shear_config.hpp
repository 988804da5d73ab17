// Every parameter of the NGI simple-shear cell, in SI units, declared once: the keys of its specimen,
// contacts, rings, engine, generation, consolidation, shear, measurements and outputs, which the
// simple-shear, cyclic and calibration protocols share (a protocol adds its own section, as the
// cyclic test's [cyclic]). The struct nests one
// struct per file section ([specimen], [grading], [ball_ball], [rings], [engine], ...); each field
// is the key of its name (specimen.diameter is SimpleShearConfig::specimen.diameter), and one
// binding table per struct (simple_shear_config.cpp) gives its unit, range and help. The schema's
// defaults are the values of a default-constructed SimpleShearConfig: the study's 4D specimen.
//
// Presets "1D", "2D", "4D" are the study's three particle-size scales with its Table 1 contact
// parameters (docs/model.md 1.3): simple_shear_preset() in C++, preset_values() as keys. Items the
// study does not state (docs/model.md 12: dashpots, ring geometry, shear rate, probe radius...) are
// keys with defensible defaults, never constants.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/io/config_binding.hpp>
#include <dem/lab/toolkit/cementation.hpp>
#include <dem/lab/toolkit/contact_config.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>

namespace dem::lab {

/// [specimen]: the cylinder the balls are generated in.
struct SpecimenConfig {
  double diameter = 0.070;  // m
  double height = 0.022;    // m, before consolidation
  double porosity = 0.46;   // -, target of the generation (sets the ball count; docs/size-effect.md says why 0.46)
  double density = 2650.0;  // kg/m^3, particle density
  std::uint64_t seed = 1;   // random seed of the generation

  bool operator==(const SpecimenConfig&) const = default;
};

/// [rings]: the stack of clump rings around the specimen.
struct RingsConfig {
  double pebble_diameter = 0.0;  // m, 0: the smallest ball diameter
  double gap = 0.0;              // m, vertical gap between rings, 0: a tenth of the pebble radius
  double density = 2700.0;       // kg/m^3, of the solid ring the pebbles stand for
  RingVertical vertical = RingVertical::Follow;
  double stack_height = 0.0;     // m, 0: the specimen height (1.1 x with fixed rings)

  bool operator==(const RingsConfig&) const = default;
};

/// [engine]: integration and stability.
struct EngineConfig {
  double local_damping = 0.7;      // -, alpha
  double time_step = 0.0;          // s, 0: automatic
  double time_step_safety = 0.8;   // -
  double max_overlap_ratio = 1.0;  // -, overlap / smaller radius that stops the run
  int threads = 0;                 // 0: auto (OMP_NUM_THREADS where set, else the affinity mask)
  bool adapt_threads = true;       // fewer threads while that is faster (core/thread_team.hpp)

  bool operator==(const EngineConfig&) const = default;
};

/// The top plate while the radii grow.
enum class GenerationPlate { Fixed, Servo };

/// [generation]: radius expansion, then (servo plate) the friction schedule to the target porosity.
struct GenerationConfig {
  int stages = 8;                  // radius expansion stages from half to full size
  long steps_per_stage = 12000;    // steps per stage and per friction-schedule step, at most
  double equilibrium_ratio = 1e-2; // -, mean unbalanced / mean contact force that ends a stage
  std::optional<double> friction;          // -, ball-ball mu while the radii grow; none: ball_ball.friction
  std::optional<double> rolling_friction;  // -, ball-ball mu_r while the radii grow; none: ball_ball.rolling_friction
  GenerationPlate plate = GenerationPlate::Servo;
  double stress = 5e3;             // Pa, servo target of the top plate while the radii grow
  double servo_max_speed = 1.0;    // m/s, speed cap of that plate (it must keep up with the growth)
  double porosity_tolerance = 0.005;  // -, the friction schedule ends within this of the target
  double friction_reduction = 0.5;    // -, factor on the generation friction per schedule step

  bool operator==(const GenerationConfig&) const = default;
};

/// [consolidation]: the servo-held top plate brought to the vertical stress.
struct ConsolidationConfig {
  double vertical_stress = 200e3;  // Pa
  double tolerance = 0.01;         // -, relative stress error that counts as on target
  double servo_relaxation = 0.5;   // -, alpha_s
  double servo_max_speed = 0.05;   // m/s
  long settle_steps = 500;         // consecutive steps on target that end consolidation
  long max_steps = 400000;         // steps after which consolidation stops with a warning

  bool operator==(const ConsolidationConfig&) const = default;
};

/// [shear]: the shear path and its rate.
struct ShearConfig {
  ShearMode mode = ShearMode::Drained;
  MovingPlate moving_plate = MovingPlate::Bottom;
  ShearDampingFrame damping_frame = ShearDampingFrame::Plates;
  std::vector<double> directions_deg{0.0};  // deg, of each leg
  std::vector<double> leg_strains{};        // -, of each leg; empty: one leg of target_strain
  double target_strain = 0.4;               // -, of a single-leg test
  double servo_max_speed = 0.0;   // m/s; 0: max(consolidation.servo_max_speed, shear plate speed)
  double inertial_number = 1e-3;  // -, target; sets the shear rate unless strain_rate > 0
  double strain_rate = 0.0;       // 1/s, 0: from inertial_number

  /// The legs in order; InputError naming the key for lists of different lengths.
  std::vector<ShearLeg> legs() const;
  /// Sum of the legs' strains.
  double total_strain() const;
  bool operator==(const ShearConfig&) const = default;
};

/// [measure]: the measurement sphere and the profiles.
struct MeasureConfig {
  double sphere_radius_ratio = 0.8;   // -, measurement sphere radius / (H/2)
  int profile_bins = 12;              // height bins of the displacement profile
  double detection_gap_ratio = 0.05;  // -, gap / smallest ball diameter of a contact within detection

  bool operator==(const MeasureConfig&) const = default;
};

enum class VolumeSign { DilationPositive, ContractionPositive };  // sign of volumetric_strain

/// [output]: what is written, and how often.
struct OutputConfig {
  double every_strain = 0.005;  // -, history row interval
  std::vector<double> fabric_strains{0.0, 0.2, 0.4};
  std::vector<double> snapshot_strains{0.0, 0.2, 0.4};
  long restart_every_steps = 20000;
  VolumeSign volumetric_strain_sign = VolumeSign::DilationPositive;
  double progress_seconds = 5.0;  // s, wall-clock interval of progress lines

  bool operator==(const OutputConfig&) const = default;
};

/// The sand of the study: number-uniform diameters on [0.7, 1.2] mm at the 4D scale, with the
/// Leighton Buzzard fraction B sieve curve for grading.sampling = mass.
Grading study_grading();

struct SimpleShearConfig {
  SpecimenConfig specimen;
  Grading grading = study_grading();
  // contacts: Table 1 of the study, 4D row
  ContactTypeConfig ball_ball = ContactTypeConfig::rolling_linear(1.2e7, 1.0, 0.5, 0.4);
  ContactTypeConfig ball_facet = ContactTypeConfig::rolling_linear(2e7, 1.0, 0.9, 0.9);
  ContactTypeConfig ball_pebble = ContactTypeConfig::rolling_linear(2e7, 1.0, 0.1, 0.1);
  RingsConfig rings;
  EngineConfig engine;
  GenerationConfig generation;
  ConsolidationConfig consolidation;
  ShearConfig shear;
  MeasureConfig measure;
  OutputConfig output;
  CementationConfig cementation;  // bonds between close balls (docs/cementation.md); none by default

  /// Ball-ball friction and rolling friction while the radii grow (generation.friction, or the
  /// ball-ball contact's).
  double generation_friction() const;
  double generation_rolling_friction() const;
  /// The checks across keys (the grading, the ring stack against the specimen, the shear legs);
  /// InputError naming the key.
  void validate() const;
  bool operator==(const SimpleShearConfig&) const = default;
};

/// The [engine] keys, for a protocol with a configuration of its own (each key declared once).
const io::BindingTable<EngineConfig>& engine_keys();
/// The value of an engine.threads text: 0 for "auto" (or "0"), else 1 to 256; InputError naming
/// `key` otherwise.
int thread_count(const std::string& text, const std::string& key);
/// The [output] keys every resumable run reads (lab/toolkit/run.hpp): restart_every_steps and
/// progress_seconds.
const io::BindingTable<OutputConfig>& run_output_keys();

/// The schema of every key (section.name), with the defaults of SimpleShearConfig{}.
io::Schema simple_shear_schema();

/// A preset ("1D", "2D", "4D") as a struct: the study's Table 1 ball-ball E*, mu, mu_r and size
/// scale; the generation friction is the same number (not "ball-ball"), so that a calibration
/// varying the ball-ball friction keeps making the same specimen. InputError for another name.
SimpleShearConfig simple_shear_preset(const std::string& preset);

/// Every key and its value's text for `config`, in schema order: what the struct says in the
/// configuration language (each text reads back to the same value).
std::vector<std::pair<std::string, std::string>> simple_shear_values(const SimpleShearConfig& config);

/// The keys a preset sets differently from the defaults, as key=value overrides.
std::vector<std::pair<std::string, std::string>> preset_values(const std::string& preset);

/// The typed configuration from validated values; runs SimpleShearConfig::validate().
SimpleShearConfig simple_shear_config(const io::Config& config);

}  // namespace dem::lab
