// The thread team's choice of size, against a model machine whose step times per team size are
// known (no clock is read): it must settle on the fastest size, follow a change of load, and lose
// little time to its probes.
#include <catch2/catch.hpp>

#include <functional>

#include <dem/core/thread_team.hpp>

using dem::ThreadTeam;

namespace {

// Runs `steps` steps; `seconds(size, step)` is a step's time on `size` threads. Returns the time
// taken.
double run(ThreadTeam& team, std::int64_t steps, const std::function<double(int, std::int64_t)>& seconds,
           std::int64_t first_step = 0) {
  double total = 0.0;
  for (std::int64_t s = first_step; s < first_step + steps; ++s) {
    const double t = seconds(team.size(), s);
    total += t;
    team.step_took(t);
  }
  return total;
}

}  // namespace

TEST_CASE("thread team: on an idle machine it keeps the whole team and loses under 1 % to probes") {
  ThreadTeam team(2);
  // Alone, two threads run a step in 0.55 of one thread's time.
  const auto idle = [](int size, std::int64_t) { return size == 2 ? 0.55e-3 : 1.0e-3; };
  const std::int64_t steps = 100000;
  const double taken = run(team, steps, idle);
  CHECK(team.size() == 2);
  CHECK(taken < 1.01 * 0.55e-3 * steps);
  CHECK(team.steps_on(2) > 99 * team.steps_on(1));
}

TEST_CASE("thread team: on two busy cores it runs on one thread within 5 % of one thread's time") {
  ThreadTeam team(2);
  // Two busy processes beside it: two threads wait at every barrier, 38 times slower than one.
  const auto busy = [](int size, std::int64_t) { return size == 2 ? 38.0e-3 : 1.0e-3; };
  const std::int64_t steps = 100000;
  const double taken = run(team, steps, busy);
  CHECK(team.size() == 1);
  CHECK(taken < 1.05 * 1.0e-3 * steps);
}

TEST_CASE("thread team: it follows the load as it comes and goes") {
  ThreadTeam team(2);
  const auto idle = [](int size, std::int64_t) { return size == 2 ? 0.55e-3 : 1.0e-3; };
  const auto busy = [](int size, std::int64_t) { return size == 2 ? 38.0e-3 : 1.0e-3; };
  run(team, 20000, idle);
  REQUIRE(team.size() == 2);
  // The load comes: within a few windows the team is on one thread.
  run(team, 500, busy);
  CHECK(team.size() == 1);
  // It goes: the team probes two threads again before long (at most max_probe_every windows).
  const ThreadTeam::Tuning tuning;
  run(team, 2 * tuning.max_probe_every * tuning.window_steps, idle);
  CHECK(team.size() == 2);
}

TEST_CASE("thread team: a larger team walks down the halves to the size that is fastest") {
  ThreadTeam team(8);
  // Eight threads on a machine with three free cores: four threads is the fastest size.
  const auto times = [](int size, std::int64_t) {
    switch (size) {
      case 8: return 20.0e-3;
      case 4: return 0.3e-3;
      case 2: return 0.55e-3;
      default: return 1.0e-3;
    }
  };
  run(team, 50000, times);
  CHECK(team.size() == 4);
  CHECK(team.moves() >= 1);
}

TEST_CASE("thread team: pinned, or of one thread, it never changes size") {
  const auto busy = [](int size, std::int64_t) { return size == 2 ? 38.0e-3 : 1.0e-3; };
  ThreadTeam pinned(2, false);
  run(pinned, 5000, busy);
  CHECK(pinned.size() == 2);
  CHECK(pinned.steps_on(2) == 5000);
  ThreadTeam single(1);
  run(single, 5000, busy);
  CHECK(single.size() == 1);
  CHECK_THROWS_WITH(ThreadTeam(0), Catch::Matchers::Contains("threads"));
}

TEST_CASE("thread team: a probe that has lost is given up before its window ends") {
  // The 4D preset's steps measured beside two busy processes: 0.27 ms on one thread, 10.5 ms on two.
  const auto busy = [](int size, std::int64_t) { return size == 2 ? 10.5e-3 : 0.27e-3; };
  const std::int64_t steps = 100000;
  ThreadTeam team(2);
  const double taken = run(team, steps, busy);
  // Ten or so probes of two steps each, against five steps if every probe ran a whole window.
  CHECK(taken < 1.015 * 0.27e-3 * steps);
}

TEST_CASE("thread team: the scheduler's uneven slices on one thread do not start probes") {
  // Beside busy processes one thread's windows are uneven: one in ten waits several slices for its
  // core (twenty steps of 8 ms in every 640).
  const auto uneven = [](int size, std::int64_t step) {
    if (size == 2) return 38.0e-3;
    return step % 640 < 20 ? 8.0e-3 : 1.0e-3;
  };
  const std::int64_t steps = 100000;
  double one_thread = 0.0;
  for (std::int64_t s = 0; s < steps; ++s) one_thread += uneven(1, s);
  ThreadTeam team(2);
  CHECK(run(team, steps, uneven) < 1.02 * one_thread);
}

TEST_CASE("thread team: on an idle machine a short run loses under 2 % to its probes") {
  // The 14k benchmark alone: 0.85 ms a step on two threads, 1.6 ms on one; 2,000 steps (1.7 s),
  // in which the team probes one thread five times. Each probe runs until it is a few steps
  // behind: about 3 % of the run if every probe ran a whole 50 ms window at one thread's pace.
  const auto idle = [](int size, std::int64_t) { return size == 2 ? 0.85e-3 : 1.6e-3; };
  const std::int64_t steps = 2000;
  ThreadTeam team(2);
  const double taken = run(team, steps, idle);
  CHECK(team.size() == 2);
  CHECK(team.steps_on(1) > 0);  // it did probe
  CHECK(taken < 1.02 * 0.85e-3 * steps);
}
