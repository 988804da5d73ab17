// How the World shares out the contact loops of a step: the engine's plan, kept apart from what the
// contacts are (contact/contact_sets.hpp). For each pair set, the candidates the loops run over
// (near lists), which thread computes which contacts (shares), where the parts of the sums of
// particles that two shares touch wait for their turn (deferred), and how fast each thread went;
// for every loop, each thread's fraction of the work; and, in a World spread over processes, the
// particles this process owns.
//
// All of it is derived from the contact lists and remade as they change: the plan is never saved
// (a resumed run remakes it), and no result depends on it, only who computes what.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>
#include <dem/core/parallel.hpp>  // the plan's helpers: threads_for, speed_fractions, share_begin
#include <dem/core/world_state.hpp>

namespace dem {

/// One contact's part of a particle's force and torque sums, left by a thread for the engine to
/// add after the earlier threads' parts (the serial contact order): piece 1 gets -force, piece 2
/// +force.
struct DeferredSum {
  std::int32_t particle;
  bool first_piece;
  Lane3 force;   // N, on piece 2
  Lane3 torque;  // N m, on this particle about its centre
};

/// A ball-facet candidate's closest-point search on one triangle costs about this many pair
/// candidates: the wall loop weighs its triangle tests by it when choosing threads, and a spread
/// World when it balances its subdomains.
inline constexpr std::int64_t triangle_test_weight = 4;
/// An analytic-wall candidate (one closest-point formula, then the law) costs about this many pair
/// candidates: 25 against 17 ns a candidate on the 14k benchmark. Used as triangle_test_weight is.
inline constexpr std::int64_t analytic_wall_weight = 2;

/// The plan of one pair set (ball-ball or ball-pebble) for the steps until it is next remade.
struct PairPlan {
  /// The candidates that can touch before the World next refreshes this list, ascending: the
  /// others are more than a near skin apart (WorldSettings::near_skin), so the loops skip them.
  /// In a dense packing about a quarter of the candidates are that far apart. Made by the broad
  /// phase; in a World spread over processes, only the candidates this process computes.
  std::vector<std::int32_t> near;
  /// With several threads, thread t takes the contacts [shares[t], shares[t + 1]) (weighted by
  /// which contacts touch and by how fast each thread went, so that the threads finish together).
  /// A thread that finishes first takes chunks of steal_chunk near candidates from the end of
  /// another's share (pair_loops.hpp).
  std::vector<std::int64_t> shares;
  /// Per share, its longest run of contacts [begin, end) whose particles no other share touches:
  /// a later share adds their sums directly, without asking per particle whether to defer them
  /// (the answer is no for every one).
  std::vector<std::pair<std::int64_t, std::int64_t>> unshared_run;
  /// Per thread: the near candidates it computed since the plan, and the seconds it took (the
  /// next plan gives a thread on a faster core a larger share).
  std::vector<std::int64_t> share_done;
  std::vector<double> share_seconds;
  /// Scratch of a threaded step: share t's parts of the particles shared with earlier shares
  /// (StepPlan::shared), and every part of each chunk another thread took (one list per chunk, in
  /// contact order), added after the loop in contact order.
  std::vector<std::vector<DeferredSum>> deferred, taken;
};

/// The plan of a step: one PairPlan per pair set, and what every loop of the step shares.
class StepPlan {
 public:
  /// The plan of the pair set of `kind` (ball-ball or ball-pebble).
  PairPlan& pairs(ContactKind kind) { return pairs_[kind == ContactKind::BallPebble ? 1 : 0]; }
  const PairPlan& pairs(ContactKind kind) const { return pairs_[kind == ContactKind::BallPebble ? 1 : 0]; }

  /// Shares the pair sets of `contacts` out between `threads` threads, by the work of their near
  /// candidates and the speed each thread showed since the last plan: after forget_shares() (a
  /// rebuild or a load) and every few hundred steps (contacts that open or close move the work
  /// between shares); otherwise the plan stands. `step`: the World's step count.
  void plan_shares(const WorldContacts& contacts, std::size_t particles, int threads, std::int64_t step);
  /// The contact lists changed: plan the shares again before the next threaded loop.
  void forget_shares() { shares_stale_ = true; }
  /// Per particle, 1 where its pair contacts fall in more than one thread's share (the later
  /// shares defer their parts of its sums).
  const std::vector<std::uint8_t>& shared() const { return shared_; }
  /// Each thread's fraction of a loop's work, from the speeds its ball-ball share showed (thread t
  /// stays on one core when bound): the wall loop and the integration split by it too. Empty:
  /// equal.
  const std::vector<double>& thread_fractions() const { return thread_fractions_; }

  /// The particles this process computes the contacts of and integrates, storage indices
  /// [owned_begin, owned_end): all of them in one process; a subdomain in a spread World.
  void set_owned(std::pair<std::size_t, std::size_t> range) {
    owned_begin_ = static_cast<std::int64_t>(range.first);
    owned_end_ = static_cast<std::int64_t>(range.second);
  }
  std::int64_t owned_begin() const { return owned_begin_; }
  std::int64_t owned_end() const { return owned_end_; }

 private:
  std::array<PairPlan, 2> pairs_;  // ball-ball, ball-pebble
  std::vector<std::uint8_t> shared_;
  std::vector<double> thread_fractions_;
  bool shares_stale_ = true;
  std::int64_t shares_planned_at_ = 0;  // step of the plan
  std::int64_t owned_begin_ = 0;
  std::int64_t owned_end_ = std::numeric_limits<std::int64_t>::max();
};

}  // namespace dem
