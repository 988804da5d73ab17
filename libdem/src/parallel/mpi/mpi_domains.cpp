// Built into libdem::mpi only (libdem/CMakeLists.txt), beside the MPI task farm.
#include <dem/parallel/mpi_domains.hpp>

#include <mpi.h>

#include <climits>
#include <stdexcept>
#include <string>

namespace dem::parallel {

namespace {

void check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + call + " failed with code " + std::to_string(code));
}

int byte_count(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(INT_MAX))
    throw std::runtime_error("MPI: a message of " + std::to_string(bytes) + " bytes is above MPI's int count limit");
  return static_cast<int>(bytes);
}

constexpr int ghost_tag = 0x0de3;

}  // namespace

MpiDomains::MpiDomains(const MpiFarm& mpi) : ranks_(mpi.processes()), rank_(mpi.process()) {}

void MpiDomains::allgather(std::byte* data, const std::vector<std::size_t>& offsets) {
  std::vector<int> counts(static_cast<std::size_t>(ranks_)), displacements(static_cast<std::size_t>(ranks_));
  for (std::size_t r = 0; r < counts.size(); ++r) {
    counts[r] = byte_count(offsets[r + 1] - offsets[r]);
    displacements[r] = byte_count(offsets[r]);
  }
  bytes_sent_ += (offsets[static_cast<std::size_t>(rank_) + 1] - offsets[static_cast<std::size_t>(rank_)]) *
                 static_cast<std::size_t>(ranks_ - 1);
  check(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, data, counts.data(), displacements.data(), MPI_BYTE,
                       MPI_COMM_WORLD),
        "MPI_Allgatherv");
}

void MpiDomains::exchange(const std::vector<std::vector<std::byte>>& send, std::vector<std::vector<std::byte>>& receive) {
  std::vector<MPI_Request> requests;
  for (int r = 0; r < ranks_; ++r) {
    std::vector<std::byte>& in = receive[static_cast<std::size_t>(r)];
    if (r == rank_ || in.empty()) continue;
    requests.emplace_back();
    check(MPI_Irecv(in.data(), byte_count(in.size()), MPI_BYTE, r, ghost_tag, MPI_COMM_WORLD, &requests.back()), "MPI_Irecv");
  }
  for (int r = 0; r < ranks_; ++r) {
    const std::vector<std::byte>& out = send[static_cast<std::size_t>(r)];
    if (r == rank_ || out.empty()) continue;
    bytes_sent_ += out.size();
    requests.emplace_back();
    check(MPI_Isend(out.data(), byte_count(out.size()), MPI_BYTE, r, ghost_tag, MPI_COMM_WORLD, &requests.back()), "MPI_Isend");
  }
  check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
}

void MpiDomains::max(double* values, std::size_t count) {
  bytes_sent_ += count * sizeof(double) * static_cast<std::size_t>(ranks_ - 1);
  check(MPI_Allreduce(MPI_IN_PLACE, values, byte_count(count), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
}

}  // namespace dem::parallel
