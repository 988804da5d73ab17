// Servo-controlled loading wall (docs/model.md 5): moves one Wall along its outward normal so that
// the compressive normal stress on it approaches a target, the way PFC's triaxial and biaxial
// examples drive their platens.
//
// Why a proportional law with a stiffness-based gain rather than a PID or a prescribed velocity:
// with G = alpha_s A / (sum k_n dt), one step of wall motion changes the wall stress by exactly
// alpha_s times the current error if the balls touching it stood still. The loop is then stable
// and overshoot-free for any packing stiffness (0 < alpha_s <= 1), needs no tuning, and its speed
// follows the specimen as contacts form and break. The cap max_speed keeps the wall from ploughing
// into a loose specimen; without contacts the wall approaches the specimen at that cap.
//
// Only the normal component of Wall::velocity is owned by the servo: a tangential velocity
// set by the user (simple shear of a platen) is left as it is. The servo runs as a World
// controller, i.e. every step after the contact forces and before integration, so it always acts
// on the forces of the current step.
//
// Typical use:
//   auto top = dem::add_servo_wall(world, top_id, {.target_stress = 200e3, .max_speed = 0.05});
//   world.run_until([&](const dem::World&) { return top->settled(); }, 100, 1'000'000);
//   top->hold_position(true);   // constant-volume shear from here on
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <dem/boundary/wall.hpp>

namespace dem {

class World;

/// Settings of one servo wall. SI units; stresses are compressive-positive.
struct ServoSettings {
  double target_stress = 0.0;      // Pa, compressive normal stress to hold, >= 0
  double relaxation = 0.5;         // -, alpha_s in (0, 1]: fraction of the stress error removed per step
  double max_speed = 0.0;          // m/s, cap on the normal wall speed, > 0 (required)
  int gain_update_every = 1;       // steps, >= 1: the gain is recomputed this often
  double settle_tolerance = 0.01;  // -, |stress - target| <= this x target counts as on target, >= 0
  int settle_steps = 100;          // steps, >= 1: consecutive on-target steps for settled()

  /// Throws InputError naming `where`.<key>, the value and the allowed range.
  void validate(const std::string& where = "servo") const;
};

/// Controller holding a target normal stress on one facet wall. Register it with add_servo_wall
/// (or World::add_controller); the World then calls operator() once per step.
class ServoWall {
 public:
  /// Validates the settings (InputError names the key). The wall id is checked on first use.
  ServoWall(WallId wall, ServoSettings settings);

  /// One control step: reads the wall's stress and contact stiffness from the current step and
  /// sets the normal component of its velocity (m/s).
  void operator()(World& world);

  /// Sets a constant target stress (Pa, >= 0), replacing any target function. The settled
  /// count restarts.
  void set_target(double stress);
  /// Target stress (Pa) as a function of the world time (s), evaluated every step; it must return
  /// a finite value >= 0 (else InputError at that step). The settled count restarts.
  void set_target_function(std::function<double(double time)> target_of_time);
  /// Changes the speed cap (m/s, finite and > 0): a shearing specimen may dilate faster than a
  /// consolidating one settles.
  void set_max_speed(double max_speed);
  /// true: the normal wall speed is held at 0 (constant volume / fixed height); false: stress
  /// control. Switchable at any time; the tangential velocity is kept in both modes.
  void hold_position(bool hold) { holding_ = hold; }
  bool holding_position() const { return holding_; }

  /// Target stress of the last step (or the constant target before the first step), Pa.
  double target() const { return target_; }
  /// Compressive normal stress the wall carried in the last step, Pa.
  double achieved_stress() const { return achieved_; }
  /// Wall displacement along its outward normal since it was added, at which achieved_stress()
  /// was measured, m (negative: moved into the specimen).
  double normal_displacement() const { return normal_displacement_; }
  /// Normal speed the servo set in the last step, m/s along the outward normal.
  double normal_speed() const { return normal_speed_; }
  /// Gain G = alpha_s A / (sum k_n dt) in use, m/(s Pa); 0 before the wall first touched a ball.
  double gain() const { return gain_; }
  /// Consecutive steps, up to the last one, with |stress - target| <= settle_tolerance x target.
  std::int64_t steps_on_target() const { return steps_on_target_; }
  /// true once the stress has been on target for settle_steps consecutive steps (ends a
  /// consolidation stage).
  bool settled() const { return steps_on_target_ >= settings_.settle_steps; }
  /// Continues the count of a servo restored from a restart file (>= 0).
  void resume_steps_on_target(std::int64_t steps);

  WallId wall() const { return wall_; }
  const ServoSettings& settings() const { return settings_; }

 private:
  WallId wall_;
  ServoSettings settings_;
  std::function<double(double)> target_of_time_;
  bool holding_ = false;
  double target_ = 0.0;               // Pa
  double achieved_ = 0.0;             // Pa
  double normal_displacement_ = 0.0;  // m
  double normal_speed_ = 0.0;         // m/s
  double gain_ = 0.0;                 // m/(s Pa)
  std::int64_t calls_ = 0;
  bool touched_last_step_ = false;
  std::int64_t steps_on_target_ = 0;
};

/// Creates a servo on wall `wall` of `world` and registers it as a controller. Keep the returned
/// pointer to change the target or mode and to read the results; the World shares ownership.
/// Throws InputError for a wall id out of range, a wall with a non-positive area, or bad settings.
std::shared_ptr<ServoWall> add_servo_wall(World& world, WallId wall, ServoSettings settings);

}  // namespace dem
