#include <dem/control/servo_wall.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>

namespace dem {

namespace {

void require_target(const std::string& name, double stress) {
  require(std::isfinite(stress) && stress >= 0.0, name, stress, "finite and >= 0 (Pa, compressive)");
}

}  // namespace

void ServoSettings::validate(const std::string& where) const {
  require_target(where + ".target_stress", target_stress);
  require(relaxation > 0.0 && relaxation <= 1.0, where + ".relaxation", relaxation, "in (0, 1]");
  require(std::isfinite(max_speed) && max_speed > 0.0, where + ".max_speed", max_speed, "finite and > 0 (m/s)");
  require(gain_update_every >= 1, where + ".gain_update_every", gain_update_every, ">= 1 (steps)");
  require(std::isfinite(settle_tolerance) && settle_tolerance >= 0.0, where + ".settle_tolerance", settle_tolerance,
          "finite and >= 0 (relative to the target)");
  require(settle_steps >= 1, where + ".settle_steps", settle_steps, ">= 1 (steps)");
}

ServoWall::ServoWall(WallId wall, ServoSettings settings) : wall_(wall), settings_(settings) {
  settings_.validate("servo on wall " + std::to_string(wall));
  target_ = settings_.target_stress;
}

void ServoWall::set_target(double stress) {
  require_target("servo on wall " + std::to_string(wall_) + " target_stress", stress);
  target_of_time_ = nullptr;
  settings_.target_stress = stress;
  target_ = stress;
  steps_on_target_ = 0;
}

void ServoWall::resume_steps_on_target(std::int64_t steps) {
  require(steps >= 0, "servo on wall " + std::to_string(wall_) + " steps on target", steps, ">= 0");
  steps_on_target_ = steps;
}

void ServoWall::set_max_speed(double max_speed) {
  require(std::isfinite(max_speed) && max_speed > 0.0, "servo on wall " + std::to_string(wall_) + " max_speed", max_speed,
          "finite and > 0 (m/s)");
  settings_.max_speed = max_speed;
}

void ServoWall::set_target_function(std::function<double(double time)> target_of_time) {
  require(static_cast<bool>(target_of_time), "servo on wall " + std::to_string(wall_) + " target function", "empty",
          "a callable");
  target_of_time_ = std::move(target_of_time);
  steps_on_target_ = 0;
}

void ServoWall::operator()(World& world) {
  require(wall_ >= 0 && static_cast<std::size_t>(wall_) < world.walls().size(), "servo wall id", wall_,
          "an id of this world's walls, 0 <= id < " + std::to_string(world.walls().size()));
  Wall& wall = world.wall(wall_);
  const Vec3& n = wall.outward_normal;
  if (target_of_time_) {
    const double t = world.time();
    target_ = target_of_time_(t);
    require_target("servo on wall " + std::to_string(wall_) + " target function at t = " + std::to_string(t) + " s",
                   target_);
  }
  achieved_ = wall.normal_stress();
  normal_displacement_ = wall.displacement.dot(n);
  const double error = achieved_ - target_;  // Pa, > 0: too much stress, back off
  steps_on_target_ = std::abs(error) <= settings_.settle_tolerance * target_ ? steps_on_target_ + 1 : 0;

  // docs/model.md 5: G = alpha_s A / (sum k_n dt). With the stiffness of this step, the wall's own
  // motion changes the stress by -alpha_s * error. The gain is also recomputed whenever contacts
  // reappear, so that a wall arriving at the specimen never uses a stale or zero gain.
  const bool touching = wall.stiffness_sum > 0.0;
  if (touching && (!touched_last_step_ || calls_ % settings_.gain_update_every == 0))
    gain_ = settings_.relaxation * wall.area / (wall.stiffness_sum * world.time_step());
  touched_last_step_ = touching;
  ++calls_;

  double speed = 0.0;  // m/s along +n (outward, away from the specimen)
  if (holding_)
    speed = 0.0;
  else if (touching)
    speed = std::clamp(gain_ * error, -settings_.max_speed, settings_.max_speed);
  else if (target_ > 0.0)
    speed = -settings_.max_speed;  // nothing touches: approach the specimen
  normal_speed_ = speed;
  wall.velocity += (speed - wall.velocity.dot(n)) * n;
}

std::shared_ptr<ServoWall> add_servo_wall(World& world, WallId wall, ServoSettings settings) {
  require(wall >= 0 && static_cast<std::size_t>(wall) < world.walls().size(), "servo wall id", wall,
          "an id of this world's walls, 0 <= id < " + std::to_string(world.walls().size()));
  const Wall& w = world.wall(wall);
  require(w.area > 0.0, "wall '" + w.name + "' area (for the servo stress)", w.area, "> 0 (m^2)");
  auto servo = std::make_shared<ServoWall>(wall, settings);
  world.add_controller([servo](World& target_world) { (*servo)(target_world); });
  return servo;
}

}  // namespace dem
