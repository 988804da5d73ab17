// Hertz-Mindlin with DMT adhesion: the Hertz-Mindlin law (hertz_mindlin_law.hpp) plus a constant
// attraction while the surfaces touch, for moist or fine grains that stick. It is LAMMPS's
// `pair_style granular dmt E e nu gamma` normal model (pair_granular docs and
// gran_sub_mod_normal.cpp, after Derjaguin, Muller & Toporov 1975, J. Colloid Interface Sci.
// 53:314; Johnson 1985, Contact Mechanics, 5.8 and Maugis 2000, 3.4.2):
//
//   F_ne = 4/3 E* a delta - F_po,    F_po = 4 pi gamma R*      (compression positive)
//
// with gamma the surface energy (J/m^2; the work of adhesion of two like surfaces is w = 2 gamma,
// and DMT's pull-off force is 2 pi w R* = 4 pi gamma R*), a = sqrt(R* delta), R* the effective
// radius (the ball's radius for a facet). F_po is the pull-off force: the largest tension the
// contact carries, reached as the overlap goes to zero; the contact breaks when the surfaces part
// (delta = 0, zero separation), as in LAMMPS's dmt, so a pair that was never touching is never
// pulled together. The equilibrium overlap with no load is delta_0 = (3 F_po / (4 E* sqrt(R*)))^(2/3).
//
// Everything else is Hertz-Mindlin's (the same keys, the same damping models on the Hertz part,
// c_n and c_t from the restitution): the dashpots and the Mindlin stiffness follow the Hertz
// contact radius, and Coulomb's limit (and the rolling cap) take the load pressing the surfaces
// together, adhesion included, as LAMMPS's dmt does (its Fncrit = |F_ne + 2 F_po|):
//
//   F_n = F_ne - c_n v_n,   |F_t| <= mu |F_n + 2 F_po|,   |M_r| <= mu_r R* |F_n + 2 F_po|
//
// (the rolling model epsd's cap; cdt's constant torque is mu_r R* |F_ne + 2 F_po|, the elastic
// load as Hertz-Mindlin's cdt takes F_ne).
//
// The reported normal force (ContactForce::normal_force) is F_ne, negative while the contact is
// in tension (stress and fabric see the attraction).
//
// Rejected: JKR (LAMMPS `jkr`), whose contact lives on after the surfaces part, to a negative
// overlap of -delta_c: the engine's pair search only visits pairs within their reach (overlap >
// 0), so it would need a per-law reach in the broad phase. DMT's attraction ends at contact, so it
// needs none; it is the better model for small, stiff grains (Tabor parameter below ~0.1), JKR for
// large, soft ones.
//
// This law runs one contact at a time (force only, no force_lanes): the engine's scalar loops,
// the same bits for any thread count; the SIMD blocks are for the non-adhesive laws.
#pragma once

#include <cmath>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/hertz_mindlin_law.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>

namespace dem {

struct HertzDmtParams {
  HertzMindlinParams hertz;    // the material and dashpots (derive() it, or make it with material())
  double surface_energy = 0.0;  // J/m^2, gamma (LAMMPS dmt's cohesion coefficient); 0: no adhesion

  /// The pull-off force of a contact of effective radius R* (m): 4 pi gamma R*, N.
  double pull_off_force(double effective_radius) const { return 4.0 * pi * surface_energy * effective_radius; }

  void validate(const std::string& where) const {
    hertz.validate(where);
    require_non_negative(where + ".surface_energy", surface_energy);
  }
};

/// Hertz-Mindlin with DMT's constant adhesion 4 pi gamma R* while the surfaces touch.
struct HertzDmtLaw {
  using Params = HertzDmtParams;
  using State = HertzMindlinLaw::State;  // the same history: adhesion adds none
  static constexpr const char* name = "hertz-dmt";

  /// Hertz-Mindlin's estimate: the attraction adds no stiffness.
  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    return HertzMindlinLaw::stiffness(p.hertz, k);
  }

  static ContactForce force(const Params& params, const ContactKinematics& kin, State& state) {
    const HertzMindlinParams& p = params.hertz;
    const LaneKinematics k = lane(kin);
    const Lane3& n = k.normal;
    const double normal_speed = dot(k.relative_velocity, n);  // < 0 approaching
    const Lane3 shear_velocity = k.relative_velocity - normal_speed * n;

    const double contact_radius = std::sqrt(k.effective_radius * k.overlap);
    const double pull_off = params.pull_off_force(k.effective_radius);
    const double elastic_normal = (4.0 / 3.0) * p.effective_modulus * contact_radius * k.overlap - pull_off;
    const double shear_stiffness = 8.0 * p.effective_shear_modulus * contact_radius;
    const double damping_root = std::sqrt(contact_radius * k.effective_mass);
    const double c_n = p.normal_damping_factor * damping_root;
    const double c_t = p.shear_damping_factor * damping_root;
    const double normal_total = elastic_normal - c_n * normal_speed;
    const double pressing = std::abs(normal_total + 2.0 * pull_off);  // the load the friction sees
    const double limit = p.friction * pressing;

    // Shear history and Coulomb slip exactly as Hertz-Mindlin's (its damping model's rules).
    Lane3 xi = state.shear_displacement;
    const double length_sq = squared_norm(xi);
    xi = xi - dot(xi, n) * n;
    const double projected_sq = squared_norm(xi);
    if (p.rescale_history != 0.0 && projected_sq > 0.0) xi = std::sqrt(length_sq / projected_sq) * xi;
    xi = xi + k.dt * shear_velocity;
    const Lane3 damping_force = c_t * shear_velocity;
    const Lane3 trial = -(shear_stiffness * xi) - p.damping_in_slip * damping_force;
    const double trial_sq = squared_norm(trial);
    Lane3 shear_force;
    if (trial_sq > limit * limit) {
      const double scale = squared_norm(xi) != 0.0 ? limit / std::sqrt(trial_sq) : 0.0;
      shear_force = scale * trial;
      const double inverse_stiffness = 1.0 / (shear_stiffness > 0.0 ? shear_stiffness : 1.0);
      state.shear_displacement = -inverse_stiffness * (shear_force + p.damping_in_slip * damping_force);
    } else {
      shear_force = trial - (1.0 - p.damping_in_slip) * damping_force;
      state.shear_displacement = xi;
    }

    // Rolling resistance as Hertz-Mindlin's, on the load pressing the surfaces together: epsd's
    // (or sds's) spring capped at mu_r R* |F_n + 2 F_po|, or cdt's torque mu_r R* |F_ne + 2 F_po| (elastic, as
    // Hertz-Mindlin's cdt; the same bits as Hertz-Mindlin's without surface energy).
    const Lane3 bend_rate = k.relative_angular_velocity - dot(k.relative_angular_velocity, n) * n;
    Lane3 moment;
    if (p.rolling == HertzRolling::cdt) {
      moment = detail::constant_directional_torque(p.rolling_friction, k.effective_radius,
                                                   std::abs(elastic_normal + 2.0 * pull_off),
                                                   k.relative_angular_velocity, bend_rate);
      state.rolling_moment = Lane3{};
    } else {
      const double spring_stiffness = p.rolling == HertzRolling::sds ? p.rolling_stiffness : shear_stiffness;  // N/m
      moment = detail::rotate_into_plane(state.rolling_moment, n);
      moment = moment - (spring_stiffness * k.effective_radius * k.effective_radius * k.dt) * bend_rate;
      moment = detail::cap_length(moment, p.rolling_friction * k.effective_radius * pressing);
      state.rolling_moment = moment;
    }

    LaneForce out;
    out.force = normal_total * n + shear_force;
    out.moment = moment;
    out.normal_force = elastic_normal;
    out.normal_stiffness = 2.0 * p.effective_modulus * contact_radius;  // dF_ne / d delta
    return to_contact_force(out);
  }
};

}  // namespace dem
