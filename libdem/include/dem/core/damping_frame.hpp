// The velocity field that local damping measures velocities against (docs/model.md 3.1).
//
// PFC's local damping opposes each degree of freedom's velocity in the fixed frame. In a specimen
// that flows, the fixed frame is not at rest with the material: a layer that moves with a plate is
// braked by a force of about alpha |F| against its motion even when it moves steadily, and a
// simple-shear specimen then carries more shear stress next to the moving plate than next to the
// held one. Damping against the material's mean flow removes that body force: a steady flow is
// not braked, only the fluctuations about it are, and which plate moves no longer matters.
#pragma once

#include <dem/core/math.hpp>

namespace dem {

/// A velocity field linear in height, v(x) = velocity + (x.z - height) velocity_gradient: a
/// uniform translation plus simple shear (and vertical stretch) of horizontal layers. The default
/// is the fixed frame (at rest everywhere), PFC's.
struct DampingFrame {
  Vec3 velocity = Vec3::Zero();           // m/s, of the field at z = height
  double height = 0.0;                    // m
  Vec3 velocity_gradient = Vec3::Zero();  // 1/s, dv/dz

  bool at_rest() const { return velocity.isZero(0.0) && velocity_gradient.isZero(0.0); }
  /// The field's velocity at x (m/s).
  Vec3 velocity_at(const Vec3& x) const { return velocity + (x.z() - height) * velocity_gradient; }
  /// Half the field's vorticity (rad/s): the mean spin of material that follows the field, which
  /// spins are damped against. The vertical gradient (g_z, a stretch) turns nothing.
  Vec3 spin() const { return 0.5 * Vec3(-velocity_gradient.y(), velocity_gradient.x(), 0.0); }
};

}  // namespace dem
