// Small parallel helpers every floor may use (the ground floor of the house: no engine types).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem {

/// Threads worth using for a loop of `count` items: small loops run serially, since starting a
/// parallel region costs more than it saves (and oversubscribed cores make it far worse).
inline constexpr std::int64_t min_parallel_items = 4096;
inline int threads_for(std::int64_t count, int threads) { return count >= min_parallel_items ? threads : 1; }

/// The fraction of a loop's work to give each of `work.size()` threads, from what each did last
/// time: `work[t]` units in `seconds[t]` s. In proportion to the speeds, so that threads on cores
/// of different speed (a VM's busy neighbour, a laptop's efficiency cores) finish together; equal
/// when a measurement is missing. No thread gets less than half an equal fraction, so that one
/// bad measurement cannot starve a thread. The fractions sum to 1.
inline std::vector<double> speed_fractions(const std::vector<std::int64_t>& work, const std::vector<double>& seconds) {
  const std::size_t n = work.size();
  std::vector<double> fraction(n, n > 0 ? 1.0 / static_cast<double>(n) : 0.0);
  if (n < 2 || seconds.size() != n) return fraction;
  std::vector<double> speed(n);
  for (std::size_t t = 0; t < n; ++t) {
    if (work[t] <= 0 || !(seconds[t] > 0.0)) return fraction;
    speed[t] = static_cast<double>(work[t]) / seconds[t];
  }
  // Threads held at the floor take exactly it; the others share the rest by speed. Each pass
  // can only add threads to the floor, so n passes settle it.
  const double floor = 0.5 / static_cast<double>(n);
  std::vector<bool> at_floor(n, false);
  for (std::size_t pass = 0; pass < n; ++pass) {
    double free_speed = 0.0, floor_share = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
      if (at_floor[t]) floor_share += floor;
      else free_speed += speed[t];
    }
    bool changed = false;
    for (std::size_t t = 0; t < n; ++t) {
      if (at_floor[t]) continue;
      fraction[t] = (1.0 - floor_share) * speed[t] / free_speed;
      if (fraction[t] < floor) at_floor[t] = changed = true;
    }
    for (std::size_t t = 0; t < n; ++t)
      if (at_floor[t]) fraction[t] = floor;
    if (!changed) break;
  }
  return fraction;
}

}  // namespace dem
