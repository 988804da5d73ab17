// One World spread over processes (World::spread_over; docs/parallel.md): the World delegates the
// subdomains, their ghosts and gathers to parallel::Subdomains, as it does its lists to BroadPhase.
// Each method here does nothing in one process.
#include <memory>
#include <type_traits>
#include <utility>
#include <variant>

#include <dem/base/errors.hpp>
#include <dem/core/world.hpp>
#include <dem/parallel/subdomains.hpp>

namespace dem {

void World::spread_over(std::shared_ptr<parallel::DomainComm> comm) {
  require(comm != nullptr, "spread_over communicator", "null", "a communicator");
  if (comm->ranks() <= 1) {
    domains_.reset();
    return;
  }
  require(state_.bonds.empty(), "a World with bonds spread over processes", std::to_string(comm->ranks()) + " processes",
          "one process: bonds do not cross subdomains yet");
  require(!state_.cell, "a World with a periodic cell spread over processes", std::to_string(comm->ranks()) + " processes",
          "one process: the subdomains do not wrap across the cell's faces yet");
  domains_ = std::make_shared<parallel::Subdomains>(std::move(comm));
}

int World::ranks() const { return domains_ ? domains_->ranks() : 1; }
int World::rank() const { return domains_ ? domains_->rank() : 0; }

std::pair<std::size_t, std::size_t> World::owned_range() const {
  if (!domains_) return {0, state_.particles.size()};
  return domains_->owned_range(state_.particles.size());
}

void World::plan_domains() {
  if (domains_) domains_->plan(state_);
}

void World::require_whole(const char* what) const {
  if (domains_) domains_->require_whole(what);
}

void World::forget_domains() {
  if (domains_) domains_->forget();
}

void World::copies_go_stale() {
  if (domains_) domains_->copies_go_stale();
}

void World::keep_local_near() {
  if (domains_) domains_->keep_local_near(state_.contacts, plan_);
}

void World::share_contact_results(double local_worst_ratio) {
  if (domains_) domains_->share_contact_results(state_, local_worst_ratio);
}

void World::share_ghosts() {
  if (domains_) domains_->share_ghosts(state_.particles);
}

void World::synchronise() {
  if (domains_) domains_->synchronise(state_);
}

void World::synchronise_history() {
  if (domains_) domains_->synchronise_history(state_);
}

const WorldState& World::state() const {
  require_whole("state()");
  require_pair_records("state()");  // a restart file's touching contacts are those with records
  // The history is a restart file's alone (and a rebuild's): gathered when asked for.
  const_cast<World*>(this)->synchronise_history();
  return state_;
}

void World::global_max(double* values, std::size_t count) {
  if (domains_) domains_->max(values, count);
}

World::WorstOverlap World::global_worst(const WorstOverlap& local) {
  if (!domains_) return local;
  const double ratio = domains_->worst_ratio();
  if (ratio <= state_.settings.max_overlap_ratio) return local;
  // This process's worst, as a set number in force order, and then the one of all processes.
  int set = 0, found = -1;
  state_.contacts.for_each_set([&](const auto& c) {
    if (const auto* const* mine = std::get_if<std::remove_cvref_t<decltype(&c)>>(&local.set); mine && *mine == &c) found = set;
    ++set;
  });
  const std::pair<int, std::int64_t> first_worst = domains_->worst_contact(found, local.monitor, state_);
  const int winner = first_worst.first;
  WorstOverlap worst;
  worst.monitor = OverlapMonitor{ratio, first_worst.second};
  set = 0;
  state_.contacts.for_each_set([&](const auto& c) {
    if (set++ == winner) worst.set = &c;
  });
  return worst;
}

}  // namespace dem
