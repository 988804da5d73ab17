// Linear contact law with Coulomb slip (PFC "linear", docs/model.md 1.1) and its rolling-resistance
// extension (PFC "rrlinear", docs/model.md 1.2). Both are header-inline because the engine's contact
// loop is a template on the law: the compiler sees the whole force computation.
//
// Stiffness: either from an effective modulus by the deformability method (docs/model.md 1.3),
//   kn = pi rbar^2 E* / L, ks = kn / kappa*, rbar = min(R1, R2) (R1 for a facet), L = R1 + R2,
// or constant per contact type (kn, ks given), as LAMMPS and LIGGGHTS set them.
// Damping: optional dashpots, either as critical-damping ratios (PFC) or mass-proportional
// (LAMMPS `damping mass_velocity`: c = gamma m_eff). Normal force: absolute mode, no tension.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include <dem/contact/kinematics.hpp>
#include <dem/core/errors.hpp>

// The force functions run once per contact per step inside the engine's templated loop; GCC's
// heuristics otherwise keep them out of line, which costs about a third of the step.
#if defined(__GNUC__)
#define DEM_HOT_INLINE __attribute__((always_inline)) inline
#else
#define DEM_HOT_INLINE inline
#endif

namespace dem {

/// Contact stiffness and friction parameters shared by the linear family of laws.
struct LinearParams {
  double effective_modulus = 0.0;  // Pa, E*; if 0 the constant stiffnesses below are used
  double stiffness_ratio = 1.0;    // -, kappa* = kn/ks (deformability method)
  double normal_stiffness = 0.0;   // N/m, constant kn (only when effective_modulus == 0)
  double shear_stiffness = 0.0;    // N/m, constant ks (only when effective_modulus == 0)
  double friction = 0.0;           // -, Coulomb coefficient mu
  double normal_damping_ratio = 0.0;  // -, beta_n: c_n = 2 beta_n sqrt(m_eff kn)
  double shear_damping_ratio = 0.0;   // -, beta_s: c_s = 2 beta_s sqrt(m_eff ks)
  double normal_damping_rate = 0.0;   // 1/s, gamma_n: c_n = gamma_n m_eff (LAMMPS mass_velocity)
  double shear_damping_rate = 0.0;    // 1/s, gamma_s: c_s = gamma_s m_eff
  bool pebble_as_wall = false;  // ball-pebble stiffness as if the pebble were a rigid wall

  /// Parameters by the deformability method (the study's Table 1 form).
  static LinearParams deformable(double effective_modulus, double stiffness_ratio, double friction) {
    LinearParams p;
    p.effective_modulus = effective_modulus;
    p.stiffness_ratio = stiffness_ratio;
    p.friction = friction;
    return p;
  }
  /// Parameters with the same kn and ks for every contact of this type.
  static LinearParams constant(double normal_stiffness, double shear_stiffness, double friction) {
    LinearParams p;
    p.normal_stiffness = normal_stiffness;
    p.shear_stiffness = shear_stiffness;
    p.friction = friction;
    return p;
  }

  void validate(const std::string& where) const {
    if (effective_modulus != 0.0) {
      require_positive(where + ".effective_modulus", effective_modulus);
      require_positive(where + ".stiffness_ratio", stiffness_ratio);
    } else {
      require(normal_stiffness > 0.0, where + ".normal_stiffness", normal_stiffness,
              "> 0 (or give effective_modulus > 0)");
      require_positive(where + ".shear_stiffness", shear_stiffness);
    }
    require_non_negative(where + ".friction", friction);
    require_non_negative(where + ".normal_damping_ratio", normal_damping_ratio);
    require_non_negative(where + ".shear_damping_ratio", shear_damping_ratio);
    require_non_negative(where + ".normal_damping_rate", normal_damping_rate);
    require_non_negative(where + ".shear_damping_rate", shear_damping_rate);
  }

  /// kn and ks of one contact (docs/model.md 1.3).
  DEM_HOT_INLINE ContactStiffness stiffness(const ContactKinematics& k) const {
    ContactStiffness s;
    if (effective_modulus != 0.0) {
      const bool rigid_partner = k.radius_2 == 0.0 || (pebble_as_wall && k.kind == ContactKind::BallPebble);
      const double rbar = rigid_partner ? k.radius_1 : std::min(k.radius_1, k.radius_2);
      const double length = rigid_partner ? k.radius_1 : k.radius_1 + k.radius_2;
      s.normal = pi * rbar * rbar * effective_modulus / length;
      s.shear = s.normal / stiffness_ratio;
    } else {
      s.normal = normal_stiffness;
      s.shear = shear_stiffness;
    }
    return s;
  }
};

namespace detail {

/// Rotates a stored tangential vector into the current contact plane, keeping its length
/// (docs/model.md 1.1 step 1; LAMMPS rotates and rescales its tangential history the same way).
DEM_HOT_INLINE void rotate_into_plane(Vec3& stored, const Vec3& normal) {
  const double length_sq = stored.squaredNorm();
  if (length_sq == 0.0) return;
  // Written per component: GCC sometimes leaves Eigen's `v -= s * n` out of line in the contact
  // loop (two calls per contact, a few per cent of the step), depending on unrelated code.
  const double along = stored.dot(normal);
  stored = Vec3(stored.x() - along * normal.x(), stored.y() - along * normal.y(), stored.z() - along * normal.z());
  const double projected_sq = stored.squaredNorm();
  if (projected_sq > 0.0) stored *= std::sqrt(length_sq / projected_sq);
}

/// The linear normal and shear part shared by LinearLaw and RollingLinearLaw. Returns the
/// elastic normal force (compression positive) and fills `out.force`.
DEM_HOT_INLINE double linear_force(const LinearParams& p, const ContactStiffness& s, const ContactKinematics& k,
                           Vec3& shear_force, ContactForce& out) {
  const Vec3& n = k.normal;
  const double normal_speed = k.relative_velocity.dot(n);  // < 0 approaching
  const Vec3 shear_velocity = k.relative_velocity - normal_speed * n;

  const double elastic_normal = s.normal * k.overlap;  // absolute mode, compression positive

  rotate_into_plane(shear_force, n);
  shear_force -= s.shear * k.dt * shear_velocity;  // force on piece 2 opposes its sliding
  const double shear_limit = p.friction * elastic_normal;
  const double shear_sq = shear_force.squaredNorm();
  const bool sliding = shear_sq > shear_limit * shear_limit;
  if (sliding) shear_force *= shear_limit / std::sqrt(shear_sq);

  double c_n = p.normal_damping_rate * k.effective_mass;
  double c_s = p.shear_damping_rate * k.effective_mass;
  if (p.normal_damping_ratio > 0.0) c_n += 2.0 * p.normal_damping_ratio * std::sqrt(k.effective_mass * s.normal);
  if (p.shear_damping_ratio > 0.0) c_s += 2.0 * p.shear_damping_ratio * std::sqrt(k.effective_mass * s.shear);

  const double normal_total = elastic_normal - c_n * normal_speed;
  out.force = normal_total * n + shear_force - c_s * shear_velocity;
  out.normal_force = elastic_normal;
  out.normal_stiffness = s.normal;
  return elastic_normal;
}

}  // namespace detail

/// PFC's linear model: normal spring (no tension), Coulomb-limited shear spring, optional dashpots.
struct LinearLaw {
  using Params = LinearParams;
  struct State {
    Vec3 shear_force = Vec3::Zero();  // N, on piece 2, in the contact plane
  };
  static constexpr const char* name = "linear";

  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) { return p.stiffness(k); }

  DEM_HOT_INLINE static ContactForce force(const Params& p, const ContactKinematics& k, State& state) {
    ContactForce out;
    detail::linear_force(p, p.stiffness(k), k, state.shear_force, out);
    return out;
  }
};

/// PFC's rolling-resistance linear model: LinearLaw plus an elastic-perfectly plastic rolling
/// spring kr = ks Rbar^2 (type C of Ai et al. 2011, without the rolling dashpot), capped at
/// mu_r Rbar Fn, acting on the bend part of the relative rotation only (twist is free).
struct RollingLinearLaw {
  struct Params : LinearParams {
    double rolling_friction = 0.0;  // -, mu_r
    /// Ai et al. (2011) type C rolling stiffness 2.25 kn mu_r^2 Rbar^2 instead of PFC's ks Rbar^2.
    bool ai_rolling_stiffness = false;

    static Params deformable(double effective_modulus, double stiffness_ratio, double friction,
                             double rolling_friction) {
      Params p;
      static_cast<LinearParams&>(p) = LinearParams::deformable(effective_modulus, stiffness_ratio, friction);
      p.rolling_friction = rolling_friction;
      return p;
    }
    static Params constant(double normal_stiffness, double shear_stiffness, double friction,
                           double rolling_friction) {
      Params p;
      static_cast<LinearParams&>(p) = LinearParams::constant(normal_stiffness, shear_stiffness, friction);
      p.rolling_friction = rolling_friction;
      return p;
    }
    void validate(const std::string& where) const {
      LinearParams::validate(where);
      require_non_negative(where + ".rolling_friction", rolling_friction);
    }
    double rolling_stiffness(const ContactStiffness& s, double effective_radius) const {
      const double r2 = effective_radius * effective_radius;
      return ai_rolling_stiffness ? 2.25 * s.normal * rolling_friction * rolling_friction * r2 : s.shear * r2;
    }
  };
  struct State {
    Vec3 shear_force = Vec3::Zero();     // N, on piece 2
    Vec3 rolling_moment = Vec3::Zero();  // N m, on piece 2, in the contact plane
  };
  static constexpr const char* name = "rolling-linear";

  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    ContactStiffness s = p.stiffness(k);
    s.rolling = p.rolling_stiffness(s, k.effective_radius);
    return s;
  }

  DEM_HOT_INLINE static ContactForce force(const Params& p, const ContactKinematics& k, State& state) {
    ContactForce out;
    const ContactStiffness s = p.stiffness(k);
    const double normal = detail::linear_force(p, s, k, state.shear_force, out);

    const Vec3& n = k.normal;
    const Vec3 bend_rate = k.relative_angular_velocity - k.relative_angular_velocity.dot(n) * n;
    detail::rotate_into_plane(state.rolling_moment, n);
    state.rolling_moment -= p.rolling_stiffness(s, k.effective_radius) * k.dt * bend_rate;
    const double limit = p.rolling_friction * k.effective_radius * normal;
    const double moment_sq = state.rolling_moment.squaredNorm();
    if (moment_sq > limit * limit) state.rolling_moment *= limit / std::sqrt(moment_sq);
    out.moment = state.rolling_moment;
    return out;
  }
};

}  // namespace dem
