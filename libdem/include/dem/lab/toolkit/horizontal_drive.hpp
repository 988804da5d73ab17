// The plates' horizontal motion in a cyclic or monotonic simple-shear stage, as a World controller
// (docs/cyclic-shear.md). Shear strain gamma = (u_bottom - u_top)_horizontal / H and shear stress
// tau = the sand's horizontal force on the top plate / area.
//
// - Stress control moves the top plate by a servo on its own horizontal force, the rule of the
//   vertical servo (control/servo_wall.hpp) turned sideways: v = -G (tau_target - tau) with
//   G = relaxation A / (sum k_s dt), sum k_s the plate contacts' normal stiffness over
//   stiffness_ratio, capped at max_speed: each step removes that fraction of the stress error if
//   the balls stood still.
// - Strain control moves the bottom plate so that gamma is exactly on its target at every step.
// - Monotonic moves the bottom plate at a constant velocity.
//
// Targets are functions of the cycles N since the stage began, counted in steps (steps_per_cycle),
// at the end of the step being taken. The drive sets only the plates' x and y velocities, so it
// runs after the vertical servo and the rings. It adds each step's work tau . d gamma (J/m^3).
//
//   auto drive = std::make_shared<HorizontalDrive>(settings);
//   world.add_controller([drive](World& w) { (*drive)(w); });
//   drive->servo_stress([&](double n) { return csr * sigma_v0 * path.at(n); }, world.step_count(), steps_per_cycle);
#pragma once

#include <cstdint>
#include <functional>

#include <dem/core/world.hpp>

namespace dem::lab {

struct HorizontalDriveSettings {
  WallId top = -1, bottom = -1;  // the plates
  double area = 0.0;             // m^2, over which the plate force is a stress
  double height = 0.0;           // m, H of gamma (the consolidated height)
  double stiffness_ratio = 1.0;  // -, the plate contacts' kn / ks
  double relaxation = 1.0;       // -, in (0, 1]: fraction of the stress error removed per step
  double max_speed = 0.0;        // m/s, of the top plate under stress control
};

class HorizontalDrive {
 public:
  enum class Mode { Idle, StressServo, StrainPath, Monotonic };

  /// InputError for missing plates or a non-positive area, height, ratio or speed.
  explicit HorizontalDrive(const HorizontalDriveSettings& settings);

  /// Plates at rest horizontally from the next step on.
  void hold() { mode_ = Mode::Idle; }
  /// Stress control from `start_step` on: target(N) in Pa, horizontal.
  void servo_stress(std::function<Vec3(double)> target, std::int64_t start_step, double steps_per_cycle);
  /// Strain control from `start_step` on: target(N) a horizontal shear strain.
  void follow_strain(std::function<Vec3(double)> target, std::int64_t start_step, double steps_per_cycle);
  /// The bottom plate at `velocity` (m/s, horizontal), the top plate at rest.
  void move_bottom(const Vec3& velocity);

  /// One control step: sets the plates' horizontal velocities and adds the step's work.
  void operator()(World& world);

  Mode mode() const { return mode_; }
  /// N since the stage began, `step` steps into the run.
  double cycles_at(std::int64_t step) const { return static_cast<double>(step - start_step_) / steps_per_cycle_; }
  /// The target at the cycles `n` (Pa or -), NaN when neither stress nor strain is controlled.
  Vec3 target(double n) const;
  double work() const { return work_; }  // J/m^3, since the last reset_work()
  void reset_work() { work_ = 0.0; }
  /// The work of a stage resumed from a restart file (J/m^3).
  void resume_work(double work) { work_ = work; }
  const HorizontalDriveSettings& settings() const { return settings_; }

 private:
  HorizontalDriveSettings settings_;
  Mode mode_ = Mode::Idle;
  std::int64_t start_step_ = 0;
  double steps_per_cycle_ = 1.0;
  std::function<Vec3(double)> target_;
  Vec3 bottom_velocity_ = Vec3::Zero();  // m/s, Monotonic
  double work_ = 0.0;                    // J/m^3
};

}  // namespace dem::lab
