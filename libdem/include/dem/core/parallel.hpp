// The thread plan's helpers: how the engine shares a loop between threads by the speed each showed
// (speed_fractions, share_begin, split_work) and how a thread that is done takes work from another
// (ChunkQueue). threads_for, which every floor may use, is on the ground floor (base/threads.hpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <dem/base/threads.hpp>

namespace dem {

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

/// Where thread t's share of `count` items begins, thread s taking the fraction (*fraction)[s] of
/// them: in proportion to the threads' speeds (speed_fractions), or equal shares when `fraction` is
/// null or not one per thread of the `team`. Thread t's share ends where t + 1's begins; t = team
/// gives `count`.
inline std::int64_t share_begin(std::int64_t count, const std::vector<double>* fraction, std::int64_t team,
                                std::int64_t t) {
  if (t >= team) return count;
  if (!fraction || static_cast<std::int64_t>(fraction->size()) != team) return count * t / team;
  double before = 0.0;
  for (std::int64_t s = 0; s < t; ++s) before += (*fraction)[static_cast<std::size_t>(s)];
  return std::min(count, static_cast<std::int64_t>(before * static_cast<double>(count)));
}

/// Borders of contiguous shares of the items [0, count), one share per entry of `fraction`: share t
/// is [border[t], border[t + 1]) and ends at the first item where the work so far reaches the
/// fractions' sum up to t of the whole (`work(k)`: item k's units). `share_work`, if given, gets
/// each share's units. A share may be empty; the last one ends at `count`.
template <class Work>
std::vector<std::int64_t> split_work(std::int64_t count, const std::vector<double>& fraction, const Work& work,
                                     std::vector<std::int64_t>* share_work = nullptr) {
  const auto shares = static_cast<std::int64_t>(fraction.size());
  std::int64_t total = 0;
  for (std::int64_t k = 0; k < count; ++k) total += work(k);
  std::vector<std::int64_t> border(1, 0), done_at(1, 0);  // done_at: work before each border
  std::int64_t done = 0;
  double goal = shares > 0 ? fraction[0] * static_cast<double>(total) : 0.0;
  for (std::int64_t k = 0; k < count && static_cast<std::int64_t>(border.size()) < shares; ++k) {
    done += work(k);
    if (static_cast<double>(done) >= goal) {
      border.push_back(k + 1);
      done_at.push_back(done);
      goal += fraction[border.size() - 1] * static_cast<double>(total);
    }
  }
  while (static_cast<std::int64_t>(border.size()) <= shares) {
    border.push_back(count);
    done_at.push_back(total);
  }
  if (share_work) {
    share_work->resize(static_cast<std::size_t>(shares));
    for (std::size_t t = 0; t < share_work->size(); ++t) (*share_work)[t] = done_at[t + 1] - done_at[t];
  }
  return border;
}

/// The chunks of one thread's share of a loop still to run, [front, back): its own thread takes
/// them from the front, and a thread that has run out of work takes them from the back, so that
/// threads finish together even when a core slows down mid-loop. Front and back share one word,
/// so a claim is one compare-and-swap and no chunk is taken twice. A claim hands over no data
/// (each chunk's memory belongs to whoever claims it), so it needs no ordering.
class alignas(64) ChunkQueue {
 public:
  /// Chunks [0, chunks) left; no more than 2^32 - 1.
  void reset(std::int64_t chunks) { bounds_.store(static_cast<std::uint64_t>(chunks), std::memory_order_relaxed); }
  /// The next chunk from the front, or -1 when none is left.
  std::int64_t take_front() { return take(true); }
  /// The last chunk left, or -1 when none is left.
  std::int64_t take_back() { return take(false); }
  /// How many chunks are left (a snapshot).
  std::int64_t left() const {
    const std::uint64_t b = bounds_.load(std::memory_order_relaxed);
    return static_cast<std::int64_t>(b & low) - static_cast<std::int64_t>(b >> 32);
  }

 private:
  static constexpr std::uint64_t low = 0xffffffffu;
  std::int64_t take(bool from_front) {
    std::uint64_t b = bounds_.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t front = b >> 32, back = b & low;
      if (front >= back) return -1;
      const std::uint64_t next = from_front ? ((front + 1) << 32) | back : (front << 32) | (back - 1);
      if (bounds_.compare_exchange_weak(b, next, std::memory_order_relaxed))
        return static_cast<std::int64_t>(from_front ? front : back - 1);
    }
  }
  std::atomic<std::uint64_t> bounds_{0};  // front in the high half, back in the low half
};

}  // namespace dem
