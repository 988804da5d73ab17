// Time integration (leapfrog: v(t+dt/2) = v(t-dt/2) + a(t) dt, x(t+dt) = x(t) + v(t+dt/2) dt) with
// PFC's local non-viscous damping, rigid clumps, moving walls, and the checks that stop a run
// which has gone unstable before it produces garbage.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <dem/base/errors.hpp>
#include <dem/core/world.hpp>

#include "leapfrog.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace dem {

using detail::damped;
using detail::masked_add;

namespace {

/// Pebble i's torque about its clump's centre: its force's moment and its contact torque. One
/// function for both ways integrate() sums them, so that both give the same bits.
inline Vec3 pebble_torque(const ParticleStore& p, std::size_t i, const Clump& c) {
  return (p.x[i] - c.x).cross(p.f[i]) + p.t[i];
}

}  // namespace

void World::integrate() {
  ParticleStore& p = state_.particles;
  const double alpha = state_.settings.local_damping;
  const Vec3 g = state_.settings.gravity;
  const double dt = state_.clock.dt;
  // This process's particles (all of them unless the World is spread over processes).
  const auto [owned_begin, owned_end] = owned_range();
  const auto first = static_cast<std::int64_t>(owned_begin);
  const auto n = static_cast<std::int64_t>(owned_end - owned_begin);
  const double step_ratio = state_.settings.max_step_travel_ratio;
  // broad_phase_.positions_at_near() is current: step() refreshed the near lists before the forces
  const DampingFrame* frame = damping_frame_.at_rest() ? nullptr : &damping_frame_;
  const detail::LeapfrogStep leapfrog_step{g, alpha, dt, step_ratio * step_ratio, state_.rebuild.x_at_rebuild.data(), broad_phase_.positions_at_near().data(), frame};
  double travel_sq = state_.rebuild.max_travel_sq, near_travel_sq = broad_phase_.near_travel_sq();
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();

  // Each thread a contiguous range of whole groups of eight (the kernel's SIMD width), sized by
  // the threads' speeds in the pair loop: a particle's update depends on nothing else, so any
  // split gives the same bits.
  const int threads = threads_for(n, threads_);
#pragma omp parallel num_threads(open_team(threads)) reduction(max : travel_sq, near_travel_sq) reduction(min : bad)
  {
#if defined(_OPENMP)
    const std::int64_t team = omp_get_num_threads(), me = omp_get_thread_num();
#else
    const std::int64_t team = 1, me = 0;
#endif
    const std::int64_t groups = (n + 7) / 8;
    const std::vector<double>* fraction = team > 1 ? &plan_.thread_fractions() : nullptr;  // by speed (StepPlan)
    const std::int64_t begin = first + std::min(n, 8 * share_begin(groups, fraction, team, me));
    const std::int64_t end = first + std::min(n, 8 * share_begin(groups, fraction, team, me + 1));
    detail::LeapfrogTally tally{travel_sq, near_travel_sq, bad};
    detail::leapfrog(p, leapfrog_step, begin, end, tally);
    travel_sq = tally.travel_sq;
    near_travel_sq = tally.near_travel_sq;
    bad = tally.first_unstable;
  }
  if (spread()) {  // the largest travels and the first unstable particle of all subdomains
    double maxima[3] = {travel_sq, near_travel_sq, -static_cast<double>(bad)};
    global_max(maxima, 3);
    travel_sq = maxima[0], near_travel_sq = maxima[1];
    if (maxima[2] != -static_cast<double>(std::numeric_limits<std::int64_t>::max())) {
      bad = static_cast<std::int64_t>(-maxima[2]);
      synchronise();  // the message reads the particle where it is owned
    }
  }
  state_.rebuild.max_travel_sq = travel_sq;
  broad_phase_.set_near_travel_sq(near_travel_sq);
  if (bad != std::numeric_limits<std::int64_t>::max()) {
    const auto i = static_cast<std::size_t>(bad);
    std::ostringstream what;
    what.precision(4);
    if (!p.x[i].allFinite() || !p.v[i].allFinite() || !p.w[i].allFinite())
      what << "its position or velocity became NaN or infinite";
    else
      what << "it moved " << p.v[i].norm() * dt / p.radius[i] << " radii in one step (limit "
           << state_.settings.max_step_travel_ratio << ", speed " << p.v[i].norm() << " m/s)";
    fail(what.str(), i);
  }

  // Clumps: rigid bodies driven by the forces on their pebbles (docs/model.md 4). Each clump is
  // its own: they run in parallel (a ring stack has thousands of pebbles), each summing its
  // pebbles' shares in order. With several threads the shares are found first, each thread those
  // of the pebbles stored in its range: a clump's pebbles lie all over the storage, in lines that
  // either thread's pair loop wrote. One thread reads them where they are.
  const auto clump_count = static_cast<std::int64_t>(state_.clumps.size());
  std::int64_t bad_clump = clump_count;
  const int clump_threads = threads_for(pebble_count(), threads_);
  if (clump_count > 0 && clump_threads > 1) {
    refresh_pebble_layout();
    pebble_shares();
  }
#pragma omp parallel for schedule(static) num_threads(open_team(clump_threads)) reduction(min : bad_clump)
  for (std::int64_t ci = 0; ci < clump_count; ++ci) {
    Clump& c = state_.clumps[static_cast<std::size_t>(ci)];
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    if (clump_threads > 1) {
      for (std::size_t k = pebble_begin_[static_cast<std::size_t>(ci)]; k < pebble_begin_[static_cast<std::size_t>(ci) + 1]; ++k) {
        force += pebble_force_[k];
        torque += pebble_torque_[k];
      }
    } else {
      for (ParticleId pid : c.pebbles) {
        const std::size_t i = p.index_of(pid);
        force += p.f[i];
        torque += pebble_torque(p, i, c);
      }
    }
    c.force = force;
    c.torque = torque;
    const Vec3 damped_velocity = frame ? Vec3(c.v - frame->velocity_at(c.x)) : c.v;  // relative to the frame
    const Vec3 total_force = damped(force + c.mass * g + c.applied_force, damped_velocity, alpha);
    masked_add(c.v, total_force * (dt / c.mass), c.fixed, 0);
    if ((c.fixed & dof_rotation) != dof_rotation) {
      const Mat3 inertia = c.inertia_world();
      const Vec3 total_torque =
          damped(torque + c.applied_torque, frame ? Vec3(c.w - frame->spin()) : c.w, alpha) - c.w.cross(inertia * c.w);
      masked_add(c.w, inertia.ldlt().solve(total_torque) * dt, c.fixed, 3);
    }
    // A prescribed (fixed) spin turns the clump too.
    const double angle = c.w.norm() * dt;
    if (angle > 0.0) c.orientation = (Quat(Eigen::AngleAxisd(angle, c.w.normalized())) * c.orientation).normalized();
    c.x += c.v * dt;
    c.displacement += c.v * dt;
    // A finite spin whose norm overflows makes the orientation NaN while w itself stays finite;
    // the pebbles would then go NaN unseen and break the next broad-phase rebuild.
    if (!c.x.allFinite() || !c.v.allFinite() || !c.w.allFinite() || !c.orientation.coeffs().allFinite())
      bad_clump = std::min(bad_clump, ci);
  }
  if (bad_clump < clump_count)
    fail("its clump became NaN or infinite", p.index_of(state_.clumps[static_cast<std::size_t>(bad_clump)].pebbles.front()));
  if (!state_.clumps.empty()) update_pebbles();

  for (std::size_t w = 0; w < state_.walls.size(); ++w) {
    Wall& wall = state_.walls[w];
    if (wall.velocity.isZero(0.0)) continue;
    const Vec3 move = wall.velocity * dt;
    for (Vec3& v : wall.mesh.vertices) v += move;
    wall.surface.point += move;
    wall.reference_point += move;
    wall.displacement += move;
    if (w < state_.rebuild.wall_disp_at_rebuild.size())
      state_.rebuild.max_wall_travel = std::max(state_.rebuild.max_wall_travel, (wall.displacement - state_.rebuild.wall_disp_at_rebuild[w]).norm());
    else
      state_.rebuild.need_rebuild = true;
  }
  // The periodic cell deforms with the step, as the particles moved (h' = L h).
  if (state_.cell) state_.cell->advance(dt);
}

std::int64_t World::pebble_count() const {
  std::int64_t count = 0;
  for (const Clump& c : state_.clumps) count += static_cast<std::int64_t>(c.pebbles.size());
  return count;
}

void World::refresh_pebble_layout() {
  const std::size_t clump_count = state_.clumps.size();
  // A clump added or a storage change not announced (ParticleStore edited by hand) shows as counts.
  if (!pebble_layout_stale_ && pebble_begin_.size() == clump_count + 1 &&
      pebble_begin_.back() == static_cast<std::size_t>(pebble_count()))
    return;
  const ParticleStore& p = state_.particles;
  pebble_begin_.assign(1, 0);
  pebbles_in_storage_.clear();
  for (std::size_t ci = 0; ci < clump_count; ++ci) {
    const Clump& c = state_.clumps[ci];
    for (std::size_t k = 0; k < c.pebbles.size(); ++k)
      pebbles_in_storage_.push_back({static_cast<std::int32_t>(p.index_of(c.pebbles[k])), static_cast<std::int32_t>(ci),
                                     static_cast<std::int32_t>(k)});
    pebble_begin_.push_back(pebbles_in_storage_.size());
  }
  std::sort(pebbles_in_storage_.begin(), pebbles_in_storage_.end(),
            [](const PebbleSlot& a, const PebbleSlot& b) { return a.index < b.index; });
  pebble_layout_stale_ = false;
}

// Each thread takes the pebbles stored in its range of the integration (integrate(): whole groups
// of eight, by the threads' speeds), whose lines its pair loop share mostly wrote. A pebble's
// terms and place depend on it and its clump only, so any split gives the same bits.
std::pair<const World::PebbleSlot*, const World::PebbleSlot*> World::pebbles_of_this_thread() const {
#if defined(_OPENMP)
  const std::int64_t team = omp_get_num_threads(), me = omp_get_thread_num();
#else
  const std::int64_t team = 1, me = 0;
#endif
  const PebbleSlot* const slots = pebbles_in_storage_.data();
  const PebbleSlot* const slots_end = slots + pebbles_in_storage_.size();
  const auto n = static_cast<std::int64_t>(state_.particles.size());
  const std::int64_t groups = (n + 7) / 8;
  const std::vector<double>* fraction = team > 1 ? &plan_.thread_fractions() : nullptr;
  const std::int64_t begin = std::min(n, 8 * share_begin(groups, fraction, team, me));
  const std::int64_t end = std::min(n, 8 * share_begin(groups, fraction, team, me + 1));
  const auto by_index = [](const PebbleSlot& s, std::int64_t i) { return s.index < i; };
  const PebbleSlot* const first = std::lower_bound(slots, slots_end, begin, by_index);
  return {first, std::lower_bound(first, slots_end, end, by_index)};
}

void World::pebble_shares() {
  const ParticleStore& p = state_.particles;
  pebble_force_.resize(pebbles_in_storage_.size());
  pebble_torque_.resize(pebbles_in_storage_.size());
#pragma omp parallel num_threads(open_team(threads_for(static_cast<std::int64_t>(pebbles_in_storage_.size()), threads_)))
  {
    const auto [first, last] = pebbles_of_this_thread();
    for (const PebbleSlot* s = first; s != last; ++s) {
      const auto i = static_cast<std::size_t>(s->index);
      const std::size_t k = pebble_begin_[static_cast<std::size_t>(s->clump)] + static_cast<std::size_t>(s->place);
      pebble_force_[k] = p.f[i];
      pebble_torque_[k] = pebble_torque(p, i, state_.clumps[static_cast<std::size_t>(s->clump)]);
    }
  }
}

void World::update_pebbles() {
  ParticleStore& p = state_.particles;
  double travel_sq = state_.rebuild.max_travel_sq, near_travel_sq = broad_phase_.near_travel_sq();
  // Plain pointers in locals: a pebble's stores are doubles, which could be a clump's own or a
  // vector's size for all the compiler knows, and it would reload each of them for every pebble.
  Vec3* const x = p.x.data();
  Vec3* const v = p.v.data();
  Vec3* const w = p.w.data();
  const Vec3* const x_at_rebuild = state_.rebuild.x_at_rebuild.data();
  const std::size_t rebuild_count = state_.rebuild.x_at_rebuild.size();
  const Vec3* const x_at_near = broad_phase_.positions_at_near().data();
  const std::size_t near_count = broad_phase_.positions_at_near().size();
  // Pebble i at `arm` from its clump's centre, which moves at `velocity` and spins at `spin`.
  const auto place = [=](std::size_t i, const Vec3& centre, const Vec3& velocity, const Vec3& spin, const Vec3& arm,
                         double& moved_sq, double& moved_near_sq) {
    x[i] = centre + arm;
    v[i] = velocity + spin.cross(arm);
    w[i] = spin;
    if (i < rebuild_count) moved_sq = std::max(moved_sq, (x[i] - x_at_rebuild[i]).squaredNorm());
    if (i < near_count) moved_near_sq = std::max(moved_near_sq, (x[i] - x_at_near[i]).squaredNorm());
  };
  const int threads = threads_for(pebble_count(), threads_);
  if (threads == 1) {
    // Clump by clump, each clump's motion held in registers (a pebble's place does not depend on
    // the order: the same bits as below).
    for (const Clump& c : state_.clumps) {
      const Mat3 r = c.orientation.toRotationMatrix();
      const Vec3 centre = c.x, velocity = c.v, spin = c.w;
      for (std::size_t k = 0; k < c.pebbles.size(); ++k)
        place(p.index_of(c.pebbles[k]), centre, velocity, spin, r * c.pebble_offsets[k], travel_sq, near_travel_sq);
    }
  } else {
    refresh_pebble_layout();
    clump_rotation_.resize(state_.clumps.size());
    for (std::size_t ci = 0; ci < state_.clumps.size(); ++ci)
      clump_rotation_[ci] = state_.clumps[ci].orientation.toRotationMatrix();
    const Clump* const clumps = state_.clumps.data();
    const Mat3* const rotation = clump_rotation_.data();
#pragma omp parallel num_threads(open_team(threads)) reduction(max : travel_sq, near_travel_sq)
    {
      const auto [first, last] = pebbles_of_this_thread();
      for (const PebbleSlot* s = first; s != last; ++s) {
        const Clump& c = clumps[s->clump];
        place(static_cast<std::size_t>(s->index), c.x, c.v, c.w,
              rotation[s->clump] * c.pebble_offsets[static_cast<std::size_t>(s->place)], travel_sq, near_travel_sq);
      }
    }
  }
  state_.rebuild.max_travel_sq = travel_sq;
  broad_phase_.set_near_travel_sq(near_travel_sq);
}

void World::check_stability(const WorstOverlap& worst) {
  if (worst.monitor.ratio <= state_.settings.max_overlap_ratio) return;
  const auto k = static_cast<std::size_t>(worst.monitor.contact);
  std::ostringstream what;
  what.precision(4);
  std::size_t ball = 0;
  ContactKind kind = ContactKind::BallFacet;
  if (const auto* walls = std::get_if<const WallContacts*>(&worst.set)) {
    const WallContacts& c = **walls;
    ball = static_cast<std::size_t>(c.ball[k]);
    what << "it overlaps wall '" << state_.walls[static_cast<std::size_t>(c.wall[k])].name << "' by " << worst.monitor.ratio
         << " of its radius";
  } else {
    const PairContacts& c = *std::get<const PairContacts*>(worst.set);
    kind = c.kind;
    ball = static_cast<std::size_t>(c.first[k]);
    what << "it overlaps " << (kind == ContactKind::BallBall ? "ball" : "pebble") << " id "
         << state_.particles.id[static_cast<std::size_t>(c.second[k])] << " by " << worst.monitor.ratio
         << " of the smaller radius";
  }
  what << " (limit " << state_.settings.max_overlap_ratio << ")";
  fail(what.str(), ball, kind);
}

namespace {

// The key that sets a law's stiffness, as the configuration names it.
std::string stiffness_key(const ContactModel* model) {
  if (model == nullptr) return "stiffness";
  const std::string law = model->law_name();
  if (law.starts_with("hertz")) return "youngs_modulus (law " + law + ")";
  if (law == "linear" || law == "rolling-linear") return "effective_modulus (law " + law + ")";
  return "stiffness (law " + law + ")";
}

}  // namespace

void World::fail(const std::string& what, std::size_t i, std::optional<ContactKind> kind) const {
  std::ostringstream msg;
  msg.precision(4);
  const Vec3& x = state_.particles.x[i];
  msg << "simulation unstable at step " << state_.clock.steps << " (t = " << state_.clock.time << " s): ball id " << state_.particles.id[i]
      << " at (" << x.x() << ", " << x.y() << ", " << x.z() << ") m, radius " << state_.particles.radius[i] << " m: " << what << ". ";
  double critical = std::numeric_limits<double>::quiet_NaN();
  try {
    critical = critical_time_step();
  } catch (const std::exception&) {
  }
  // The single-contact stiffness of each contact type for this ball: the stiffest sets the stable
  // step, a soft one beside it is the usual cause when the step is below the estimate.
  std::optional<ContactKind> stiffest;
  double stiffest_k = 0.0;
  std::ostringstream stiffness;
  stiffness.precision(3);
  for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) {
    const ContactModel* model = contact_model(k);
    if (model == nullptr) continue;
    ContactKinematics c{};
    c.kind = k;
    c.radius_1 = state_.particles.radius[i];
    c.radius_2 = k == ContactKind::BallFacet ? 0.0 : state_.particles.radius[i];
    c.effective_radius = k == ContactKind::BallFacet ? c.radius_1 : c.radius_1 / 2;
    c.normal = Vec3::UnitZ();
    const double kn = model->stiffness(c).normal;
    stiffness << (stiffness.tellp() > 0 ? ", " : "") << to_string(k) << " " << kn << " N/m (" << model->law_name() << ")";
    if (kn > stiffest_k) stiffest_k = kn, stiffest = k;
  }
  if (!std::isfinite(critical) || stiffness.tellp() == 0) {
    msg << "Likely cause: no contact bounds the time step here (no contact law, or none touching), so the "
           "time step " << state_.clock.dt << " s is too large for the speeds given to the balls. Reduce time_step or the speeds.";
  } else if (state_.clock.dt > critical) {
    msg << "Likely cause: the time step " << state_.clock.dt << " s is above the stable estimate " << critical
        << " s for the contact stiffness and mass (normal stiffness for this ball: " << stiffness.str()
        << "). Reduce time_step or time_step_safety.";
  } else {
    msg << "The time step " << state_.clock.dt << " s is below the stable estimate " << critical << " s";
    if (stiffest) msg << " (set by the stiffest contact type, " << to_string(*stiffest) << ")";
    msg << ", so the step is not the cause. Normal stiffness for this ball: " << stiffness.str() << ". Likely cause: ";
    if (kind && stiffest && *kind != *stiffest)
      msg << "the " << to_string(*kind) << " contacts are too soft for the load on them beside the stiffer "
          << to_string(*stiffest) << " contacts: raise the " << to_string(*kind) << " "
          << stiffness_key(contact_model(*kind)) << ", or lower the load or the loading speed.";
    else
      msg << "the load (a wall's speed or stress, or gravity) is too large for the contact stiffness: overlaps grow "
             "without bound. Raise the " << to_string(kind.value_or(ContactKind::BallBall)) << " "
          << stiffness_key(contact_model(kind.value_or(ContactKind::BallBall))) << ", or lower the load or the loading speed.";
  }
  throw InstabilityError(msg.str());
}

}  // namespace dem
