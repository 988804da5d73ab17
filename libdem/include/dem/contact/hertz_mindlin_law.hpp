// Hertz-Mindlin contact law with Coulomb slip, viscous damping set from a coefficient of
// restitution, and optional elastic-plastic rolling resistance (docs/model.md 1.4): the default
// law of LIGGGHTS, EDEM and most granular studies run in LAMMPS, so that a parameter set
// calibrated there (Young's modulus, Poisson's ratio, restitution, friction, rolling friction)
// runs here unchanged.
//
// One material per contact type (both pieces of it; a facet or pebble is of the same material):
//   E* = E / (2 (1 - nu^2)),   G* = E / (4 (2 - nu)(1 + nu))      [Johnson 1985, LIGGGHTS, LAMMPS]
// Per contact, with R* the effective radius (R1 for a facet), m* the effective mass, delta the
// overlap, a = sqrt(R* delta) the contact radius, v_n and v_s the normal and shear parts of the
// relative velocity (piece 2 relative to piece 1), xi the shear displacement (the history):
//   F_ne = 4/3 E* a delta                  Hertz, elastic (compression positive)
//   k_t  = 8 G* a                          Mindlin's no-slip tangential stiffness
//   F_n  = F_ne - c_n v_n                  total, not clipped at zero (as both peers by default)
//   F_t  = -k_t xi - c_t v_s, Coulomb-limited at mu |F_n| (each peer's way, below)
// The two damping models (`damping_model`), each as its peer computes it:
//   liggghts  LIGGGHTS `model hertz tangential history` (normal_model_hertz.h, its default):
//               beta = ln e / sqrt(ln^2 e + pi^2),  S_n = 2 E* a,  S_t = 8 G* a,
//               c_n = 2 sqrt(5/6) |beta| sqrt(S_n m*),  c_t = 2 sqrt(5/6) |beta| sqrt(S_t m*).
//             History: xi += v_s dt, then projected into the contact plane (not rescaled).
//             Slip when k_t |xi| > mu |F_n|: the elastic part is scaled to mu |F_n|, xi with it,
//             and the tangential dashpot is left out; otherwise F_t = -k_t xi - c_t v_s.
//   tsuji     LAMMPS `pair granular hertz/material E e nu damping tsuji tangential mindlin NULL
//             1.0 mu` (gran_sub_mod_damping.cpp, after Tsuji et al. 1992 and Marshall 2009 eq. 53):
//               alpha(e) = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5
//                          + 4.8218 e^6,
//               c_n = sqrt(2) alpha(e) sqrt(m* F_ne / delta) = sqrt(2) alpha(e) sqrt(4/3 E* a m*),
//               c_t = 1.0 c_n  (the `1.0` of `tangential mindlin NULL 1.0 mu`).
//             History: xi rotated into the contact plane keeping its length, then xi += v_s dt.
//             Slip when |-k_t xi - c_t v_s| > mu |F_n|: the total is scaled to mu |F_n| and
//             xi = -(F_t + c_t v_s) / k_t.
// In both, a history of zero length at slip gives F_t = 0 (as both peers). LIGGGHTS's model gives
// the set restitution exactly for a head-on impact; Tsuji's polynomial is a fit (within 0.6 %
// over 0.1 <= e <= 0.9, docs/model.md 1.4).
//
// Rolling resistance (rolling_friction mu_r > 0), one of three models (`rolling`):
//   epsd  the elastic-plastic spring of PFC's rrlinear and LIGGGHTS's epsd2, k_r = k_t R*^2
//         (current k_t), on the bend part of the relative rotation, capped at mu_r R* |F_n|
//         (epsd2's cap), the moment rotated into the contact plane as RollingLinearLaw's;
//   cdt   LIGGGHTS's constant directional torque (rolling_model_cdt.h, after Zhou et al. 1999):
//         M_r = -mu_r R* F_ne w_b / |w| on piece 2, w = w2 - w1 and w_b its bend part (LIGGGHTS
//         takes w's direction and then drops the normal part), F_ne the elastic normal force
//         (LIGGGHTS's kn deltan); zero while w is. No spring and no history: at rest it flips
//         with w from step to step, as LIGGGHTS's does, and it adds no stiffness to the time-step
//         estimate;
//   sds   LAMMPS's `rolling sds k_roll 0 mu_r` (pair granular): epsd's spring and cap with a
//         constant k_r = k_roll R*^2 (rolling_stiffness k_roll, N/m) instead of Hertz's current k_t.
// A ball rolling on a plane slows at (5/7) mu_r g under either (a solid sphere: M_r / (R m 7/5)).
// No rolling resistance: rolling_friction = 0 (the registry's `rolling = none` sets it so).
//
// The time-step estimate (stiffness()) takes the tangent stiffnesses at an overlap of 1 % of R*:
// dF_ne/d delta = 2 E* a and k_t. Leapfrog stays stable while the actual stiffness is below
// (2 / safety)^2 times the estimate, i.e. (k ~ sqrt(delta)) while a ball's one contact stays below
// (2 / 0.8)^4 = 39 times the reference overlap, 39 % of R*: far beyond the overlaps of a granular
// packing (below 1 % of R*). A ball's several contacts add their stiffnesses in the estimate too.
//
// The same arithmetic runs one contact at a time (force) and in the engine's SIMD blocks
// (force_lanes): the same bits (contact/lanes.hpp). The damping model is a per-type constant
// that selects by weights of 0 and 1, so one compiled loop serves both. The rolling model is a
// lane variant: a type with epsd runs the loop it ran before cdt and sds existed.
#pragma once

#include <cmath>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>
#include <dem/contact/linear_law.hpp>

namespace dem {

/// Which peer's damping (and slip rule) a Hertz-Mindlin contact type follows.
enum class HertzDamping : int { liggghts = 0, tsuji = 1 };

inline const char* to_string(HertzDamping model) { return model == HertzDamping::tsuji ? "tsuji" : "liggghts"; }

/// Hertz-Mindlin's rolling resistance model (when rolling_friction > 0): LIGGGHTS's epsd2 spring,
/// its constant directional torque cdt, or LAMMPS's spring of constant stiffness sds.
enum class HertzRolling : int { epsd = 0, cdt = 1, sds = 2 };

inline const char* to_string(HertzRolling model) {
  return model == HertzRolling::cdt ? "cdt" : model == HertzRolling::sds ? "sds" : "epsd";
}

struct HertzMindlinParams {
  // The material, as LIGGGHTS users give it.
  double youngs_modulus = 0.0;    // Pa, E
  double poissons_ratio = 0.25;   // -, nu, in [0, 0.5]
  double restitution = 1.0;       // -, e, in (0, 1]
  double friction = 0.0;          // -, Coulomb mu
  double rolling_friction = 0.0;  // -, mu_r (0: no rolling resistance)
  HertzDamping damping_model = HertzDamping::liggghts;
  HertzRolling rolling = HertzRolling::epsd;
  double rolling_stiffness = 0.0;  // N/m, k_roll of sds: k_r = k_roll R*^2 (0 unless rolling = sds)

  // Derived by derive() (the force never takes a logarithm or a polynomial per contact).
  double effective_modulus = 0.0;        // Pa, E*
  double effective_shear_modulus = 0.0;  // Pa, G*
  double normal_damping_factor = 0.0;    // sqrt(kg/m)/s: c_n = factor sqrt(a m*)
  double shear_damping_factor = 0.0;     // sqrt(kg/m)/s: c_t = factor sqrt(a m*)
  double rescale_history = 0.0;          // 1: keep xi's length when rotating it (LAMMPS), 0: project only
  double damping_in_slip = 0.0;          // 1: the slip test and cap include the dashpot (LAMMPS), 0: not

  /// The parameters of one material, derived.
  static HertzMindlinParams material(double youngs_modulus, double poissons_ratio, double restitution, double friction,
                                     double rolling_friction = 0.0, HertzDamping damping_model = HertzDamping::liggghts) {
    HertzMindlinParams p;
    p.youngs_modulus = youngs_modulus;
    p.poissons_ratio = poissons_ratio;
    p.restitution = restitution;
    p.friction = friction;
    p.rolling_friction = rolling_friction;
    p.damping_model = damping_model;
    p.derive();
    return p;
  }

  /// Recomputes the derived constants from the material; call it after changing a material field.
  void derive() {
    const double nu = poissons_ratio;
    effective_modulus = youngs_modulus / (2.0 * (1.0 - nu * nu));
    effective_shear_modulus = youngs_modulus / (4.0 * (2.0 - nu) * (1.0 + nu));
    const double e = restitution;
    if (damping_model == HertzDamping::tsuji) {
      const double e2 = e * e, e3 = e2 * e, e4 = e3 * e, e5 = e4 * e, e6 = e5 * e;
      const double alpha = 1.2728 - 4.2783 * e + 11.087 * e2 - 22.348 * e3 + 27.467 * e4 - 18.022 * e5 + 4.8218 * e6;
      normal_damping_factor = std::sqrt(2.0) * alpha * std::sqrt(4.0 / 3.0 * effective_modulus);
      shear_damping_factor = normal_damping_factor;
      rescale_history = 1.0;
      damping_in_slip = 1.0;
    } else {
      const double log_e = std::log(e);
      const double beta = std::abs(log_e) / std::sqrt(log_e * log_e + pi * pi);
      const double two_root_five_sixths = 2.0 * std::sqrt(5.0 / 6.0);
      normal_damping_factor = two_root_five_sixths * beta * std::sqrt(2.0 * effective_modulus);
      shear_damping_factor = two_root_five_sixths * beta * std::sqrt(8.0 * effective_shear_modulus);
      rescale_history = 0.0;
      damping_in_slip = 0.0;
    }
  }

  void validate(const std::string& where) const {
    require_positive(where + ".youngs_modulus", youngs_modulus);
    require(poissons_ratio >= 0.0 && poissons_ratio <= 0.5, where + ".poissons_ratio", poissons_ratio, "in [0, 0.5]");
    require(restitution > 0.0 && restitution <= 1.0, where + ".restitution", restitution, "in (0, 1]");
    require_non_negative(where + ".friction", friction);
    require_non_negative(where + ".rolling_friction", rolling_friction);
    require(damping_model == HertzDamping::liggghts || damping_model == HertzDamping::tsuji, where + ".damping_model",
            static_cast<int>(damping_model), "liggghts (0) or tsuji (1)");
    require(rolling == HertzRolling::epsd || rolling == HertzRolling::cdt || rolling == HertzRolling::sds,
            where + ".rolling", static_cast<int>(rolling), "epsd (0), cdt (1) or sds (2)");
    require_non_negative(where + ".rolling_stiffness", rolling_stiffness);
    require(rolling == HertzRolling::sds || rolling_stiffness == 0.0, where + ".rolling_stiffness", rolling_stiffness,
            "0 unless rolling = sds (the other models take no rolling stiffness)");
    require(rolling != HertzRolling::sds || rolling_friction == 0.0 || rolling_stiffness > 0.0,
            where + ".rolling_stiffness", rolling_stiffness, "> 0 N/m with rolling = sds and rolling_friction > 0");
    HertzMindlinParams fresh = *this;
    fresh.derive();
    require(fresh.effective_modulus == effective_modulus && fresh.effective_shear_modulus == effective_shear_modulus &&
                fresh.normal_damping_factor == normal_damping_factor &&
                fresh.shear_damping_factor == shear_damping_factor && fresh.rescale_history == rescale_history &&
                fresh.damping_in_slip == damping_in_slip,
            where + ".effective_modulus", effective_modulus,
            "derived from the material: call derive() after changing youngs_modulus, poissons_ratio, restitution or "
            "damping_model (or make the parameters with HertzMindlinParams::material)");
  }

  /// The overlap, as a fraction of R*, at which the time-step estimate takes the stiffness.
  static constexpr double reference_overlap_ratio = 0.01;
};

namespace detail {

/// `choose ? a : b`, component by component: a choice between two whole Lane3 values becomes a
/// load through a chosen address, which keeps the vectoriser out of the loop.
DEM_HOT_INLINE Lane3 select_lanes(bool choose, const Lane3& a, const Lane3& b) {
  return {choose ? a.x : b.x, choose ? a.y : b.y, choose ? a.z : b.z};
}

/// LIGGGHTS's constant directional torque on piece 2: -mu_r R* load w_b / |w|, with w the relative
/// spin (w2 - w1) and w_b its bend part; zero while w is. Selected, not branched (lanes.hpp).
DEM_HOT_INLINE Lane3 constant_directional_torque(double rolling_friction, double effective_radius, double load,
                                                 const Lane3& spin, const Lane3& bend_rate) {
  const double spin_sq = squared_norm(spin);
  const bool turning = spin_sq > 0.0;
  const double per_rate = rolling_friction * effective_radius * load / std::sqrt(turning ? spin_sq : 1.0);
  return -(turning ? per_rate : 0.0) * bend_rate;
}

}  // namespace detail

/// Hertz normal force, Mindlin tangential stiffness with Coulomb slip, damping from restitution
/// after LIGGGHTS or LAMMPS (HertzMindlinParams::damping_model), optional rolling resistance.
struct HertzMindlinLaw {
  using Params = HertzMindlinParams;
  struct State {
    Lane3 shear_displacement{};  // m, xi, in the contact plane
    Lane3 rolling_moment{};      // N m, on piece 2, in the contact plane
  };
  static constexpr const char* name = "hertz-mindlin";

  /// Tangent stiffnesses at an overlap of reference_overlap_ratio R* (see the header's top).
  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    const double a = k.effective_radius * std::sqrt(Params::reference_overlap_ratio);
    ContactStiffness s;
    s.normal = 2.0 * p.effective_modulus * a;
    s.shear = 8.0 * p.effective_shear_modulus * a;
    const double rolling_spring = p.rolling == HertzRolling::epsd  ? s.shear
                                  : p.rolling == HertzRolling::sds ? p.rolling_stiffness
                                                                   : 0.0;
    s.rolling = p.rolling_friction > 0.0 ? rolling_spring * k.effective_radius * k.effective_radius : 0.0;
    return s;
  }

  /// Lane variants (lanes.hpp): 0 the epsd spring only (the loop of every epsd type), 1 any
  /// model, the one of the parameters selected per contact (right for any parameters).
  static constexpr int lane_variants = 2;
  static int lane_variant(const Params& p) { return p.rolling == HertzRolling::epsd ? 0 : 1; }

  template <int Variant = 1>
  DEM_HOT_INLINE static LaneForce force_lanes(const Params& p, const LaneKinematics& k, State& state) {
    const Lane3& n = k.normal;
    const double normal_speed = dot(k.relative_velocity, n);  // < 0 approaching
    const Lane3 shear_velocity = k.relative_velocity - normal_speed * n;

    const double contact_radius = std::sqrt(k.effective_radius * k.overlap);
    const double elastic_normal = (4.0 / 3.0) * p.effective_modulus * contact_radius * k.overlap;
    const double shear_stiffness = 8.0 * p.effective_shear_modulus * contact_radius;
    const double damping_root = std::sqrt(contact_radius * k.effective_mass);
    const double c_n = p.normal_damping_factor * damping_root;
    const double c_t = p.shear_damping_factor * damping_root;
    const double normal_total = elastic_normal - c_n * normal_speed;
    const double limit = p.friction * std::abs(normal_total);

    // History: rotated into the plane (LAMMPS: keeping its length, LIGGGHTS: projected), plus this
    // step's shear displacement (in the plane already: the order does not matter otherwise).
    Lane3 xi = state.shear_displacement;
    const double length_sq = squared_norm(xi);
    xi = xi - dot(xi, n) * n;
    const double projected_sq = squared_norm(xi);
    const bool rescale = (p.rescale_history != 0.0) & (projected_sq > 0.0);
    const double root = std::sqrt(length_sq / (rescale ? projected_sq : 1.0));
    xi = (rescale ? root : 1.0) * xi;
    xi = xi + k.dt * shear_velocity;

    // Coulomb: the trial force holds the dashpot where the peer's slip test does (LAMMPS).
    const Lane3 damping_force = c_t * shear_velocity;
    const Lane3 trial = -(shear_stiffness * xi) - p.damping_in_slip * damping_force;
    const double trial_sq = squared_norm(trial);
    const bool slip = trial_sq > limit * limit;
    const bool has_history = squared_norm(xi) != 0.0;
    const double scale = has_history ? limit / std::sqrt(slip ? trial_sq : 1.0) : 0.0;
    const Lane3 slipping = scale * trial;
    const Lane3 sticking = trial - (1.0 - p.damping_in_slip) * damping_force;
    const Lane3 shear_force = detail::select_lanes(slip, slipping, sticking);
    const double inverse_stiffness = 1.0 / (shear_stiffness > 0.0 ? shear_stiffness : 1.0);
    const Lane3 xi_slipping = -inverse_stiffness * (slipping + p.damping_in_slip * damping_force);
    state.shear_displacement = detail::select_lanes(slip, xi_slipping, xi);

    // Rolling resistance: epsd's k_r = k_t R*^2 on the bend rate, capped at mu_r R* |F_n|; sds's
    // k_r = k_roll R*^2 with the same cap; or cdt.
    const Lane3 bend_rate = k.relative_angular_velocity - dot(k.relative_angular_velocity, n) * n;
    double spring_stiffness = shear_stiffness;  // N/m, epsd's
    if constexpr (Variant == 1) spring_stiffness = p.rolling == HertzRolling::sds ? p.rolling_stiffness : shear_stiffness;
    Lane3 moment = detail::rotate_into_plane(state.rolling_moment, n);
    moment = moment - (spring_stiffness * k.effective_radius * k.effective_radius * k.dt) * bend_rate;
    moment = detail::cap_length(moment, p.rolling_friction * k.effective_radius * std::abs(normal_total));
    if constexpr (Variant == 1) {
      const bool cdt = p.rolling == HertzRolling::cdt;
      const Lane3 spring = moment;
      const Lane3 constant = detail::constant_directional_torque(p.rolling_friction, k.effective_radius, elastic_normal,
                                                                 k.relative_angular_velocity, bend_rate);
      moment = detail::select_lanes(cdt, constant, spring);
      state.rolling_moment = detail::select_lanes(cdt, Lane3{}, spring);  // cdt keeps no history
    } else {
      state.rolling_moment = moment;
    }

    LaneForce out;
    out.force = normal_total * n + shear_force;
    out.moment = moment;
    out.normal_force = elastic_normal;
    out.normal_stiffness = 2.0 * p.effective_modulus * contact_radius;  // dF_ne / d delta
    return out;
  }
  /// One contact at a time, in the parameters' variant (an epsd type: the arithmetic it ran before
  /// cdt and sds existed).
  DEM_HOT_INLINE static ContactForce force(const Params& p, const ContactKinematics& k, State& state) {
    return to_contact_force(lane_variant(p) == 1 ? force_lanes<1>(p, lane(k), state) : force_lanes<0>(p, lane(k), state));
  }
};

}  // namespace dem
