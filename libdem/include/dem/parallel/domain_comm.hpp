// The processes one World is spread over (domain decomposition, World::spread_over) and the few
// collective operations its step needs. A World stays the same API on every process; the
// communicator only moves bytes. dem/parallel/mpi_domains.hpp (target libdem::mpi) implements it
// over MPI ranks; libdem::dem itself never needs MPI.
//
// Every process calls every operation in the same order with the same arguments apart from its
// own data (they are collective).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem::parallel {

class DomainComm {
 public:
  virtual ~DomainComm() = default;

  /// Processes the World is spread over, and this one's number in 0 .. ranks() - 1.
  virtual int ranks() const = 0;
  virtual int rank() const = 0;

  /// In place: process r holds the valid bytes [offsets[r], offsets[r + 1]) of `data` (offsets
  /// has ranks() + 1 entries, ascending); afterwards every process holds all of them.
  virtual void allgather(std::byte* data, const std::vector<std::size_t>& offsets) = 0;

  /// Point to point: sends `send[r]` to process r and receives `receive[r]` from it, whose sizes
  /// the caller has set to what r sends (both sides know the lists). Empty buffers are skipped.
  virtual void exchange(const std::vector<std::vector<std::byte>>& send, std::vector<std::vector<std::byte>>& receive) = 0;

  /// In place, element by element: the largest of `values` over all processes (exact, so the same
  /// on every process whatever their number).
  virtual void max(double* values, std::size_t count) = 0;

  /// Bytes this process has sent to the others so far (its slices to each, its ghosts, its
  /// maxima): the communication volume, for benchmarks.
  std::uint64_t bytes_sent() const { return bytes_sent_; }

 protected:
  std::uint64_t bytes_sent_ = 0;
};

}  // namespace dem::parallel
