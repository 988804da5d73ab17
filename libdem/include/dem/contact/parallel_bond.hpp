// The linear parallel bond (Potyondy & Cundall 2004, "A bonded-particle model for rock", IJRMMS
// 41; PFC's `linearpbond`; docs/cementation.md): a disc of cement between two balls that carries
// force and moments, beside (never in place of) the contact law of the pair, until it breaks.
//
// The disc: radius Rb = lambda min(R1, R2), area A = pi Rb^2, moments of area I = pi Rb^4 / 4
// (bending) and J = pi Rb^4 / 2 (twisting); normal and shear stiffness per area kn, ks (Pa/m).
// Incremental, from the relative motion of piece 2 to piece 1 at the bond point over one step
// (P&C 2004 eqs. 11-14, in PFC's sign convention, tension positive):
//   dFn = kn A d(delta_n)      dFs = -ks A d(delta_s)
//   dMt = -ks J d(theta_t)     dMb = -kn I d(theta_b)
// with the shear force and bending moment first rotated into the current bond plane (keeping
// their length, as the contact laws rotate their tangential history). Edge stresses (eq. 15):
//   sigma = Fn / A + |Mb| Rb / I     (tension positive)
//   tau   = |Fs| / A + |Mt| Rb / J
// The bond breaks in tension when sigma > sigma_c, else in shear when tau > c - (Fn / A) tan(phi)
// (PFC's shear strength: compression, Fn < 0, strengthens it). A broken bond carries nothing more.
//
// Plain data and static functions, as the contact laws: the engine's bond loop (core) reads the
// pieces' motion of a block of bonds, calls update_lanes() for each and adds the results to the pieces.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/base/math.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>

namespace dem {

/// How a bond ended; stored per bond (BondStore::status).
enum class BondStatus : std::uint8_t { intact = 0, broken_tension = 1, broken_shear = 2 };

inline const char* to_string(BondStatus s) {
  switch (s) {
    case BondStatus::intact: return "intact";
    case BondStatus::broken_tension: return "broken in tension";
    case BondStatus::broken_shear: return "broken in shear";
  }
  return "?";
}

struct ParallelBondLaw {
  /// One bond's parameters (each bond has its own: strengths are drawn per bond).
  struct Params {
    double radius = 0.0;            // m, Rb = lambda min(R1, R2)
    double normal_stiffness = 0.0;  // Pa/m, kn, per area
    double shear_stiffness = 0.0;   // Pa/m, ks, per area
    double tensile_strength = 0.0;  // Pa, sigma_c
    double cohesion = 0.0;          // Pa, c
    double friction_angle = 0.0;    // rad, phi, in [0, pi/2)

    void validate(const std::string& where) const {
      require_positive(where + ".radius", radius);
      require_positive(where + ".normal_stiffness", normal_stiffness);
      require_positive(where + ".shear_stiffness", shear_stiffness);
      require_non_negative(where + ".tensile_strength", tensile_strength);
      require_non_negative(where + ".cohesion", cohesion);
      require(friction_angle >= 0.0 && friction_angle < 0.5 * pi, where + ".friction_angle", friction_angle,
              "in [0, pi/2) rad");
    }
    double area() const { return pi * radius * radius; }                              // m^2
    double bending_inertia() const { return 0.25 * pi * radius * radius * radius * radius; }  // m^4, I
    double polar_inertia() const { return 0.5 * pi * radius * radius * radius * radius; }     // m^4, J
  };

  /// What the bond carries, in the bond's frame at the last step.
  struct State {
    double normal_force = 0.0;             // N, Fn, tension positive
    Vec3 shear_force = Vec3::Zero();       // N, Fs on piece 2, in the bond plane
    double twist_moment = 0.0;             // N m, Mt on piece 2 about the normal
    Vec3 bend_moment = Vec3::Zero();       // N m, Mb on piece 2, in the bond plane
  };

  /// The relative motion the bond sees over one step.
  struct Motion {
    Vec3 normal;                     // unit, from piece 1 to piece 2
    Vec3 relative_velocity;          // m/s, of piece 2 relative to piece 1 at the bond point
    Vec3 relative_angular_velocity;  // rad/s, w2 - w1
    double dt;                       // s
  };

  /// Advances the bond by one step and checks its strength; returns intact or how it broke (then
  /// the State is zero and `at_break`, if given, receives the loads that broke it).
  static BondStatus update(const Params& p, const Motion& m, State& s, State* at_break = nullptr) {
    LaneState l{s.normal_force, lane(s.shear_force), s.twist_moment, lane(s.bend_moment)};
    const auto out = static_cast<BondStatus>(update_lanes(p, tan_friction(p.friction_angle), lane(m.normal), lane(m.relative_velocity),
                                                          lane(m.relative_angular_velocity), m.dt, l));
    s = {l.normal_force, to_vec3(l.shear_force), l.twist_moment, to_vec3(l.bend_moment)};
    if (out != BondStatus::intact) {
      if (at_break) *at_break = s;
      s = State{};
    }
    return out;
  }

  /// State in plain doubles (contact/lanes.hpp), for update_lanes.
  struct LaneState {
    double normal_force;
    Lane3 shear_force;
    double twist_moment;
    Lane3 bend_moment;
  };

  /// update() for the engine's SIMD bond blocks: the bond's loads advanced by one step over the
  /// relative motion (unit `normal`, velocity and angular velocity of piece 2 relative to piece 1)
  /// in plain doubles and without branches, the loads kept even when it breaks; returns the
  /// BondStatus as an int. `tan_phi` is tan_friction(p.friction_angle). update() calls it: one
  /// formula, the same bits in lanes as one bond at a time.
  DEM_HOT_INLINE static int update_lanes(const Params& p, double tan_phi, const Lane3& normal,
                                         const Lane3& relative_velocity, const Lane3& relative_angular_velocity,
                                         double dt, LaneState& s) {
    const Lane3& n = normal;
    s.shear_force = rotate_into_plane(s.shear_force, n);
    s.bend_moment = rotate_into_plane(s.bend_moment, n);
    const double normal_speed = dot(relative_velocity, n);  // > 0 separating
    const Lane3 shear_velocity = relative_velocity - normal_speed * n;
    const double twist_rate = dot(relative_angular_velocity, n);
    const Lane3 bend_rate = relative_angular_velocity - twist_rate * n;
    const double area = p.area(), inertia = p.bending_inertia(), polar = p.polar_inertia();
    s.normal_force += p.normal_stiffness * area * (normal_speed * dt);
    s.shear_force = s.shear_force - (p.shear_stiffness * area) * (dt * shear_velocity);
    s.twist_moment -= p.shear_stiffness * polar * (twist_rate * dt);
    s.bend_moment = s.bend_moment - (p.normal_stiffness * inertia) * (dt * bend_rate);
    // the stresses at the disc's edge (tension positive) against the strengths
    const double tensile = s.normal_force / area + std::sqrt(squared_norm(s.bend_moment)) * p.radius / inertia;
    const double shear = std::sqrt(squared_norm(s.shear_force)) / area + std::abs(s.twist_moment) * p.radius / polar;
    // phi = 0, the usual cement: c - (Fn / A) x 0 is c (Fn is finite); selected, not branched on
    const double shear_strength =
        std::max(0.0, tan_phi == 0.0 ? p.cohesion : p.cohesion - s.normal_force / area * tan_phi);
    const int broken_in_shear = shear > shear_strength ? static_cast<int>(BondStatus::broken_shear) : 0;
    return tensile > p.tensile_strength ? static_cast<int>(BondStatus::broken_tension) : broken_in_shear;
  }

  /// tan(phi) of a friction angle (rad) for update_lanes: 0 for phi = 0, the usual cement, without
  /// calling tan().
  static double tan_friction(double friction_angle) { return friction_angle == 0.0 ? 0.0 : std::tan(friction_angle); }

  /// The elastic energy the bond stores with loads `s`, J (PFC's pb strain energy):
  /// Fn^2 / (2 kn A) + |Fs|^2 / (2 ks A) + Mt^2 / (2 ks J) + |Mb|^2 / (2 kn I).
  static double strain_energy(const Params& p, const State& s) {
    const double area = p.area();
    return s.normal_force * s.normal_force / (2.0 * p.normal_stiffness * area) +
           s.shear_force.squaredNorm() / (2.0 * p.shear_stiffness * area) +
           s.twist_moment * s.twist_moment / (2.0 * p.shear_stiffness * p.polar_inertia()) +
           s.bend_moment.squaredNorm() / (2.0 * p.normal_stiffness * p.bending_inertia());
  }

  /// The force on piece 2 (N); piece 1 gets the opposite. Tension pulls piece 2 back to piece 1.
  DEM_HOT_INLINE static Lane3 force(const LaneState& s, const Lane3& normal) {
    return (-s.normal_force) * normal + s.shear_force;
  }
  /// The pure moment on piece 2 (N m); piece 1 gets the opposite.
  DEM_HOT_INLINE static Lane3 moment(const LaneState& s, const Lane3& normal) {
    return s.twist_moment * normal + s.bend_moment;
  }

  /// The bond's stiffness on its pieces, for the stable time step (docs/model.md 3.2): kn A and
  /// ks A on translation; on rotation the larger of bending kn I and twisting ks J, plus the shear
  /// spring at the lever `arm` (m, the ball's radius), as the contact laws count theirs.
  static ContactStiffness stiffness(const Params& p) {
    ContactStiffness k;
    k.normal = p.normal_stiffness * p.area();
    k.shear = p.shear_stiffness * p.area();
    k.rolling = std::max(p.normal_stiffness * p.bending_inertia(), p.shear_stiffness * p.polar_inertia());
    return k;
  }

  /// A vector rotated into the plane normal to `normal`, keeping its length (zero stays zero);
  /// the square root and quotient computed and then selected, so that blocks run in SIMD lanes.
  DEM_HOT_INLINE static Lane3 rotate_into_plane(const Lane3& v, const Lane3& normal) {
    const double length_sq = squared_norm(v);
    const Lane3 projected = v - dot(v, normal) * normal;
    const double projected_sq = squared_norm(projected);
    const bool rescale = projected_sq > 0.0;
    const double root = std::sqrt(length_sq / (rescale ? projected_sq : 1.0));
    const Lane3 rotated = (rescale ? root : 1.0) * projected;
    const bool zero = length_sq == 0.0;
    return {zero ? v.x : rotated.x, zero ? v.y : rotated.y, zero ? v.z : rotated.z};
  }
};

}  // namespace dem
