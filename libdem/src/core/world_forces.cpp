// Contact forces of one step: each contact type runs its own law-typed loop, adding each contact's
// force and torque into its particles' sums in contact order. With several threads, each takes a
// contiguous share of the contacts, sized by the speed it showed (the step's plan, StepPlan); a
// particle with contacts in two shares gets the first share's parts directly and the later shares'
// parts afterwards, in share order, and a thread done early takes chunks from the end of another's
// share with all their parts deferred (pair_loops.hpp). So every particle's sum is the serial one,
// bit for bit, for any thread count, any split and whoever computes a chunk, and only the particles
// on the shares' borders and in the taken chunks cost a deferred add.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <type_traits>

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

void World::compute_forces(bool record_pair_forces) {
  KernelContext ctx;
  ctx.record_pair_forces = record_pair_forces;
  ctx.particles = &state_.particles;
  ctx.walls = &state_.walls;
  ctx.dt = state_.clock.dt;
  ctx.threads = threads_;
  plan_.set_owned(owned_range());  // spread over processes: this one's subdomain
  ctx.owned_begin = plan_.owned_begin();
  ctx.owned_end = plan_.owned_end();
  std::optional<ImageShifts> images;  // the periodic cell's shifts of this step
  if (state_.cell) images = state_.cell->image_shifts();
  ctx.images = images ? &*images : nullptr;

  ParticleStore& p = state_.particles;
  WorldContacts& contacts = state_.contacts;
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(open_team(threads_for(n, threads_)))
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
    plan_.plan_shares(contacts, p.size(), threads_, state_.clock.steps);
    ctx.shared = plan_.shared().data();
    ctx.thread_fractions = &plan_.thread_fractions();
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
    if (set.size() > 0) {
      const ContactModel& model = model_for(models_[static_cast<std::size_t>(law)], law);
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(set)>, PairContacts>)
        model.compute(set, plan_.pairs(set.kind), ctx, set_worst);
      else
        model.compute(set, ctx, set_worst);
    }
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
  if (!state_.bonds.empty()) compute_bond_forces();  // after every contact law (world_bonds.cpp)
  pair_records_current_ = record_pair_forces;
  check_stability(global_worst(worst));
  time_into(timing_.force_sums);
}

}  // namespace dem
