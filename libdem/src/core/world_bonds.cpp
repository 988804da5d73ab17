// The bonds' part of a step: after the contact laws have summed their forces, the intact bonds in
// bond order are taken in blocks: each block's balls' motion is copied out, the bonds' law
// (contact/parallel_bond.hpp, update_lanes) runs for the whole block in SIMD lanes, and then each
// bond in turn stores its loads and adds its force and torques into its balls' sums. On a team,
// each thread computes the blocks of its share of the bonds and keeps their outcomes, and then one
// thread adds them: every ball's sum gets its bond parts in bond order whatever the thread count,
// so the results are the same bits on any team, and the same as one bond at a time on any
// instruction set.
//
// Why blocks: one bond's arithmetic is a chain of dependent square roots and divisions (the loads
// rotated into the bond plane, the edge stresses), which one bond at a time leaves the processor
// waiting on; side by side in lanes, as the contact blocks (core/contact_loops.hpp), they overlap.
//
// The bond point is where a contact's would be: on the line of centres, halfway across the gap (or
// the overlap). In a periodic cell piece 2 is the image nearest to piece 1, found each step: a
// bond is far shorter than half the cell, which the World keeps at least three search cells wide.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <dem/base/errors.hpp>
#include <dem/base/threads.hpp>
#include <dem/contact/lanes.hpp>
#include <dem/core/block_isa.hpp>
#include <dem/core/block_targets.hpp>
#include <dem/core/world.hpp>

namespace dem {

namespace {

constexpr int bond_block = 64;

/// A block of intact bonds: the inputs copied from the balls and the store, the loads (updated in
/// place) and the results, one entry per bond.
struct BondBlock {
  std::size_t bond[bond_block], first[bond_block], second[bond_block];  // bond index; balls' storage indices
  // inputs: branch d = x2 - x1 (m; to piece 2's nearest image in a cell), radii (m), both pieces'
  // velocities (piece 2's image's, m/s) and angular velocities (rad/s), x y z of each bond in turn
  double dx[bond_block], dy[bond_block], dz[bond_block], radius_1[bond_block], radius_2[bond_block];
  double v1[3 * bond_block], v2[3 * bond_block], w1[3 * bond_block], w2[3 * bond_block];
  // the bonds' parameters (ParallelBondLaw::Params; tan(phi) for the friction angle)
  double radius[bond_block], normal_stiffness[bond_block], shear_stiffness[bond_block];
  double tensile_strength[bond_block], cohesion[bond_block], tan_phi[bond_block];
  // loads (ParallelBondLaw::LaneState), in and out
  double normal_force[bond_block], fsx[bond_block], fsy[bond_block], fsz[bond_block];
  double twist_moment[bond_block], mbx[bond_block], mby[bond_block], mbz[bond_block];
  // results: distance of centres (m), force on piece 2, torques on pieces 1 and 2, BondStatus
  double distance[bond_block], fx[bond_block], fy[bond_block], fz[bond_block];
  double t1x[bond_block], t1y[bond_block], t1z[bond_block], t2x[bond_block], t2y[bond_block], t2z[bond_block];
  int status[bond_block];
};

/// The block's kinematics, law and torques, each bond independent of the others: the arithmetic
/// of one bond at a time, in the same order (the same bits).
DEM_HOT_INLINE void bond_lanes(BondBlock& b, int count, double dt) {
DEM_INDEPENDENT_ITERATIONS
  for (int m = 0; m < count; ++m) {
    const Lane3 d{b.dx[m], b.dy[m], b.dz[m]};
    const double dist = std::sqrt(squared_norm(d));
    const Lane3 normal = (1.0 / dist) * d;
    const double overlap = b.radius_1[m] + b.radius_2[m] - dist;   // m, negative across a gap
    const Lane3 arm_first = (b.radius_1[m] - 0.5 * overlap) * normal;  // bond point - x_1
    const Lane3 arm_second = arm_first - d;                             // bond point - x_2
    const Lane3 w1{b.w1[3 * m], b.w1[3 * m + 1], b.w1[3 * m + 2]}, w2{b.w2[3 * m], b.w2[3 * m + 1], b.w2[3 * m + 2]};
    const Lane3 v1{b.v1[3 * m], b.v1[3 * m + 1], b.v1[3 * m + 2]}, v2{b.v2[3 * m], b.v2[3 * m + 1], b.v2[3 * m + 2]};
    const Lane3 relative_velocity = (v2 + cross(w2, arm_second)) - (v1 + cross(w1, arm_first));
    const ParallelBondLaw::Params params{b.radius[m],           b.normal_stiffness[m], b.shear_stiffness[m],
                                         b.tensile_strength[m], b.cohesion[m],         0.0};
    ParallelBondLaw::LaneState s{b.normal_force[m], {b.fsx[m], b.fsy[m], b.fsz[m]}, b.twist_moment[m],
                                 {b.mbx[m], b.mby[m], b.mbz[m]}};
    b.status[m] = ParallelBondLaw::update_lanes(params, b.tan_phi[m], normal, relative_velocity, w2 - w1, dt, s);
    b.normal_force[m] = s.normal_force, b.twist_moment[m] = s.twist_moment;
    b.fsx[m] = s.shear_force.x, b.fsy[m] = s.shear_force.y, b.fsz[m] = s.shear_force.z;
    b.mbx[m] = s.bend_moment.x, b.mby[m] = s.bend_moment.y, b.mbz[m] = s.bend_moment.z;
    const Lane3 force = ParallelBondLaw::force(s, normal);  // on piece 2
    const Lane3 torque_first = -cross(arm_first, force) - ParallelBondLaw::moment(s, normal);
    const Lane3 torque_second = -cross(d, force) - torque_first;  // as second_torque()
    b.distance[m] = dist;
    b.fx[m] = force.x, b.fy[m] = force.y, b.fz[m] = force.z;
    b.t1x[m] = torque_first.x, b.t1y[m] = torque_first.y, b.t1z[m] = torque_first.z;
    b.t2x[m] = torque_second.x, b.t2y[m] = torque_second.y, b.t2z[m] = torque_second.z;
  }
}

// The block compiled for each instruction set (block_targets.hpp); the best is chosen at run time.
DEM_TARGET_AVX2 void bond_block_avx2(BondBlock& b, int count, double dt) { bond_lanes(b, count, dt); }
DEM_TARGET_AVX512 void bond_block_avx512(BondBlock& b, int count, double dt) { bond_lanes(b, count, dt); }
void bond_block_scalar(BondBlock& b, int count, double dt) { bond_lanes(b, count, dt); }

/// What one bond of a block did this step (the block's results for entry m): enough to add it to
/// its balls later, in bond order.
struct BondOutcome {
  std::size_t bond, first, second;  // bond index; balls' storage indices
  int status;                       // BondStatus
  double distance;                  // m, of the centres
  Lane3 force, torque_first, torque_second;
};
BondOutcome outcome(const BondBlock& b, int m) {
  return {b.bond[m],
          b.first[m],
          b.second[m],
          b.status[m],
          b.distance[m],
          {b.fx[m], b.fy[m], b.fz[m]},
          {b.t1x[m], b.t1y[m], b.t1z[m]},
          {b.t2x[m], b.t2y[m], b.t2z[m]}};
}

using BondKernel = void (*)(BondBlock&, int, double);
BondKernel bond_kernel() {
  switch (detail::block_isa()) {
    case detail::BlockIsa::avx512: return &bond_block_avx512;
    case detail::BlockIsa::avx2: return &bond_block_avx2;
    default: return &bond_block_scalar;
  }
}

/// Moves piece 2 of a bond with branch `d` = x2 - x1 to its image nearest piece 1 in `cell`:
/// d gets the image's shift and `v_second` (if given) its velocity shift.
void to_nearest_image(const PeriodicCell& cell, Vec3& d, Vec3* v_second) {
  const Vec3 reduced = cell.inverse() * d;
  const std::array<int, 3> n{static_cast<int>(-std::round(reduced.x())), static_cast<int>(-std::round(reduced.y())),
                             static_cast<int>(-std::round(reduced.z()))};
  d += cell.image_shift(n);
  if (v_second) *v_second += cell.image_velocity_shift(n);
}

}  // namespace

Vec3 World::bond_branch(std::size_t k) const {
  const BondStore& bonds = state_.bonds;
  require(k < bonds.size(), "bond index", k, "below the bond count " + std::to_string(bonds.size()));
  const ParticleStore& p = state_.particles;
  Vec3 d = p.x[p.index_of(bonds.second[k])] - p.x[p.index_of(bonds.first[k])];
  if (state_.cell) to_nearest_image(*state_.cell, d, nullptr);
  return d;
}

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
  const BondKernel kernel = bond_kernel();
  const double dt = state_.clock.dt;
  // The arrays as plain pointers: the block's stores could otherwise alias the vectors' own
  // pointers for the compiler, which would then reload them for every bond.
  const std::size_t total = bonds.size();
  const std::uint8_t* status = bonds.status.data();
  const ParticleId *first = bonds.first.data(), *second = bonds.second.data();
  const double *radius = bonds.radius.data(), *normal_stiffness = bonds.normal_stiffness.data();
  const double *shear_stiffness = bonds.shear_stiffness.data(), *tensile_strength = bonds.tensile_strength.data();
  const double *cohesion = bonds.cohesion.data(), *friction_angle = bonds.friction_angle.data();
  double *normal_force = bonds.normal_force.data(), *twist_moment = bonds.twist_moment.data();
  Vec3 *shear_force = bonds.shear_force.data(), *bend_moment = bonds.bend_moment.data();
  const Vec3 *x = p.x.data(), *v = p.v.data(), *w = p.w.data();
  const double* ball_radius = p.radius.data();
  Vec3 *f = p.f.data(), *t = p.t.data();
  const auto intact = static_cast<std::uint8_t>(BondStatus::intact);

  // 1. The intact bonds of [next, end), up to a block's worth, copied into `b` with their balls'
  //    motion and their loads; `next` moves past them. Returns how many.
  const auto gather = [&](BondBlock& b, std::size_t& next, std::size_t end) {
    int count = 0;
    for (; next < end && count < bond_block; ++next) {
      if (status[next] != intact) continue;
      const std::size_t k = next, i = p.index_of(first[k]), j = p.index_of(second[k]);
      Vec3 d = x[j] - x[i];  // branch, m
      Vec3 v_second = v[j];
      if (cell) to_nearest_image(*cell, d, &v_second);
      const int m = count++;
      b.bond[m] = k, b.first[m] = i, b.second[m] = j;
      b.dx[m] = d.x(), b.dy[m] = d.y(), b.dz[m] = d.z();
      b.radius_1[m] = ball_radius[i], b.radius_2[m] = ball_radius[j];
      for (int c = 0; c < 3; ++c) {
        b.v1[3 * m + c] = v[i][c], b.v2[3 * m + c] = v_second[c];
        b.w1[3 * m + c] = w[i][c], b.w2[3 * m + c] = w[j][c];
      }
      b.radius[m] = radius[k], b.normal_stiffness[m] = normal_stiffness[k];
      b.shear_stiffness[m] = shear_stiffness[k], b.tensile_strength[m] = tensile_strength[k];
      b.cohesion[m] = cohesion[k];
      b.tan_phi[m] = ParallelBondLaw::tan_friction(friction_angle[k]);
      b.normal_force[m] = normal_force[k], b.twist_moment[m] = twist_moment[k];
      b.fsx[m] = shear_force[k].x(), b.fsy[m] = shear_force[k].y(), b.fsz[m] = shear_force[k].z();
      b.mbx[m] = bend_moment[k].x(), b.mby[m] = bend_moment[k].y(), b.mbz[m] = bend_moment[k].z();
    }
    return count;
  };
  // 2. (the law: kernel) 3. The block's loads stored, each bond's own entries (any thread may):
  //    a broken bond keeps those that broke it (BondStore::released_energy).
  const auto store_loads = [&](const BondBlock& b, int count) {
    for (int m = 0; m < count; ++m) {
      const std::size_t k = b.bond[m];
      normal_force[k] = b.normal_force[m], twist_moment[k] = b.twist_moment[m];
      shear_force[k] = Vec3(b.fsx[m], b.fsy[m], b.fsz[m]);
      bend_moment[k] = Vec3(b.mbx[m], b.mby[m], b.mbz[m]);
    }
  };
  // 4. Bond k's outcome, in bond order on one thread: its status, or its force and torques added
  //    to its balls' sums.
  const auto add_to_balls = [&](const BondOutcome& o) {
    const std::size_t k = o.bond, i = o.first, j = o.second;
    if (!(o.distance > 0.0)) fail("bond " + std::to_string(k) + " joins two balls at the same place", i);
    if (o.status != static_cast<int>(BondStatus::intact)) {
      bonds.status[k] = static_cast<std::uint8_t>(o.status);
      return;
    }
    f[j].x() += o.force.x, f[j].y() += o.force.y, f[j].z() += o.force.z;
    f[i].x() -= o.force.x, f[i].y() -= o.force.y, f[i].z() -= o.force.z;
    t[i].x() += o.torque_first.x, t[i].y() += o.torque_first.y, t[i].z() += o.torque_first.z;
    t[j].x() += o.torque_second.x, t[j].y() += o.torque_second.y, t[j].z() += o.torque_second.z;
  };

  const int threads = threads_for(static_cast<std::int64_t>(total), threads_);
  if (threads <= 1) {  // block after block, each added as soon as it is computed
    thread_local BondBlock block;  // 30 kB: not on the stack
    std::size_t next = 0;
    while (const int count = gather(block, next, total)) {
      kernel(block, count, dt);
      store_loads(block, count);
      for (int m = 0; m < count; ++m) add_to_balls(outcome(block, m));
    }
    return;
  }
  // Each thread computes the blocks of its share of the bonds and keeps their outcomes by bond;
  // then one thread adds them in bond order (the sums of one thread: the same bits).
  thread_local std::vector<BondOutcome> outcomes;  // the calling thread's, kept between steps
  outcomes.resize(total);
  BondOutcome* kept = outcomes.data();
#pragma omp parallel for schedule(static) num_threads(open_team(threads))
  for (int share = 0; share < threads; ++share) {
    thread_local BondBlock block;
    const auto shares = static_cast<std::size_t>(threads), s = static_cast<std::size_t>(share);
    std::size_t next = total * s / shares;
    const std::size_t end = total * (s + 1) / shares;
    while (const int count = gather(block, next, end)) {
      kernel(block, count, dt);
      store_loads(block, count);
      for (int m = 0; m < count; ++m) kept[block.bond[m]] = outcome(block, m);
    }
  }
  for (std::size_t k = 0; k < total; ++k)
    if (status[k] == intact) add_to_balls(kept[k]);  // intact before this step: computed above
}

}  // namespace dem
