// The bonds of a World: a store beside the contact sets (WorldState::bonds), as a structure of
// arrays, one entry per bond in the order they were made. Unlike a contact, a bond is not found by
// the broad phase and does not end when its balls separate: it lives until it breaks.
//
// Bonds name their balls by stable particle id (ParticleStore::id), never by storage index, so a
// re-sort or a rebuild of the neighbour lists leaves them as they are; the engine's bond loop looks
// the storage index up each step. A broken bond stays in the store with how it broke (status), so
// that counts and outputs can report it; it carries nothing more, and keeps in its state the loads
// it carried on the step it broke (what released_energy() sums; restart files keep them).
//
// The engine visits the bonds after the contact laws, in bond order, in blocks computed in SIMD
// lanes, and adds each bond's force and torques into its balls' sums in that order: the sums are
// the same bits on any thread count and instruction set (one thread, for now). An empty store
// costs one size test per step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>
#include <dem/contact/parallel_bond.hpp>
#include <dem/core/particles.hpp>

namespace dem {

struct BondStore {
  // the pieces: stable particle ids (balls)
  std::vector<ParticleId> first, second;
  // per-bond parameters (ParallelBondLaw::Params)
  std::vector<double> radius;            // m
  std::vector<double> normal_stiffness;  // Pa/m
  std::vector<double> shear_stiffness;   // Pa/m
  std::vector<double> tensile_strength;  // Pa
  std::vector<double> cohesion;          // Pa
  std::vector<double> friction_angle;    // rad
  // state (ParallelBondLaw::State)
  std::vector<double> normal_force;  // N, tension positive
  std::vector<Vec3> shear_force;     // N, on piece 2
  std::vector<double> twist_moment;  // N m, on piece 2 about the normal
  std::vector<Vec3> bend_moment;     // N m, on piece 2
  std::vector<std::uint8_t> status;  // BondStatus

  std::size_t size() const { return first.size(); }
  bool empty() const { return first.empty(); }

  /// Appends an intact bond between balls `a` and `b` (stable ids) with no load; returns its index.
  std::size_t add(ParticleId a, ParticleId b, const ParallelBondLaw::Params& p) {
    first.push_back(a), second.push_back(b);
    radius.push_back(p.radius), normal_stiffness.push_back(p.normal_stiffness);
    shear_stiffness.push_back(p.shear_stiffness), tensile_strength.push_back(p.tensile_strength);
    cohesion.push_back(p.cohesion), friction_angle.push_back(p.friction_angle);
    normal_force.push_back(0.0), shear_force.push_back(Vec3::Zero());
    twist_moment.push_back(0.0), bend_moment.push_back(Vec3::Zero());
    status.push_back(static_cast<std::uint8_t>(BondStatus::intact));
    return size() - 1;
  }

  ParallelBondLaw::Params params(std::size_t k) const {
    return {radius[k], normal_stiffness[k], shear_stiffness[k], tensile_strength[k], cohesion[k], friction_angle[k]};
  }
  ParallelBondLaw::State state(std::size_t k) const {
    return {normal_force[k], shear_force[k], twist_moment[k], bend_moment[k]};
  }
  void set_state(std::size_t k, const ParallelBondLaw::State& s) {
    normal_force[k] = s.normal_force, shear_force[k] = s.shear_force;
    twist_moment[k] = s.twist_moment, bend_moment[k] = s.bend_moment;
  }
  BondStatus status_of(std::size_t k) const { return static_cast<BondStatus>(status[k]); }
  bool intact(std::size_t k) const { return status[k] == static_cast<std::uint8_t>(BondStatus::intact); }

  /// The strain energy the broken bonds held on the step each broke, J (the energy released by
  /// breakage; ParallelBondLaw::strain_energy of the loads a broken bond keeps).
  double released_energy() const {
    double e = 0.0;
    for (std::size_t k = 0; k < size(); ++k)
      if (!intact(k)) e += ParallelBondLaw::strain_energy(params(k), state(k));
    return e;
  }

  /// How many bonds have status `s`.
  std::size_t count(BondStatus s) const {
    std::size_t n = 0;
    for (const std::uint8_t b : status) n += b == static_cast<std::uint8_t>(s);
    return n;
  }
};

}  // namespace dem
