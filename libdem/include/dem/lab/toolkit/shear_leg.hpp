// A leg of simple shear as a part of a protocol: the plates of a shear cell (lab/toolkit/shear_cell.hpp)
// move horizontally against each other along one direction, while the top plate's servo keeps the
// vertical stress (drained) or the height (constant volume). The strain of a path of legs is the
// accumulated horizontal displacement of the bottom plate relative to the top one over the
// consolidated height (docs/model.md 8).
#pragma once

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>

namespace dem::lab {

enum class ShearMode { Drained, ConstantVolume };  // drained: constant vertical stress (servo)
enum class MovingPlate { Bottom, Both };           // both: each plate moves half, oppositely
/// What local damping measures velocities against while the plates shear: the fixed frame (PFC's),
/// or the plates' affine field (plate_damping_frame in lab/toolkit/shear_cell.hpp).
enum class ShearDampingFrame { Fixed, Plates };

/// One leg of the shear path: the bottom plate moves along `direction_deg` (from +x towards +y)
/// by `strain` x the consolidated height.
struct ShearLeg {
  double direction_deg = 0.0;  // deg
  double strain = 0.0;         // -, shear strain increment of this leg
};

/// The unit horizontal vector at `deg` degrees from +x towards +y.
Vec3 horizontal_direction(double deg);

/// How the plates move during one leg.
struct ShearLegMotion {
  double direction_deg = 0.0;  // deg, of the bottom plate's motion relative to the top, from +x towards +y
  double speed = 0.0;          // m/s, of the bottom plate relative to the top
  ShearMode mode = ShearMode::Drained;
  MovingPlate moving_plate = MovingPlate::Bottom;
  double servo_max_speed = 0.05;  // m/s, cap of the top plate's vertical servo while shearing

  /// The unit horizontal vector of direction_deg.
  Vec3 direction() const;
};

/// Sets the plates' horizontal velocities for the leg and the servo's mode and speed cap.
void start_shear_leg(World& world, const ShearCell& cell, ServoWall& servo, const ShearLegMotion& motion);

/// Stops the plates horizontally (the servo keeps its mode).
void stop_shear(World& world, const ShearCell& cell);

/// Horizontal displacement of the bottom plate relative to the top one (m, z = 0).
Vec3 plate_offset(const World& world, const ShearCell& cell);

/// The strain of a path of legs: |d offset| / height summed chunk by chunk, so that a path that
/// turns counts every leg's strain.
class ShearPath {
 public:
  /// From the plates' offset now; `height` (m) is the consolidated height.
  ShearPath(const World& world, const ShearCell& cell, double height);
  /// A path resumed from a restart file: the strain so far and the offset it was measured at.
  ShearPath(double height, double strain, const Vec3& offset);
  /// No path yet (strain 0): give it one of the constructors above before advance().
  ShearPath() : ShearPath(0.0, 0.0, Vec3::Zero()) {}
  /// Adds the offset change since the last call (or the start); returns the strain so far.
  double advance(const World& world, const ShearCell& cell);
  double strain() const { return strain_; }
  const Vec3& offset() const { return offset_; }  // m, at the last advance
  double height() const { return height_; }

 private:
  double height_;   // m
  double strain_;   // -
  Vec3 offset_;     // m
};

}  // namespace dem::lab
