// How many threads a step runs on: the configured team, or fewer while the machine is busy.
//
// The engine's results do not depend on the number of threads (contact sums are added in contact
// order, whoever computes them), so the team may change size between any two steps. Every parallel
// region of a step ends in a barrier that waits for its slowest thread; when another process holds
// one of the cores, that thread waits for the scheduler's next slice at every barrier, and two
// threads on two busy cores run a step tens of times slower than one thread. The team therefore
// times its steps and runs on fewer threads when that is faster:
//
// - The sizes it may take are the configured count, its half, its quarter, ..., 1.
// - It times windows of `window_steps` steps, or of `max_window_seconds` if that comes first (wall
//   clock, the engine's part of each step), and keeps the mean step time of the last window.
// - After its first window, and then every `probe_every` windows, it tries a neighbouring size (one
//   smaller, then one larger, in turn) for one window. A probe that falls behind the current size's
//   pace by `probe_budget_steps` of its steps, or has taken longer than a whole window at the
//   current size, is given up at once, so trying a slow size costs a few steps. If the probe's mean
//   step is at least `switch_margin` faster, the team moves to that size; otherwise it stays and
//   waits twice as long before the next probe (up to `max_probe_every` windows), so a steady
//   machine is probed rarely.
// - On more than one thread, a window more than `load_change` times slower than the one before
//   (another process started) starts a probe of the next smaller size at once. On one thread a
//   slow window is not acted on: the scheduler's slices make windows uneven on a busy machine, and
//   more threads would not help.
//
// With one configured thread, or `adapt` off, the team never changes size.
#pragma once

#include <cstdint>
#include <vector>

namespace dem {

class ThreadTeam {
 public:
  struct Tuning {
    std::int64_t window_steps = 64;
    double max_window_seconds = 0.05;    // s
    std::int64_t probe_every = 2;        // windows between probes, after every move
    std::int64_t max_probe_every = 512;  // windows
    double switch_margin = 0.95;         // a probe wins when its mean step is below this fraction
    double load_change = 2.0;
    double probe_budget_steps = 4.0;     // steps at the current pace a probe may fall behind by
  };

  /// A team of up to `most` threads (>= 1); `adapt` false keeps it at `most`.
  explicit ThreadTeam(int most = 1, bool adapt = true) : ThreadTeam(most, adapt, Tuning{}) {}
  ThreadTeam(int most, bool adapt, Tuning tuning);

  /// Threads for the next step.
  int size() const { return probing_ ? sizes_[probe_] : sizes_[current_]; }
  /// The configured team.
  int most() const { return sizes_.front(); }
  bool adapts() const { return adapt_ && sizes_.size() > 1; }
  /// Records that the last step, on size() threads, took `seconds` (s); may change size().
  void step_took(double seconds);
  /// Steps run on each size so far, by size (for a run's report).
  std::int64_t steps_on(int size) const;
  /// Times the team changed size.
  std::int64_t moves() const { return moves_; }

 private:
  void end_window(bool probe_lost);
  void start_probe(bool smaller_only);

  Tuning tuning_;
  bool adapt_ = true;
  std::vector<int> sizes_;                  // most, most/2, ..., 1
  std::vector<std::int64_t> steps_on_;      // per entry of sizes_
  std::size_t current_ = 0, probe_ = 0;
  bool probing_ = false;
  bool probe_smaller_next_ = true;
  std::int64_t window_count_ = 0;           // steps in the window so far
  double window_seconds_ = 0.0;
  double current_mean_ = 0.0;               // s per step of the last whole window at current_, 0: none yet
  std::int64_t windows_until_probe_ = 0;
  std::int64_t probe_every_ = 0;
  std::int64_t moves_ = 0;
};

}  // namespace dem
