// Contact forces of one step: each contact type runs its own law-typed loop, writing one force
// record per contact; then every particle sums its records in a fixed order (its incidence list),
// so the result is bit-identical for any thread count.
#include <algorithm>
#include <cmath>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>

namespace dem {

namespace {

const ContactModel& model_for(const std::shared_ptr<const ContactModel>& model, ContactKind kind) {
  if (!model)
    throw InputError(std::string("no contact model set for ") + to_string(kind) +
                     " contacts, but such contacts exist: call World::set_contact_model");
  return *model;
}

void gather(const PairContacts& c, const std::vector<std::int32_t>& offsets, const std::vector<std::int32_t>& entries,
            const std::vector<Vec3>& x, std::size_t i, Vec3& force, Vec3& torque) {
  for (std::int32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
    const auto entry = static_cast<std::size_t>(entries[static_cast<std::size_t>(e)]);
    const std::size_t k = entry >> 1;
    if (entry & 1U) {  // i is piece 2
      force += c.force[k];
      torque += second_torque(x[i] - x[static_cast<std::size_t>(c.first[k])], c.force[k], c.torque_first[k]);
    } else {
      force -= c.force[k];
      torque += c.torque_first[k];
    }
  }
}

}  // namespace

void World::compute_forces() {
  KernelContext ctx;
  ctx.particles = &particles_;
  ctx.walls = &walls_;
  ctx.dt = dt_;
  ctx.threads = threads_;

  ParticleStore& p = particles_;
  const auto n = static_cast<std::int64_t>(p.size());
  // One thread: add forces as they are computed. Several: per-contact records, then a per-particle
  // gather in the same contact order. Both give the same bits.
  const bool serial = threads_for(static_cast<std::int64_t>(ball_ball_.size()), threads_) == 1;
  if (!serial && last_step_serial_) {
    // Serial steps leave the per-contact torque records stale; the gather must not see them.
    for (PairContacts* c : {&ball_ball_, &ball_pebble_}) c->torque_first.assign(c->size(), Vec3::Zero());
  }
  last_step_serial_ = serial;
  if (serial) {
    std::fill(p.f.begin(), p.f.end(), Vec3::Zero());
    std::fill(p.t.begin(), p.t.end(), Vec3::Zero());
    ctx.scatter_force = p.f.data();
    ctx.scatter_torque = p.t.data();
  }
  OverlapMonitor worst_bb, worst_bp, worst_wall;
  if (ball_ball_.size() > 0) model_for(models_[0], ContactKind::BallBall).compute(ball_ball_, ctx, worst_bb);
  if (ball_pebble_.size() > 0) model_for(models_[2], ContactKind::BallPebble).compute(ball_pebble_, ctx, worst_bp);
  if (wall_contacts_.size() > 0) model_for(models_[1], ContactKind::BallFacet).compute(wall_contacts_, ctx, worst_wall);

  if (!serial) {
#pragma omp parallel for schedule(static) num_threads(threads_for(n, threads_))
    for (std::int64_t s = 0; s < n; ++s) {
      const auto i = static_cast<std::size_t>(s);
      Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
      gather(ball_ball_, bb_offsets_, bb_entries_, p.x, i, force, torque);
      gather(ball_pebble_, bp_offsets_, bp_entries_, p.x, i, force, torque);
      p.f[i] = force;
      p.t[i] = torque;
    }
  }

  for (auto& w : walls_) {
    w.force.setZero();
    w.moment.setZero();
    w.contact_count = 0;
    w.stiffness_sum = 0.0;
  }
  const WallContacts& wc = wall_contacts_;
  for (std::size_t k = 0; k < wc.size(); ++k) {
    if (wc.normal_stiffness[k] == 0.0) continue;
    const auto b = static_cast<std::size_t>(wc.ball[k]);
    FacetWall& w = walls_[static_cast<std::size_t>(wc.wall[k])];
    p.f[b] -= wc.force[k];
    p.t[b] += wc.torque_ball[k];
    w.force += wc.force[k];
    w.moment += (wc.point[k] - w.reference_point).cross(wc.force[k]) + wc.moment[k];
    ++w.contact_count;
    w.stiffness_sum += wc.normal_stiffness[k];
  }

  // Stability: the worst overlap of the step, over all contact types.
  const OverlapMonitor* worst = &worst_bb;
  ContactKind kind = ContactKind::BallBall;
  if (worst_bp.ratio > worst->ratio) worst = &worst_bp, kind = ContactKind::BallPebble;
  if (worst_wall.ratio > worst->ratio) worst = &worst_wall, kind = ContactKind::BallFacet;
  check_stability(*worst, kind);
}

}  // namespace dem
