#include <dem/lab/toolkit/horizontal_drive.hpp>

#include <cmath>
#include <limits>
#include <utility>

#include <dem/core/errors.hpp>

namespace dem::lab {

namespace {

Vec3 horizontal(Vec3 v) {
  v.z() = 0.0;
  return v;
}

}  // namespace

HorizontalDrive::HorizontalDrive(const HorizontalDriveSettings& s) : settings_(s) {
  require(s.top >= 0 && s.bottom >= 0 && s.top != s.bottom, "horizontal drive plates", s.top, "two different walls");
  require(std::isfinite(s.area) && s.area > 0, "horizontal drive area", s.area, "> 0 (m^2)");
  require(std::isfinite(s.height) && s.height > 0, "horizontal drive height", s.height, "> 0 (m)");
  require(std::isfinite(s.stiffness_ratio) && s.stiffness_ratio > 0, "horizontal drive stiffness_ratio", s.stiffness_ratio, "> 0");
  require(s.relaxation > 0 && s.relaxation <= 1, "horizontal drive relaxation", s.relaxation, "in (0, 1]");
  require(std::isfinite(s.max_speed) && s.max_speed > 0, "horizontal drive max_speed", s.max_speed, "> 0 (m/s)");
}

void HorizontalDrive::servo_stress(std::function<Vec3(double)> target, std::int64_t start_step, double steps_per_cycle) {
  require(steps_per_cycle > 0, "horizontal drive steps_per_cycle", steps_per_cycle, "> 0");
  mode_ = Mode::StressServo, target_ = std::move(target), start_step_ = start_step, steps_per_cycle_ = steps_per_cycle;
}

void HorizontalDrive::follow_strain(std::function<Vec3(double)> target, std::int64_t start_step, double steps_per_cycle) {
  require(steps_per_cycle > 0, "horizontal drive steps_per_cycle", steps_per_cycle, "> 0");
  mode_ = Mode::StrainPath, target_ = std::move(target), start_step_ = start_step, steps_per_cycle_ = steps_per_cycle;
}

void HorizontalDrive::move_bottom(const Vec3& velocity) {
  mode_ = Mode::Monotonic;
  bottom_velocity_ = horizontal(velocity);
}

Vec3 HorizontalDrive::target(double n) const {
  if (mode_ == Mode::StressServo || mode_ == Mode::StrainPath) return target_(n);
  return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

void HorizontalDrive::operator()(World& w) {
  if (mode_ == Mode::Idle) return;
  Wall& top = w.wall(settings_.top);
  Wall& bottom = w.wall(settings_.bottom);
  const double dt = w.time_step();
  const double n_next = cycles_at(w.step_count() + 1);
  const Vec3 tau = horizontal(top.force) / settings_.area;
  Vec3 v_top = Vec3::Zero(), v_bottom = Vec3::Zero();
  if (mode_ == Mode::StressServo) {
    // More stress along d needs the top plate to move along -d (gamma grows).
    const double shear_stiffness = top.stiffness_sum / settings_.stiffness_ratio;
    if (shear_stiffness > 0.0) {
      const double gain = settings_.relaxation * settings_.area / (shear_stiffness * dt);
      v_top = -gain * (target_(n_next) - tau);
      if (v_top.norm() > settings_.max_speed) v_top *= settings_.max_speed / v_top.norm();
    }
  } else if (mode_ == Mode::StrainPath) {
    const Vec3 now = horizontal(bottom.displacement - top.displacement);
    v_bottom = (target_(n_next) * settings_.height - now) / dt;
  } else {
    v_bottom = bottom_velocity_;
  }
  top.velocity.x() = v_top.x(), top.velocity.y() = v_top.y();
  bottom.velocity.x() = v_bottom.x(), bottom.velocity.y() = v_bottom.y();
  work_ += tau.dot(v_bottom - v_top) * dt / settings_.height;
}

}  // namespace dem::lab
