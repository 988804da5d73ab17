// The task farm over MPI ranks (dem/parallel/task_farm.hpp): task i runs on rank i mod ranks, and
// its result is broadcast from there to every rank. Part of the target libdem::mpi, built when
// CMake finds MPI; this header does not need mpi.h.
//
// Run under a launcher (mpirun -n 4 dem-calibrate ...). Each rank runs its share of the tasks
// with the threads it is given, so ranks x threads may match the cores of the machines.
#pragma once

#include <dem/parallel/task_farm.hpp>

namespace dem::parallel {

class MpiFarm final : public TaskFarm {
 public:
  /// Initialises MPI (only the thread that made the farm calls MPI; the tasks' own threads do
  /// not). One per program; the destructor finalises MPI.
  MpiFarm(int& argc, char**& argv);
  ~MpiFarm() override;
  MpiFarm(const MpiFarm&) = delete;
  MpiFarm& operator=(const MpiFarm&) = delete;

  int processes() const override { return ranks_; }
  int process() const override { return rank_; }
  void run(std::size_t n, int workers, const TaskJob& job, const TaskDone& done) override;
  void barrier() override;
  /// Ends every rank with exit code `code` (MPI_Abort): for an error that only this rank has,
  /// where the others would wait for it for ever.
  [[noreturn]] void abort_all(int code);

 private:
  int ranks_ = 1, rank_ = 0;
};

}  // namespace dem::parallel
