#include <dem/parallel/task_farm.hpp>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace dem::parallel {

void run_on_threads(std::size_t n, int workers, const std::function<void(std::size_t)>& job) {
  if (workers <= 1 || n <= 1) {
    std::exception_ptr first;
    for (std::size_t i = 0; i < n; ++i) {
      try {
        job(i);
      } catch (...) {
        if (!first) first = std::current_exception();
      }
    }
    if (first) std::rethrow_exception(first);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(n);
  std::vector<std::thread> pool;
  for (std::size_t w = 0; w < std::min<std::size_t>(static_cast<std::size_t>(workers), n); ++w)
    pool.emplace_back([&] {
      for (std::size_t i = next++; i < n; i = next++) {
        try {
          job(i);
        } catch (...) {
          errors[i] = std::current_exception();
        }
      }
    });
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

int launched_ranks() {
  for (const char* size : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})  // OpenMPI; MPICH, Intel MPI, srun with PMI
    if (const char* value = std::getenv(size)) return std::max(1, std::atoi(value));
  for (const char* rank : {"PMIX_RANK", "PMI_RANK"})
    if (std::getenv(rank) != nullptr) return -1;
  // srun's tasks, when it sets no PMI variable (a batch script's own step counts one task).
  if (const char* tasks = std::getenv("SLURM_STEP_NUM_TASKS"); tasks != nullptr && std::atoi(tasks) > 1) return std::atoi(tasks);
  return 0;
}

std::string TaskFarm::on_leader(const std::function<std::string()>& job) {
  std::string result;
  run(1, 1, [&](std::size_t) { return job(); }, [&](std::size_t, const std::string& r) { result = r; });
  return result;
}

void TaskFarm::together(const std::function<void()>& step) {
  // One task per process: task i runs on process i.
  run(
      static_cast<std::size_t>(processes()), 1,
      [&](std::size_t) {
        step();
        return std::string();
      },
      [](std::size_t, const std::string&) {});
}

void LocalFarm::run(std::size_t n, int workers, const TaskJob& job, const TaskDone& done) {
  std::mutex handing_over;
  failed_together_ = false;
  try {
    run_on_threads(n, workers, [&](std::size_t i) {
      const std::string result = job(i);
      const std::lock_guard<std::mutex> lock(handing_over);
      done(i, result);
    });
  } catch (...) {
    failed_together_ = true;
    throw;
  }
}

}  // namespace dem::parallel
