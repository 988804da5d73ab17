// A specimen made in a periodic cell (boundary/periodic_cell.hpp), as a resumable part of a run
// (lab/toolkit/run.hpp): balls of a grading placed at random without overlap in a large cubic
// cell (a gas, seeded and deterministic), then compressed isotropically by the cell servo
// (control/cell_servo.hpp: the three normal stresses held at the target, the three shear stresses
// at zero) until every normal stress is within a tolerance of the target, the shear stresses
// within it of zero and the unbalanced force ratio low. The shear stresses are held rather than
// the shear rates kept zero: a packing of 3000 balls compressed at zero shear rates locked in
// shear stresses of 1 % of p, which no number of steps relaxed; held at zero, the cell shears a
// little and the stress is isotropic.
//
// The friction schedule: the ball-ball law with `compaction_friction` (and no rolling friction)
// while the cell compresses; 0 makes the densest specimen, the material's friction a loose one.
// use_material_law() then puts the material's law in, keeping the contacts and their history.
//
// The part keeps its stage under "specimen_stage" and "specimen_stage_start_step" in the run's
// restart files; the end test is read between chunks of steps from the World alone, so a run
// killed while compressing resumes to the same steps.
//
//   PeriodicSpecimen specimen(run, settings);     // a placeholder cell, the servo, the laws
//   specimen.run([&] { /* a history row? */ });   // what remains of placing and compressing
//   specimen.use_material_law(true);
//   specimen.servo().set_rate(dem::CellComponent::zz, -1.0);  // the test's own loading
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <dem/control/cell_servo.hpp>
#include <dem/lab/toolkit/contact_config.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/run.hpp>

namespace dem::lab {

struct PeriodicSpecimenSettings {
  Grading grading;                      // diameters (grading.scale applied)
  ContactTypeConfig ball_ball;          // the material's law
  double density = 2650.0;              // kg/m^3
  long balls = 300;                     // -, in the cell
  std::uint64_t seed = 1;               // -, of the diameters and the positions
  double initial_solid_fraction = 0.3;  // -, of the gas the balls are placed in
  double stress = 100e3;                // Pa, isotropic target (compression positive)
  double compaction_friction = 0.0;     // -, ball-ball friction while compressing
  double tolerance = 0.005;             // -, relative error of each stress that ends the compression
  double equilibrium_ratio = 1e-2;      // -, unbalanced force ratio that ends it
  double max_rate = 10.0;               // 1/s, cap on the servo's normal rates
  long max_steps = 400000;              // steps after which the compression ends with a warning
  std::string section = "specimen";     // names the keys above in errors ("<section>.balls")
};

/// Balls of `settings.grading` at random positions without overlap (periodic distances) in a
/// cubic cell whose edge gives `initial_solid_fraction`; sets the World's cell. InputError when
/// a ball finds no place within many trials (a solid fraction too high for random placing).
void fill_periodic_cell(World& world, const PeriodicSpecimenSettings& settings);

/// Whether the cell stress of the last step is the isotropic `stress` (Pa, compression positive):
/// each normal stress within tolerance x stress of it, each shear stress within tolerance x
/// stress of zero, and the unbalanced force ratio below `equilibrium_ratio`.
bool isotropic_state_reached(const World& world, double stress, double tolerance, double equilibrium_ratio);

class PeriodicSpecimen {
 public:
  /// Sets a placeholder cell (a restart file or the placing replaces it), adds the cell servo
  /// and the compaction law to the run's World, and keeps the part's stage in `run`.
  PeriodicSpecimen(Run& run, PeriodicSpecimenSettings settings);
  /// Places the balls (fill_periodic_cell) if not done.
  void place();
  /// Places the balls if not done, then compresses until isotropic_state_reached (checked every
  /// 100 steps; `after_chunk` runs after each chunk, for a protocol's history rows).
  void run(const std::function<void()>& after_chunk = {});
  bool made() const { return stage_ == Stage::Done; }
  bool placed() const { return stage_ != Stage::Empty; }
  /// The material's ball-ball law (keeping the contacts: a stage change; or not: a restart).
  void use_material_law(bool keep_contacts);
  CellServo& servo() { return *servo_; }
  const PeriodicSpecimenSettings& settings() const { return settings_; }

 private:
  enum class Stage : int { Empty = 0, Compressing = 1, Done = 2 };
  Run& run_;
  PeriodicSpecimenSettings settings_;
  std::shared_ptr<CellServo> servo_;
  Stage stage_ = Stage::Empty;
  std::int64_t stage_start_step_ = 0;
};

}  // namespace dem::lab
