// The task farm of one process (parallel/task_farm.hpp): every task runs once and its result reaches
// done(); a failing task stops none of the others, and the error rethrown is the lowest failed
// task's, whatever the number of workers. The MPI farm is checked by the mpi_task_farms test.
#include <catch2/catch.hpp>

#include <atomic>
#include <set>
#include <stdexcept>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/parallel/task_farm.hpp>

using namespace dem;

TEST_CASE("task farm: every task runs once and hands its result to done", "[parallel]") {
  for (int workers : {1, 3}) {
    parallel::LocalFarm farm;
    std::multiset<std::size_t> ran;
    std::set<std::string> results;
    std::atomic<int> calls{0};
    farm.run(
        7, workers,
        [&](std::size_t i) {
          ++calls;
          return "task " + std::to_string(i);
        },
        [&](std::size_t i, const std::string& r) {
          ran.insert(i);  // done() is called one at a time: no lock needed here
          results.insert(r);
          CHECK(r == "task " + std::to_string(i));
        });
    CHECK(calls == 7);
    CHECK(ran == std::multiset<std::size_t>{0, 1, 2, 3, 4, 5, 6});
    CHECK(results.size() == 7);
    CHECK(farm.on_leader([] { return std::string("leader"); }) == "leader");
    CHECK_FALSE(farm.failed_together());
  }
}

TEST_CASE("task farm: the lowest failed task's error, after every task has run", "[parallel]") {
  for (int workers : {1, 4}) {
    parallel::LocalFarm farm;
    std::atomic<int> ran{0};
    std::set<std::size_t> done;
    auto job = [&](std::size_t i) -> std::string {
      ++ran;
      if (i == 5) throw std::runtime_error("task 5 failed");
      if (i == 2) throw InputError("task 2: bad input");
      return {};
    };
    CHECK_THROWS_AS(farm.run(8, workers, job, [&](std::size_t i, const std::string&) { done.insert(i); }), InputError);
    CHECK(ran == 8);
    CHECK(done == std::set<std::size_t>{0, 1, 3, 4, 6, 7});
    CHECK(farm.failed_together());
  }
}
