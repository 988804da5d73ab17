// Processes simulated by threads of one test program: `ThreadDomains hub(n)` gives n DomainComm
// endpoints (dem/parallel/domain_comm.hpp) that n threads use as MPI ranks would, so that a World
// spread over "processes" is tested in every build, with or without MPI.
#pragma once

#include <algorithm>
#include <barrier>
#include <cstring>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include <dem/parallel/domain_comm.hpp>

namespace dem::testing {

class ThreadDomains {
 public:
  explicit ThreadDomains(int ranks) : ranks_(ranks), sync_(ranks), slots_(static_cast<std::size_t>(ranks)) {}

  /// Runs body(comm) on `ranks` threads, each with its endpoint; returns when all have.
  void run(const std::function<void(const std::shared_ptr<parallel::DomainComm>&)>& body) {
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks_; ++r) threads.emplace_back([this, r, &body] { body(std::make_shared<Endpoint>(*this, r)); });
    for (auto& t : threads) t.join();
  }

 private:
  struct Slot {
    std::byte* data = nullptr;
    const std::vector<std::vector<std::byte>>* send = nullptr;
    double* values = nullptr;
  };

  class Endpoint final : public parallel::DomainComm {
   public:
    Endpoint(ThreadDomains& hub, int rank) : hub_(hub), rank_(rank) {}
    int ranks() const override { return hub_.ranks_; }
    int rank() const override { return rank_; }
    void allgather(std::byte* data, const std::vector<std::size_t>& offsets) override {
      hub_.slots_[static_cast<std::size_t>(rank_)].data = data;
      hub_.sync_.arrive_and_wait();
      for (int r = 0; r < hub_.ranks_; ++r)
        if (r != rank_) {
          const std::size_t begin = offsets[static_cast<std::size_t>(r)], end = offsets[static_cast<std::size_t>(r) + 1];
          if (end > begin) std::memcpy(data + begin, hub_.slots_[static_cast<std::size_t>(r)].data + begin, end - begin);
        }
      hub_.sync_.arrive_and_wait();
    }
    void exchange(const std::vector<std::vector<std::byte>>& send, std::vector<std::vector<std::byte>>& receive) override {
      hub_.slots_[static_cast<std::size_t>(rank_)].send = &send;
      hub_.sync_.arrive_and_wait();
      for (int r = 0; r < hub_.ranks_; ++r) {
        if (r == rank_) continue;
        const std::vector<std::byte>& from = (*hub_.slots_[static_cast<std::size_t>(r)].send)[static_cast<std::size_t>(rank_)];
        std::vector<std::byte>& into = receive[static_cast<std::size_t>(r)];
        if (from.size() != into.size()) throw std::logic_error("ThreadDomains: sender and receiver disagree on a ghost list");
        std::copy(from.begin(), from.end(), into.begin());
      }
      hub_.sync_.arrive_and_wait();
    }
    void max(double* values, std::size_t count) override {
      hub_.slots_[static_cast<std::size_t>(rank_)].values = values;
      hub_.sync_.arrive_and_wait();
      std::vector<double> out(values, values + count);
      for (int r = 0; r < hub_.ranks_; ++r)
        for (std::size_t k = 0; k < count; ++k) out[k] = std::max(out[k], hub_.slots_[static_cast<std::size_t>(r)].values[k]);
      hub_.sync_.arrive_and_wait();
      std::copy(out.begin(), out.end(), values);
    }

   private:
    ThreadDomains& hub_;
    int rank_;
  };

  int ranks_;
  std::barrier<> sync_;
  std::vector<Slot> slots_;
};

}  // namespace dem::testing
