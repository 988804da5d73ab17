// One World spread over MPI ranks (World::spread_over, dem/parallel/domain_comm.hpp). Part of the
// target libdem::mpi, built when CMake finds MPI; this header does not need mpi.h.
//
//   dem::parallel::MpiFarm mpi(argc, argv);   // initialises MPI
//   dem::World world{settings};
//   ... the same balls, walls, clumps and models on every rank ...
//   world.spread_over(std::make_shared<dem::parallel::MpiDomains>(mpi));
//   world.step(100000);                        // the serial run's results, bit for bit
#pragma once

#include <dem/parallel/domain_comm.hpp>
#include <dem/parallel/mpi_farm.hpp>

namespace dem::parallel {

class MpiDomains final : public DomainComm {
 public:
  /// Over every rank of the run (MPI_COMM_WORLD), which `mpi` has initialised.
  explicit MpiDomains(const MpiFarm& mpi);

  int ranks() const override { return ranks_; }
  int rank() const override { return rank_; }
  void allgather(std::byte* data, const std::vector<std::size_t>& offsets) override;
  void exchange(const std::vector<std::vector<std::byte>>& send, std::vector<std::vector<std::byte>>& receive) override;
  void max(double* values, std::size_t count) override;

 private:
  int ranks_ = 1, rank_ = 0;
};

}  // namespace dem::parallel
