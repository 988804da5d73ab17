// Clumps: rigid bodies made of spherical pebbles (PFC clumps, docs/model.md section 4). The pebbles
// are the surface that balls touch (ball-pebble contacts with their own contact-model
// parameters); the clump carries the mass, the inertia tensor and the per-degree-of-freedom
// fixity. Pebbles of one clump never touch each other, and by default pebbles of different clumps
// do not interact either (rings of a simple-shear stack slide on each other freely).
#pragma once

#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>
#include <dem/core/particles.hpp>

namespace dem {

using ClumpId = std::int32_t;

struct PebbleSpec {
  Vec3 position = Vec3::Zero();  // m, world frame
  double radius = 0.0;           // m
};

/// Input for one clump. Mass properties are given (e.g. those of the solid ring a pebble ring
/// stands for) or computed from the pebbles by `with_pebble_mass`.
struct ClumpSpec {
  std::vector<PebbleSpec> pebbles;
  double mass = 0.0;                    // kg
  Vec3 centre_of_mass = Vec3::Zero();   // m
  Mat3 inertia = Mat3::Zero();          // kg m^2, about the centre of mass, world axes
  Vec3 velocity = Vec3::Zero();         // m/s
  Vec3 angular_velocity = Vec3::Zero(); // rad/s
  std::uint8_t fixed = 0;               // Dof bits
  int group = 0;

  /// Mass, centre and inertia of the pebbles as separate solid spheres at `density` (kg/m^3);
  /// overlapping pebbles count their common volume twice.
  ClumpSpec& with_pebble_mass(double density);
  void validate(const std::string& where) const;
};

struct Clump {
  double mass = 0.0;                   // kg
  Vec3 x = Vec3::Zero();               // m, centre of mass
  Vec3 v = Vec3::Zero();               // m/s
  Vec3 w = Vec3::Zero();               // rad/s, world frame
  Quat orientation = Quat::Identity(); // body -> world
  Mat3 inertia_body = Mat3::Identity();      // kg m^2, about the centre, body axes
  Mat3 inv_inertia_body = Mat3::Identity();  // 1/(kg m^2)
  std::uint8_t fixed = 0;              // Dof bits
  std::vector<ParticleId> pebbles;     // stable ids in the ParticleStore
  std::vector<Vec3> pebble_offsets;    // m, body frame, from the centre of mass
  Vec3 force = Vec3::Zero();           // N, from contacts in the last step
  Vec3 torque = Vec3::Zero();          // N m, about the centre, from contacts in the last step
  Vec3 applied_force = Vec3::Zero();   // N, set by the user, kept between steps
  Vec3 applied_torque = Vec3::Zero();  // N m
  Vec3 displacement = Vec3::Zero();    // m, since creation

  Mat3 inertia_world() const {
    const Mat3 r = orientation.toRotationMatrix();
    return r * inertia_body * r.transpose();
  }
};

}  // namespace dem
