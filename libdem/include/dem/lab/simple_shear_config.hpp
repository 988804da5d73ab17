// Every parameter of the simple-shear protocol, in SI units, and its configuration schema
// (keys, defaults, ranges, help) so that apps read it from INI/JSON files and --set overrides.
//
// Presets "1D", "2D", "4D" are the study's three particle-size scales with its Table 1 contact
// parameters (docs/model.md 1.3). Items the study does not state (docs/model.md 12: dashpots, ring
// geometry, shear rate, probe radius...) are keys with defensible defaults, never constants.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/lab/grading.hpp>

namespace dem::lab {

/// Contact-model parameters of one contact type (rolling-resistance linear law).
struct ContactTypeConfig {
  double effective_modulus = 0.0;    // Pa, E*
  double stiffness_ratio = 1.0;      // -, kn/ks
  double friction = 0.0;             // -, mu
  double rolling_friction = 0.0;     // -, mu_r
  double normal_damping_ratio = 0.0; // -, beta_n
  double shear_damping_ratio = 0.0;  // -, beta_s
};

/// One leg of the shear path: the bottom plate moves along `direction_deg` (from +x towards +y)
/// by `strain` x the consolidated height.
struct ShearLeg {
  double direction_deg = 0.0;  // deg
  double strain = 0.0;         // -, shear strain increment of this leg
};

/// How the rings move vertically once the specimen is made (docs/model.md 4).
enum class RingVertical {
  Fixed,       ///< held at their generation heights
  Follow,      ///< each ring moves with the specimen: its height interpolated between the plates
  Prescribed,  ///< follow, and the horizontal displacement is prescribed linear in height (diagnostic)
  Free,        ///< free in z too: each ring rides on the sand next to it, no vertical side friction on balance
  Sand,        ///< each ring moves vertically with the mean vertical velocity of the balls touching it
};

struct SimpleShearConfig {
  // specimen
  double diameter = 0.070;   // m
  double height = 0.022;     // m
  double porosity = 0.40;    // -, target of the generation (sets the ball count)
  double density = 2650.0;   // kg/m^3, particle density
  std::uint64_t seed = 1;
  Grading grading;
  // contacts (Table 1 of the study, 4D row by default)
  ContactTypeConfig ball_ball{1.2e7, 1.0, 0.5, 0.4}, ball_facet{2e7, 1.0, 0.9, 0.9}, ball_pebble{2e7, 1.0, 0.1, 0.1};
  // rings
  double pebble_diameter = 0.0;  // m, 0: the smallest ball diameter
  double ring_gap = 0.0;         // m, vertical gap between rings, 0: a tenth of the pebble radius
  double ring_density = 2700.0;  // kg/m^3
  RingVertical ring_vertical = RingVertical::Follow;
  double ring_stack_height = 0.0; // m, 0: the specimen height (1.1 x with fixed rings)
  // engine
  double local_damping = 0.7;    // -
  double time_step = 0.0;        // s, 0: automatic
  double time_step_safety = 0.8; // -
  double max_overlap_ratio = 1.0; // -, overlap / smaller radius that stops the run
  int threads = 0;               // 0: OMP_NUM_THREADS
  // generation (radius expansion)
  int expansion_stages = 8;
  long expansion_steps = 12000;         // steps per stage and per friction-schedule step, at most
  double equilibrium_ratio = 1e-2;      // -, mean unbalanced / mean contact force that ends a stage
  double generation_friction = 0.0;     // -, ball-ball mu while the radii grow
  double generation_rolling_friction = 0.0;  // -, ball-ball mu_r while the radii grow
  bool generation_servo = false;        // false: a fixed cavity; true: top plate servo-held at generation_stress
  double generation_stress = 5e3;       // Pa, servo target of the top plate while the radii grow
  double generation_servo_max_speed = 1.0;  // m/s, speed cap of that plate (it must keep up with the growth)
  double generation_porosity_tolerance = 0.005;  // -, the friction schedule ends within this of the target
  double generation_friction_reduction = 0.5;    // -, factor on the generation friction per schedule step
  // consolidation
  double vertical_stress = 200e3;       // Pa
  double stress_tolerance = 0.01;       // -, relative
  double servo_relaxation = 0.5;        // -, alpha_s
  double servo_max_speed = 0.05;        // m/s
  long settle_steps = 500;              // steps on target that end consolidation
  long consolidation_max_steps = 400000;
  // shear
  bool constant_volume = false;         // false: drained (constant vertical stress)
  bool both_plates_move = false;        // false: the bottom plate moves; true: each plate moves half, oppositely
  double shear_servo_max_speed = 0.0;   // m/s; 0: max(servo_max_speed, shear plate speed)
  std::vector<ShearLeg> legs{{0.0, 0.4}};
  double inertial_number = 1e-3;        // -, target; sets the shear rate unless strain_rate > 0
  double strain_rate = 0.0;             // 1/s, 0: from inertial_number
  // measurement and output
  double probe_radius_ratio = 0.8;      // -, measurement sphere radius / (H/2)
  int profile_bins = 12;                // height bins of the displacement profile
  double detection_gap_ratio = 0.05;    // -, gap / smallest ball diameter of a contact within detection
  double output_every_strain = 0.005;   // -, history row interval
  std::vector<double> fabric_strains{0.0, 0.2, 0.4};
  std::vector<double> snapshot_strains{0.0, 0.2, 0.4};
  long restart_every_steps = 20000;
  bool dilation_positive = true;        // sign of volumetric_strain in history.csv
  double progress_seconds = 5.0;        // s, wall-clock interval of progress lines

  double total_strain() const;
};

/// The schema of every key (section.name), with the study's 4D values as defaults.
io::Schema simple_shear_schema();

/// Key=value overrides of a preset ("1D", "2D", "4D"); InputError for another name.
std::vector<std::pair<std::string, std::string>> preset_values(const std::string& preset);

/// The typed configuration from validated values. Cross-key checks (e.g. leg lists of equal
/// length, d_max >= d_min) throw InputError naming the keys.
SimpleShearConfig simple_shear_config(const io::Config& config);

}  // namespace dem::lab
