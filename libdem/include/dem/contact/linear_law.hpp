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

#include <dem/base/errors.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>

namespace dem {

/// The dashpot terms a set of linear-law parameters uses. The vectorised contact loop is compiled
/// once for each (lanes.hpp: lane variants), so that terms that are zero for every contact of a
/// type cost nothing: the critical-ratio dashpots take two square roots per contact, and the
/// effective mass a division.
enum class Dashpots { none = 0, rate = 1, any = 2 };

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

  /// The dashpot terms these parameters make non-zero (selects the vectorised loop's variant).
  Dashpots dashpots() const {
    if (normal_damping_ratio != 0.0 || shear_damping_ratio != 0.0) return Dashpots::any;
    if (normal_damping_rate != 0.0 || shear_damping_rate != 0.0) return Dashpots::rate;
    return Dashpots::none;
  }

  /// kn and ks of one contact (docs/model.md 1.3).
  ContactStiffness stiffness(const ContactKinematics& k) const { return stiffness(k.radius_1, k.radius_2, k.kind); }

  /// The same from the radii (radius_2 = 0 for a facet). Written for the vectorised contact loop:
  /// each setting becomes a weight of 0 or 1 (the compiler vectorises a product, not a choice
  /// made on a setting), and a weight of 1 plus a weight-0 term is exact, so this gives the bits
  /// of the plain "if modulus ... else constant" formula.
  DEM_HOT_INLINE ContactStiffness stiffness(double radius_1, double radius_2, ContactKind kind) const {
    const double from_modulus = effective_modulus != 0.0 ? 1.0 : 0.0;
    const double from_constant = 1.0 - from_modulus;
    const double ratio = stiffness_ratio > 0.0 ? stiffness_ratio : 1.0;  // unused unless from_modulus
    // a rigid partner (facet, or pebble taken as a wall) counts as radius 0
    const double partner_radius = radius_2 * (pebble_as_wall && kind == ContactKind::BallPebble ? 0.0 : 1.0);
    const bool rigid_partner = partner_radius == 0.0;
    const double rbar = rigid_partner ? radius_1 : std::min(radius_1, partner_radius);
    const double length = rigid_partner ? radius_1 : radius_1 + partner_radius;
    const double modulus_normal = pi * rbar * rbar * effective_modulus / length;
    ContactStiffness s;
    s.normal = from_modulus * modulus_normal + from_constant * normal_stiffness;
    // times the reciprocal: the same for every contact, so a loop computes it once
    s.shear = from_modulus * (modulus_normal * (1.0 / ratio)) + from_constant * shear_stiffness;
    return s;
  }
};

namespace detail {

/// Rotates a stored tangential vector into the current contact plane, keeping its length
/// (docs/model.md 1.1 step 1; LAMMPS rotates and rescales its tangential history the same way).
/// A zero vector stays zero. Written without branches so that the contact loop can compute
/// several contacts at once (lanes.hpp).
DEM_HOT_INLINE Lane3 rotate_into_plane(const Lane3& stored, const Lane3& normal) {
  const double length_sq = squared_norm(stored);
  const Lane3 projected = stored - dot(stored, normal) * normal;
  const double projected_sq = squared_norm(projected);
  // Square roots and quotients are computed for every contact and then selected (never behind a
  // branch): the compiler only puts branch-free code in SIMD lanes.
  const bool rescale = projected_sq > 0.0;
  const double root = std::sqrt(length_sq / (rescale ? projected_sq : 1.0));
  return (rescale ? root : 1.0) * projected;
}

/// Scales `v` down to length `limit` if it is longer (the Coulomb and rolling caps).
DEM_HOT_INLINE Lane3 cap_length(const Lane3& v, double limit) {
  const double length_sq = squared_norm(v);
  const bool over = length_sq > limit * limit;
  const double scale = limit / std::sqrt(over ? length_sq : 1.0);
  return (over ? scale : 1.0) * v;
}

/// The linear normal and shear part shared by LinearLaw and RollingLinearLaw: fills `out.force`,
/// `out.normal_force` (elastic, compression positive) and `out.normal_stiffness`. `Terms`: the
/// dashpot terms computed (p.dashpots() or more); a term left out is zero for these parameters.
template <Dashpots Terms>
DEM_HOT_INLINE void linear_force(const LinearParams& p, const ContactStiffness& s, const LaneKinematics& k,
                                 Lane3& shear_force, LaneForce& out) {
  const Lane3& n = k.normal;
  const double normal_speed = dot(k.relative_velocity, n);  // < 0 approaching
  const Lane3 shear_velocity = k.relative_velocity - normal_speed * n;

  const double elastic_normal = s.normal * k.overlap;  // absolute mode, compression positive

  shear_force = rotate_into_plane(shear_force, n);
  shear_force = shear_force - (s.shear * k.dt) * shear_velocity;  // force on piece 2 opposes its sliding
  shear_force = cap_length(shear_force, p.friction * elastic_normal);

  // Both dashpot forms computed when present (no branch in the vectorised loop); a zero ratio or
  // rate adds 0, so each version gives the bits of the full formula (for a finite effective mass).
  double c_n = 0.0, c_s = 0.0;
  if constexpr (Terms != Dashpots::none) {
    c_n = p.normal_damping_rate * k.effective_mass;
    c_s = p.shear_damping_rate * k.effective_mass;
  }
  if constexpr (Terms == Dashpots::any) {
    c_n += 2.0 * p.normal_damping_ratio * std::sqrt(k.effective_mass * s.normal);
    c_s += 2.0 * p.shear_damping_ratio * std::sqrt(k.effective_mass * s.shear);
  }

  const double normal_total = elastic_normal - c_n * normal_speed;
  out.force = normal_total * n + shear_force - c_s * shear_velocity;
  out.normal_force = elastic_normal;
  out.normal_stiffness = s.normal;
}

}  // namespace detail

/// PFC's linear model: normal spring (no tension), Coulomb-limited shear spring, optional dashpots.
struct LinearLaw {
  using Params = LinearParams;
  struct State {
    Lane3 shear_force{};  // N, on piece 2, in the contact plane
  };
  static constexpr const char* name = "linear";

  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) { return p.stiffness(k); }

  /// Lane variants (lanes.hpp): one per Dashpots value.
  static constexpr int lane_variants = 3;
  static int lane_variant(const Params& p) { return static_cast<int>(p.dashpots()); }

  /// The force in plain doubles: what the engine's vectorised loop calls (with the parameters'
  /// variant; the default, all terms, is right for any parameters).
  template <int Variant = static_cast<int>(Dashpots::any)>
  DEM_HOT_INLINE static LaneForce force_lanes(const Params& p, const LaneKinematics& k, State& state) {
    LaneForce out;
    detail::linear_force<static_cast<Dashpots>(Variant)>(p, p.stiffness(k.radius_1, k.radius_2, k.kind), k,
                                                          state.shear_force, out);
    out.moment = Lane3{0.0, 0.0, 0.0};
    return out;
  }
  DEM_HOT_INLINE static ContactForce force(const Params& p, const ContactKinematics& k, State& state) {
    return to_contact_force(force_lanes(p, lane(k), state));
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
    DEM_HOT_INLINE double rolling_stiffness(const ContactStiffness& s, double effective_radius) const {
      const double r2 = effective_radius * effective_radius;
      const double ai = ai_rolling_stiffness ? 1.0 : 0.0;  // a weight, as in LinearParams::stiffness
      return (ai * (2.25 * s.normal * rolling_friction * rolling_friction) + (1.0 - ai) * s.shear) * r2;
    }
  };
  struct State {
    Lane3 shear_force{};     // N, on piece 2
    Lane3 rolling_moment{};  // N m, on piece 2, in the contact plane
  };
  static constexpr const char* name = "rolling-linear";

  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    ContactStiffness s = p.stiffness(k);
    s.rolling = p.rolling_stiffness(s, k.effective_radius);
    return s;
  }

  /// Lane variants (lanes.hpp): one per Dashpots value.
  static constexpr int lane_variants = 3;
  static int lane_variant(const Params& p) { return static_cast<int>(p.dashpots()); }

  /// The force in plain doubles: what the engine's vectorised loop calls (with the parameters'
  /// variant; the default, all terms, is right for any parameters).
  template <int Variant = static_cast<int>(Dashpots::any)>
  DEM_HOT_INLINE static LaneForce force_lanes(const Params& p, const LaneKinematics& k, State& state) {
    LaneForce out;
    const ContactStiffness s = p.stiffness(k.radius_1, k.radius_2, k.kind);
    detail::linear_force<static_cast<Dashpots>(Variant)>(p, s, k, state.shear_force, out);

    const Lane3& n = k.normal;
    const Lane3 bend_rate = k.relative_angular_velocity - dot(k.relative_angular_velocity, n) * n;
    Lane3 moment = detail::rotate_into_plane(state.rolling_moment, n);
    moment = moment - (p.rolling_stiffness(s, k.effective_radius) * k.dt) * bend_rate;
    moment = detail::cap_length(moment, p.rolling_friction * k.effective_radius * out.normal_force);
    state.rolling_moment = moment;
    out.moment = moment;
    return out;
  }
  DEM_HOT_INLINE static ContactForce force(const Params& p, const ContactKinematics& k, State& state) {
    return to_contact_force(force_lanes(p, lane(k), state));
  }
};

}  // namespace dem
