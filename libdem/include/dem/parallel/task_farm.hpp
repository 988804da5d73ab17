// Independent tasks spread over the processes of a run, every result handed to every process: the
// task farm of a calibration (its trials) or of a seed ensemble (its specimens). A LocalFarm is
// this process alone, running its tasks on threads; an MpiFarm (dem/parallel/mpi_farm.hpp, target
// libdem::mpi) spreads them over MPI ranks. A task's result depends on its inputs only, never on
// the process or thread that ran it, so a farm gives the same results on any number of each.
//
// Every process runs the same program and calls run() with the same tasks in the same order; the
// files all of them read (restart files, trial folders) are on a file system they all see, and
// the files of the whole run (tables, summaries) are written by the leading process alone.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace dem::parallel {

/// A task: does task number `task` and returns its result as bytes (the farm carries them between
/// processes; an empty string is a result too).
using TaskJob = std::function<std::string(std::size_t task)>;
/// Receives the result of task number `task`, on every process.
using TaskDone = std::function<void(std::size_t task, const std::string& result)>;

class TaskFarm {
 public:
  virtual ~TaskFarm() = default;

  /// Processes that share the tasks, and this one's number in 0 .. processes() - 1.
  virtual int processes() const = 0;
  virtual int process() const = 0;
  /// The process that writes the run's shared files (number 0).
  bool leads() const { return process() == 0; }

  /// Runs job(0) .. job(n - 1), each once on one process (task i on process i mod processes()),
  /// `workers` at a time on that process's threads, and calls done(i, result) on every process
  /// for every task, one call at a time: with one process as each task finishes, with several in
  /// task order once all have finished. A task that throws does not stop the others; once all
  /// have run, every process throws the error of the lowest failed task, after the done calls of
  /// those that succeeded (with one process the task's own exception; across processes an
  /// InputError stays one and any other error becomes a std::runtime_error with its message). An
  /// error thrown by done() itself ends run() on the process that threw it. Returns when every
  /// task has finished, on every process.
  virtual void run(std::size_t n, int workers, const TaskJob& job, const TaskDone& done) = 0;
  /// Runs job on the leading process only and hands its result to every process.
  std::string on_leader(const std::function<std::string()>& job);
  /// Runs `step` on every process (e.g. checks of the input, which all of them read); if it throws
  /// on any, every process throws the error of the lowest such process, as run() does.
  void together(const std::function<void()>& step);
  /// Waits until every process has got here.
  virtual void barrier() = 0;
  /// True when the last run() threw a task's error: every process holds the same error, so the
  /// program can end on each without one of them telling the others.
  bool failed_together() const { return failed_together_; }

 protected:
  bool failed_together_ = false;
};

/// This process alone: tasks on threads, results handed over as they finish.
class LocalFarm final : public TaskFarm {
 public:
  int processes() const override { return 1; }
  int process() const override { return 0; }
  void run(std::size_t n, int workers, const TaskJob& job, const TaskDone& done) override;
  void barrier() override {}
};

/// The ranks an MPI launcher (mpirun, mpiexec, srun) started with this process, read from the
/// environment without initialising MPI: 0 when none started it, -1 when one did but does not
/// say how many. A program that runs as one process must not run on several ranks, since every
/// rank would do the whole run.
int launched_ranks();

/// Runs job(0) .. job(n - 1), `workers` at a time on std::threads (inline for one worker). Every
/// job runs even if another fails; then the exception of the lowest failed index is rethrown, so
/// which error is reported does not depend on timing.
void run_on_threads(std::size_t n, int workers, const std::function<void(std::size_t)>& job);

}  // namespace dem::parallel
