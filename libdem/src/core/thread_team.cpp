#include <dem/core/thread_team.hpp>

#include <algorithm>

#include <dem/base/errors.hpp>

namespace dem {

ThreadTeam::ThreadTeam(int most, bool adapt, Tuning tuning) : tuning_(tuning), adapt_(adapt) {
  require(most >= 1, "threads", most, ">= 1");
  require(tuning.window_steps >= 1 && tuning.probe_every >= 1 && tuning.max_probe_every >= tuning.probe_every,
          "thread team tuning", tuning.window_steps, "whole windows of at least one step");
  for (int n = most; n > 1; n = (n + 1) / 2) sizes_.push_back(n);
  sizes_.push_back(1);
  steps_on_.assign(sizes_.size(), 0);
  probe_every_ = tuning_.probe_every;
  windows_until_probe_ = 1;  // the first window may have been on a busy machine already
}

std::int64_t ThreadTeam::steps_on(int size) const {
  for (std::size_t k = 0; k < sizes_.size(); ++k)
    if (sizes_[k] == size) return steps_on_[k];
  return 0;
}

void ThreadTeam::step_took(double seconds) {
  ++steps_on_[probing_ ? probe_ : current_];
  if (!adapts()) return;
  window_seconds_ += seconds;
  ++window_count_;
  // A probe that has fallen a few steps behind the current size's pace, or has taken longer than a
  // whole window at the current size at a slower pace, has lost already. (A step of a faster size
  // that rebuilds the neighbour lists does not put it steps behind.)
  const double current_window =
      std::min(current_mean_ * static_cast<double>(tuning_.window_steps), tuning_.max_window_seconds);
  const double current_pace = current_mean_ * static_cast<double>(window_count_);
  const bool lost = probing_ && current_mean_ > 0.0 &&
                    (window_seconds_ > current_pace + tuning_.probe_budget_steps * current_mean_ ||
                     (window_seconds_ > current_window && window_seconds_ > current_pace));
  if (lost || window_count_ >= tuning_.window_steps || window_seconds_ >= tuning_.max_window_seconds) end_window(lost);
}

void ThreadTeam::end_window(bool probe_lost) {
  const double mean = window_seconds_ / static_cast<double>(window_count_);
  window_seconds_ = 0.0;
  window_count_ = 0;
  if (probing_) {
    probing_ = false;
    if (!probe_lost && mean < tuning_.switch_margin * current_mean_) {
      current_ = probe_;
      current_mean_ = mean;
      probe_every_ = tuning_.probe_every;
      ++moves_;
    } else {
      probe_every_ = std::min(2 * probe_every_, tuning_.max_probe_every);
    }
    windows_until_probe_ = probe_every_;
    return;
  }
  // Work started beside a team of several threads: try fewer at once. On the smallest size a
  // slower window is the scheduler's noise or load that more threads would not help.
  const bool slowed = current_mean_ > 0.0 && mean > tuning_.load_change * current_mean_ && current_ + 1 < sizes_.size();
  current_mean_ = mean;
  if (slowed || --windows_until_probe_ <= 0) start_probe(slowed);
}

void ThreadTeam::start_probe(bool smaller_only) {
  const bool has_smaller = current_ + 1 < sizes_.size(), has_larger = current_ > 0;
  const bool smaller = has_smaller && (smaller_only || probe_smaller_next_ || !has_larger);
  if (!smaller_only) probe_smaller_next_ = !smaller;
  probe_ = smaller ? current_ + 1 : current_ - 1;
  probing_ = true;
}

}  // namespace dem
