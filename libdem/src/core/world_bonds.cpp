// The bonds' part of a step: after the contact laws have summed their forces, each intact bond in
// bond order reads its balls' motion, advances its law (contact/parallel_bond.hpp) and adds its
// force and torques into the balls' sums. One thread, one bond at a time: every ball's sum gets
// its bond parts in the same order whatever the thread count, so the results are the same bits
// on any team. (A threaded loop would need the pair loops' deferred sums; bonds are few next to
// contacts in the runs so far.)
//
// The bond point is where a contact's would be: on the line of centres, halfway across the gap (or
// the overlap). In a periodic cell piece 2 is the image nearest to piece 1, found each step: a
// bond is far shorter than half the cell, which the World keeps at least three search cells wide.
#include <cmath>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/core/world.hpp>

namespace dem {

std::size_t World::add_bond(ParticleId a, ParticleId b, const ParallelBondLaw::Params& params) {
  require(!spread(), "a bond in a World spread over processes", std::to_string(ranks()) + " processes",
          "one process: bonds do not cross subdomains yet");
  const ParticleStore& p = state_.particles;
  const auto count = static_cast<ParticleId>(p.size());
  const std::string what = "bond " + std::to_string(state_.bonds.size());
  require(a >= 0 && a < count, what + " ball id", a, "in [0, " + std::to_string(count) + ")");
  require(b >= 0 && b < count, what + " ball id", b, "in [0, " + std::to_string(count) + ")");
  require(a != b, what + " ball ids", std::to_string(a) + " and " + std::to_string(b), "two different balls");
  require(!p.is_pebble(p.index_of(a)) && !p.is_pebble(p.index_of(b)), what + " ball ids",
          std::to_string(a) + " and " + std::to_string(b), "free balls, not pebbles of a clump (not supported yet)");
  params.validate(what);
  // The bond's stiffness counts in an automatic time step: estimated again at the next step.
  if (state_.settings.time_step <= 0.0) state_.clock.dt = 0.0;
  return state_.bonds.add(a, b, params);
}

void World::compute_bond_forces() {
  BondStore& bonds = state_.bonds;
  ParticleStore& p = state_.particles;
  const PeriodicCell* cell = state_.cell ? &*state_.cell : nullptr;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!bonds.intact(k)) continue;
    const std::size_t i = p.index_of(bonds.first[k]), j = p.index_of(bonds.second[k]);
    Vec3 d = p.x[j] - p.x[i];  // branch, m
    Vec3 v_second = p.v[j];
    if (cell) {  // the image of piece 2 nearest to piece 1
      const Vec3 reduced = cell->inverse() * d;
      const std::array<int, 3> n{static_cast<int>(-std::round(reduced.x())), static_cast<int>(-std::round(reduced.y())),
                                 static_cast<int>(-std::round(reduced.z()))};
      d += cell->image_shift(n);
      v_second += cell->image_velocity_shift(n);
    }
    const double dist = d.norm();
    if (!(dist > 0.0)) fail("bond " + std::to_string(k) + " joins two balls at the same place", i);
    ParallelBondLaw::Motion m;
    m.normal = d * (1.0 / dist);
    const double overlap = p.radius[i] + p.radius[j] - dist;   // m, negative across a gap
    const Vec3 arm_first = (p.radius[i] - 0.5 * overlap) * m.normal;  // bond point - x_i
    const Vec3 arm_second = arm_first - d;                           // bond point - x_j
    m.relative_velocity = (v_second + p.w[j].cross(arm_second)) - (p.v[i] + p.w[i].cross(arm_first));
    m.relative_angular_velocity = p.w[j] - p.w[i];
    m.dt = state_.clock.dt;
    ParallelBondLaw::State s = bonds.state(k), at_break;
    const BondStatus status = ParallelBondLaw::update(bonds.params(k), m, s, &at_break);
    if (status != BondStatus::intact) {  // it keeps the loads that broke it (BondStore::released_energy)
      bonds.set_state(k, at_break);
      bonds.status[k] = static_cast<std::uint8_t>(status);
      continue;
    }
    bonds.set_state(k, s);
    const Vec3 force = ParallelBondLaw::force(s, m.normal);  // on piece 2
    const Vec3 torque_first = -arm_first.cross(force) - ParallelBondLaw::moment(s, m.normal);
    p.f[j] += force;
    p.f[i] -= force;
    p.t[i] += torque_first;
    p.t[j] += second_torque(d, force, torque_first);
  }
}

}  // namespace dem
