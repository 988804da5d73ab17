// What a contact law sees of a contact, computed once by the engine and passed by argument
// (LAMMPS's GranularModel computes the same record but shares it through public fields).
//
// Conventions (docs/model.md section 0): piece 1 is always a ball; piece 2 is a ball, a facet or a
// pebble. The normal points from piece 1 to piece 2. The law returns the force and the pure
// moment that piece 2 receives; piece 1 receives the opposite.
#pragma once

#include <cstdint>
#include <limits>

#include <dem/base/math.hpp>

namespace dem {

/// Contact types with their own contact-model parameters (the study's Table 1 rows).
enum class ContactKind : std::uint8_t { BallBall = 0, BallFacet = 1, BallPebble = 2 };
inline constexpr int contact_kind_count = 3;

inline const char* to_string(ContactKind kind) {
  switch (kind) {
    case ContactKind::BallBall: return "ball-ball";
    case ContactKind::BallFacet: return "ball-facet";
    case ContactKind::BallPebble: return "ball-pebble";
  }
  return "?";
}

struct ContactKinematics {
  Vec3 normal;                     // unit, from piece 1 to piece 2
  double overlap;                  // m, positive when the surfaces interpenetrate
  Vec3 relative_velocity;          // m/s, of piece 2 relative to piece 1 at the contact point
  Vec3 relative_angular_velocity;  // rad/s, w2 - w1
  double radius_1;                 // m, ball
  double radius_2;                 // m, ball or pebble; 0 for a facet (rigid, flat)
  double effective_radius;         // m, R1 R2/(R1 + R2); R1 for a facet
  double effective_mass;           // kg, m1 m2/(m1 + m2); m1 for a facet
  double dt;                       // s, time step
  ContactKind kind;
};

/// What a law returns. `force` and `moment` act on piece 2.
struct ContactForce {
  Vec3 force = Vec3::Zero();   // N
  Vec3 moment = Vec3::Zero();  // N m, pure moment (rolling resistance), not the moment of `force`
  double normal_force = 0.0;   // N, elastic normal force, compression positive (for stress and fabric)
  double normal_stiffness = 0.0;  // N/m, used by servo gains and time-step estimates
};

/// Stiffnesses of a contact, for the stable time step (docs/model.md 3.2).
struct ContactStiffness {
  double normal = 0.0;   // N/m
  double shear = 0.0;    // N/m
  double rolling = 0.0;  // N m/rad
};

}  // namespace dem
