#include <dem/lab/toolkit/shear_leg.hpp>

#include <cmath>

namespace dem::lab {

Vec3 horizontal_direction(double deg) {
  const double a = deg * pi / 180.0;
  return Vec3(std::cos(a), std::sin(a), 0.0);
}

Vec3 ShearLegMotion::direction() const { return horizontal_direction(direction_deg); }

void start_shear_leg(World& world, const ShearCell& cell, ServoWall& servo, const ShearLegMotion& motion) {
  const double share = (motion.moving_plate == MovingPlate::Both) ? 0.5 : 1.0;
  Wall& bottom = world.wall(cell.bottom);
  bottom.velocity = share * motion.speed * motion.direction();
  Wall& top = world.wall(cell.top);
  const Vec3 top_horizontal = (share - 1.0) * motion.speed * motion.direction();
  top.velocity.x() = top_horizontal.x();
  top.velocity.y() = top_horizontal.y();
  servo.hold_position(motion.mode == ShearMode::ConstantVolume);
  servo.set_max_speed(motion.servo_max_speed);
}

void stop_shear(World& world, const ShearCell& cell) {
  world.wall(cell.bottom).velocity.setZero();
  world.wall(cell.top).velocity.x() = world.wall(cell.top).velocity.y() = 0.0;
}

Vec3 plate_offset(const World& world, const ShearCell& cell) {
  Vec3 offset = world.wall(cell.bottom).displacement - world.wall(cell.top).displacement;
  offset.z() = 0.0;
  return offset;
}

ShearPath::ShearPath(const World& world, const ShearCell& cell, double height)
    : height_(height), strain_(0.0), offset_(plate_offset(world, cell)) {}

ShearPath::ShearPath(double height, double strain, const Vec3& offset) : height_(height), strain_(strain), offset_(offset) {}

double ShearPath::advance(const World& world, const ShearCell& cell) {
  const Vec3 offset = plate_offset(world, cell);
  strain_ += (offset - offset_).norm() / height_;
  offset_ = offset;
  return strain_;
}

}  // namespace dem::lab
