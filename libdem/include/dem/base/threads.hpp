// How many threads a loop is worth: the one thread helper every floor may use (the ground floor
// of the house: no engine types). The engine's thread plan is in core/parallel.hpp.
#pragma once

#include <atomic>
#include <cstdint>

namespace dem {

/// Threads worth using for a loop of `count` items: small loops run serially, since starting a
/// parallel region costs more than it saves (and oversubscribed cores make it far worse). From a
/// thousand items on, a loop is split even where one core could do it alone: on one thread of a
/// team it would also read every line the other threads wrote in the loop before (the 1,750-ball
/// benchmark's leapfrog: 10 us a step on one thread alone, 20 us on one thread of two, 9 us split).
inline constexpr std::int64_t min_parallel_items = 1024;
inline int threads_for(std::int64_t count, int threads) { return count >= min_parallel_items ? threads : 1; }

/// Parallel regions opened with more than one thread in this process so far. Each is a meeting
/// point: its threads wait for the slowest at its end, which on a busy machine waits for the
/// scheduler (core/thread_team.hpp); dem-bench prints the count per step.
inline std::atomic<std::int64_t>& parallel_regions() {
  static std::atomic<std::int64_t> count{0};
  return count;
}
/// `threads`, counted in parallel_regions() when more than one: every engine region opens with
/// num_threads(open_team(n)).
inline int open_team(int threads) {
  if (threads > 1) parallel_regions().fetch_add(1, std::memory_order_relaxed);
  return threads;
}

}  // namespace dem
