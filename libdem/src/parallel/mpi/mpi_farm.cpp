// Built into libdem::mpi only (libdem/CMakeLists.txt): the one source of the library that needs MPI.
#include <dem/parallel/mpi_farm.hpp>

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <dem/core/errors.hpp>

namespace dem::parallel {

namespace {

enum Outcome : std::uint64_t { Succeeded = 0, InputFailure = 1, OtherFailure = 2 };

void check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + call + " failed with code " + std::to_string(code));
}

}  // namespace

MpiFarm::MpiFarm(int& argc, char**& argv) {
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  check(MPI_Comm_size(MPI_COMM_WORLD, &ranks_), "MPI_Comm_size");
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
}

MpiFarm::~MpiFarm() { MPI_Finalize(); }

void MpiFarm::run(std::size_t n, int workers, const TaskJob& job, const TaskDone& done) {
  failed_together_ = false;
  std::vector<std::size_t> mine;
  for (std::size_t i = static_cast<std::size_t>(rank_); i < n; i += static_cast<std::size_t>(ranks_)) mine.push_back(i);
  std::vector<std::string> results(n);
  std::vector<std::uint64_t> outcome(n, Succeeded);
  // Each task catches its own error: every rank must reach the exchange below.
  run_on_threads(mine.size(), workers, [&](std::size_t k) {
    const std::size_t i = mine[k];
    try {
      results[i] = job(i);
    } catch (const InputError& e) {
      outcome[i] = InputFailure, results[i] = e.what();
    } catch (const std::exception& e) {
      outcome[i] = OtherFailure, results[i] = e.what();
    } catch (...) {
      outcome[i] = OtherFailure, results[i] = "unknown error";
    }
  });
  // In task order, from the rank that ran it: every rank receives the same bytes in the same order.
  for (std::size_t i = 0; i < n; ++i) {
    const int owner = static_cast<int>(i % static_cast<std::size_t>(ranks_));
    std::uint64_t header[2] = {outcome[i], results[i].size()};
    check(MPI_Bcast(header, 2, MPI_UINT64_T, owner, MPI_COMM_WORLD), "MPI_Bcast");
    outcome[i] = header[0];
    results[i].resize(header[1]);
    for (std::uint64_t sent = 0; sent < header[1];) {
      const int count = static_cast<int>(std::min<std::uint64_t>(header[1] - sent, INT_MAX));
      check(MPI_Bcast(results[i].data() + sent, count, MPI_CHAR, owner, MPI_COMM_WORLD), "MPI_Bcast");
      sent += static_cast<std::uint64_t>(count);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (outcome[i] == Succeeded) done(i, results[i]);
  for (std::size_t i = 0; i < n; ++i) {
    if (outcome[i] == Succeeded) continue;
    failed_together_ = true;
    if (outcome[i] == InputFailure) throw InputError(results[i]);
    throw std::runtime_error(results[i]);
  }
}

void MpiFarm::barrier() { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

void MpiFarm::abort_all(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return; this keeps [[noreturn]] honest if it did
}

}  // namespace dem::parallel
