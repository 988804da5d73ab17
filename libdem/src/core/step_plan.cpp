// The threads' shares of the pair loops (step_plan.hpp). The plan never changes a result, only who
// computes what: every particle's sum is added in the serial contact order whatever the shares.
#include <dem/core/step_plan.hpp>

namespace dem {

void StepPlan::plan_shares(const WorldContacts& contacts, std::size_t particles, int threads_available,
                           std::int64_t step) {
  // Re-planned after every rebuild and every few hundred steps: contacts that open or close move
  // the work between shares.
  constexpr std::int64_t replan_every = 250;
  if (!shares_stale_ && shared_.size() == particles && step - shares_planned_at_ < replan_every) return;
  const std::size_t n = particles;
  shared_.assign(n, 0);
  std::vector<std::int32_t> owner;
  contacts.for_each_pair_set([&](const PairContacts& c) {
    PairPlan& plan = pairs(c.kind);
    const auto count = static_cast<std::int64_t>(c.size());
    const int threads = threads_for(count, threads_available);
    // Work units: a touching contact costs about four separated near candidates, and the loops
    // skip the others.
    std::vector<std::uint8_t> near(static_cast<std::size_t>(count), 0);
    for (const std::int32_t k : plan.near) near[static_cast<std::size_t>(k)] = 1;
    auto work = [&c, &near](std::int64_t k) -> std::int64_t {
      const auto s = static_cast<std::size_t>(k);
      return near[s] == 0 ? 0 : s < c.touching.size() && c.touching[s] != 0 ? 4 : 1;
    };
    // Each thread's share of the work: equal, or in proportion to the speed each thread showed in
    // its share since the last plan. A VM's cores can differ by a third in speed (and a laptop's
    // performance and efficiency cores by more): an equal split waits for the slowest.
    const std::vector<double> fraction =
        plan.share_done.size() == static_cast<std::size_t>(threads)
            ? speed_fractions(plan.share_done, plan.share_seconds)
            : std::vector<double>(static_cast<std::size_t>(threads), 1.0 / threads);
    if (c.kind == ContactKind::BallBall) thread_fractions_ = fraction;
    plan.shares = split_work(count, fraction, work);
    const std::vector<std::int64_t>& shares = plan.shares;
    plan.share_seconds.assign(static_cast<std::size_t>(threads), 0.0);
    plan.share_done.assign(static_cast<std::size_t>(threads), 0);
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
  contacts.for_each_pair_set([&](const PairContacts& c) {
    PairPlan& plan = pairs(c.kind);
    plan.unshared_run.assign(plan.shares.empty() ? 0 : plan.shares.size() - 1, {0, 0});
    for (std::size_t t = 0; t < plan.unshared_run.size(); ++t) {
      auto& longest = plan.unshared_run[t];
      std::int64_t run_begin = plan.shares[t];
      for (std::int64_t k = plan.shares[t]; k <= plan.shares[t + 1]; ++k) {
        const auto s = static_cast<std::size_t>(k);
        if (k < plan.shares[t + 1] && shared_[static_cast<std::size_t>(c.first[s])] == 0 &&
            shared_[static_cast<std::size_t>(c.second[s])] == 0)
          continue;
        if (k - run_begin > longest.second - longest.first) longest = {run_begin, k};
        run_begin = k + 1;
      }
    }
  });
  shares_stale_ = false;
  shares_planned_at_ = step;
}

}  // namespace dem
