// Contact forces of one step: each contact type runs its own law-typed loop, adding each contact's
// force and torque into its particles' sums in contact order. With several threads, each takes a
// contiguous share of the contacts, sized by the speed it showed; a particle with contacts in two
// shares gets the first share's parts directly and the later shares' parts afterwards, in share
// order, and a thread done early takes chunks from the end of another's share with all their parts
// deferred (contact_loops.hpp). So every particle's sum is the serial one, bit for bit, for any
// thread count, any split and whoever computes a chunk, and only the particles on the shares'
// borders and in the taken chunks cost a deferred add.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <dem/base/errors.hpp>
#include <dem/core/contact_loops.hpp>
#include <dem/core/world.hpp>

namespace dem {

namespace {

const ContactModel& model_for(const std::shared_ptr<const ContactModel>& model, ContactKind kind) {
  if (!model)
    throw InputError(std::string("no contact model set for ") + to_string(kind) +
                     " contacts, but such contacts exist: call World::set_contact_model");
  return *model;
}

}  // namespace

void World::plan_shares() {
  // Re-planned after every rebuild and every few hundred steps: contacts that open or close move
  // the work between shares. The plan never changes a result, only who computes what.
  constexpr std::int64_t replan_every = 250;
  if (!share_plan_stale_ && shared_.size() == state_.particles.size() && state_.clock.steps - shares_planned_at_ < replan_every) return;
  const std::size_t n = state_.particles.size();
  shared_.assign(n, 0);
  std::vector<std::int32_t> owner;
  state_.contacts.for_each_pair_set([&](PairContacts& c) {
    const auto count = static_cast<std::int64_t>(c.size());
    const int threads = threads_for(count, threads_);
    // Work units: a touching contact costs about four separated near candidates, and the loops
    // skip the others.
    std::vector<std::uint8_t> near(static_cast<std::size_t>(count), 0);
    for (const std::int32_t k : c.near) near[static_cast<std::size_t>(k)] = 1;
    auto work = [&c, &near](std::int64_t k) -> std::int64_t {
      const auto s = static_cast<std::size_t>(k);
      return near[s] == 0 ? 0 : s < c.touching.size() && c.touching[s] != 0 ? 4 : 1;
    };
    // Each thread's share of the work: equal, or in proportion to the speed each thread showed in
    // its share since the last plan. A VM's cores can differ by a third in speed (and a laptop's
    // performance and efficiency cores by more): an equal split waits for the slowest.
    const std::vector<double> fraction =
        c.share_done.size() == static_cast<std::size_t>(threads)
            ? speed_fractions(c.share_done, c.share_seconds)
            : std::vector<double>(static_cast<std::size_t>(threads), 1.0 / threads);
    if (c.kind == ContactKind::BallBall) thread_fractions_ = fraction;
    c.shares = split_work(count, fraction, work);
    const std::vector<std::int64_t>& shares = c.shares;
    c.share_seconds.assign(static_cast<std::size_t>(threads), 0.0);
    c.share_done.assign(static_cast<std::size_t>(threads), 0);
    owner.assign(n, -1);
    for (int t = 0; t < threads; ++t)
      for (std::int64_t k = shares[static_cast<std::size_t>(t)]; k < shares[static_cast<std::size_t>(t) + 1]; ++k)
        for (const std::int32_t piece : {c.first[static_cast<std::size_t>(k)], c.second[static_cast<std::size_t>(k)]}) {
          std::int32_t& o = owner[static_cast<std::size_t>(piece)];
          if (o < 0) o = t;
          else if (o != t) shared_[static_cast<std::size_t>(piece)] = 1;
        }
  });
  // Each share's longest run of contacts that touch no particle shared between shares (shared_
  // is complete only now: a particle can be shared in any of the sets).
  state_.contacts.for_each_pair_set([&](PairContacts& c) {
    c.unshared_run.assign(c.shares.empty() ? 0 : c.shares.size() - 1, {0, 0});
    for (std::size_t t = 0; t < c.unshared_run.size(); ++t) {
      auto& longest = c.unshared_run[t];
      std::int64_t run_begin = c.shares[t];
      for (std::int64_t k = c.shares[t]; k <= c.shares[t + 1]; ++k) {
        const auto s = static_cast<std::size_t>(k);
        if (k < c.shares[t + 1] && shared_[static_cast<std::size_t>(c.first[s])] == 0 &&
            shared_[static_cast<std::size_t>(c.second[s])] == 0)
          continue;
        if (k - run_begin > longest.second - longest.first) longest = {run_begin, k};
        run_begin = k + 1;
      }
    }
  });
  share_plan_stale_ = false;
  shares_planned_at_ = state_.clock.steps;
}

void World::compute_forces(bool record_pair_forces) {
  KernelContext ctx;
  ctx.record_pair_forces = record_pair_forces;
  ctx.particles = &state_.particles;
  ctx.walls = &state_.walls;
  ctx.dt = state_.clock.dt;
  ctx.threads = threads_;
  const auto [owned_begin, owned_end] = owned_range();
  ctx.owned_begin = static_cast<std::int64_t>(owned_begin);
  ctx.owned_end = static_cast<std::int64_t>(owned_end);

  ParticleStore& p = state_.particles;
  WorldContacts& contacts = state_.contacts;
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(threads_for(n, threads_))
  for (std::int64_t i = 0; i < n; ++i) {
    p.f[static_cast<std::size_t>(i)].setZero();
    p.t[static_cast<std::size_t>(i)].setZero();
  }
  ctx.scatter_force = p.f.data();
  ctx.scatter_torque = p.t.data();
  // The walls' totals of this step. The wall loops add into them as they go, unless the World is
  // spread: then every subdomain's wall records come first (share_contact_results).
  for (auto& w : state_.walls) {
    w.force.setZero();
    w.moment.setZero();
    w.contact_count = 0;
    w.stiffness_sum = 0.0;
  }
  if (!spread()) ctx.wall_totals = &state_.walls;
  const bool parallel = threads_for(static_cast<std::int64_t>(contacts.ball_ball.size()), threads_) > 1;
  if (parallel) {
    plan_shares();
    ctx.shared = shared_.data();
    ctx.thread_fractions = &thread_fractions_;
  }
  auto lap = std::chrono::steady_clock::now();
  const auto time_into = [&lap](double& part) {
    const auto now = std::chrono::steady_clock::now();
    part += std::chrono::duration<double>(now - lap).count();
    lap = now;
  };
  time_into(timing_.force_sums);
  // Each set with its law; the worst overlap of the step over all of them (the first set wins a tie).
  WorstOverlap worst;
  contacts.for_each_set([&](auto& set) {
    OverlapMonitor set_worst;
    const ContactKind law = WorldContacts::law_kind(set);
    if (set.size() > 0) model_for(models_[static_cast<std::size_t>(law)], law).compute(set, ctx, set_worst);
    time_into(law == ContactKind::BallBall ? timing_.ball_ball
              : law == ContactKind::BallPebble ? timing_.ball_pebble
                                                : timing_.ball_facet);
    if (set_worst.ratio > worst.monitor.ratio) worst = WorstOverlap{set_worst, &set};
  });

  time_into(timing_.force_sums);
  share_contact_results(worst.monitor.ratio);  // spread over processes: pebbles and wall contacts of every subdomain
  time_into(timing_.communication);

  if (!ctx.wall_totals)
    contacts.for_each_wall_set([&](const WallContacts& wc) {
      detail::add_wall_contacts(wc, 0, static_cast<std::int64_t>(wc.size()), p.f.data(), p.t.data(), state_.walls);
    });
  pair_records_current_ = record_pair_forces;
  check_stability(global_worst(worst));
  time_into(timing_.force_sums);
}

}  // namespace dem
