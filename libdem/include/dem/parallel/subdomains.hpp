// One World spread over processes (World::spread_over; docs/parallel.md): its subdomains, their
// ghosts, and the gathers that give every process the serial run's state. The World delegates to
// this part as it does to its BroadPhase; it moves bytes through a DomainComm (one process, or MPI
// ranks in libdem::mpi).
//
// Every process holds the whole state, and owns a contiguous run of the cell-sorted storage: its
// subdomain. In a step it computes the contacts that touch its particles (a contact between two
// subdomains is computed by both, as LAMMPS's `newton off`), sums its particles' forces in the
// serial contact order, and integrates them; the partners it needs from other subdomains (ghosts:
// the other pieces of its Verlet candidates, so within reach plus skin) arrive from their owners
// after every step. Pebbles and walls are stepped by every process from sums gathered in the
// serial order, so all of them move their clumps and servo walls identically. A particle's force
// is the serial one bit for bit, so the run is the serial run for any number of processes.
//
// Before a rebuild every process receives the whole state and rebuilds the same lists (the
// broad phase runs everywhere: a few per cent of a step); the subdomains are re-balanced by
// contact count then, and particles change owner with their contact history, which is keyed by
// the partners' stable ids as in one process.
//
// Every call that moves bytes is collective: every process makes it at the same point.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <dem/core/contact_model.hpp>
#include <dem/core/step_plan.hpp>
#include <dem/core/world_state.hpp>
#include <dem/parallel/domain_comm.hpp>

namespace dem::parallel {

class Subdomains {
 public:
  /// Over the processes of `comm`.
  explicit Subdomains(std::shared_ptr<DomainComm> comm);

  int ranks() const { return ranks_; }
  int rank() const { return rank_; }
  /// This process's particles (storage indices [first, second)) since the last plan; all
  /// `particles` of them before one.
  std::pair<std::size_t, std::size_t> owned_range(std::size_t particles) const;

  /// Subdomains, ghosts and slices from the lists of `state` now (after a rebuild or a load);
  /// nothing if they are planned already.
  void plan(const WorldState& state);
  /// The lists changed (a rebuild or a load): plan again before the next forces.
  void forget() { planned_ = false; }
  /// A step starts: other processes' particles and contacts held here go stale until a gather.
  void copies_go_stale() { whole_ = history_ = false; }
  /// std::logic_error naming World::`what` when the state is read between a step that ended with
  /// World::StepEnd::WallsAndClumps (or, during a step, from a controller) and the next gather.
  void require_whole(const char* what) const;

  /// Keeps in the near lists of `plan` only the contacts of `contacts` this process computes.
  void keep_local_near(const WorldContacts& contacts, StepPlan& plan) const;
  /// After the contact loops: the pebbles' sums and the wall contacts' records of every process,
  /// and the step's worst overlap ratio over them (worst_ratio()).
  void share_contact_results(WorldState& state, double local_worst_ratio);
  double worst_ratio() const { return worst_ratio_; }
  /// The set (in WorldContacts::for_each_set's order) and contact of the step's worst overlap over
  /// every process, given this process's own (`set` -1: none), with the whole state synchronised
  /// (it stops the run, whose message reads it).
  std::pair<int, std::int64_t> worst_contact(int set, const OverlapMonitor& local, WorldState& state);
  /// After integration: the ghosts' positions and velocities from their owners.
  void share_ghosts(ParticleStore& p);
  /// Every process gets every particle and contact record from their owners (not the history).
  void synchronise(WorldState& state);
  /// Every process gets every contact's history (before a rebuild, or for World::state()).
  void synchronise_history(WorldState& state);
  /// The largest of `values` over the processes (element by element, in place).
  void max(double* values, std::size_t count) { comm_->max(values, count); }

 private:
  std::shared_ptr<DomainComm> comm_;
  int ranks_ = 1, rank_ = 0;
  bool planned_ = false;
  bool whole_ = false;    // every process holds every particle and contact record (since the last step)
  bool history_ = false;  // ... and every contact's history
  double worst_ratio_ = 0.0;  // the step's worst overlap ratio over all processes
  std::vector<std::int64_t> begin_;  // ranks + 1: process r owns particles [begin[r], begin[r + 1])
  std::vector<std::int32_t> range_of_;  // per particle: the process whose subdomain holds it
  // Per pair set (ball-ball, ball-pebble), per candidate: 1 where this process computes it.
  std::array<std::vector<std::uint8_t>, 2> local_;
  // Slices (in contacts) that each process holds the current records of: pair candidates by the
  // owner of their lower storage index (the lists are in that order), wall candidates by the
  // owner of their ball.
  std::array<std::vector<std::size_t>, 2> pair_slices_, wall_slices_;
  // The pebbles in storage order, and the slice of them in each subdomain.
  std::vector<std::int32_t> pebbles_;
  std::vector<std::size_t> pebble_slices_;
  // Ghosts: send[r] are this process's balls that r computes contacts of; receive[r] are r's that
  // this process does (storage indices, ascending).
  std::vector<std::vector<std::int32_t>> send_, receive_;
  std::vector<std::vector<std::byte>> send_bytes_, receive_bytes_;
  std::vector<std::byte> buffer_;
};

}  // namespace dem::parallel
