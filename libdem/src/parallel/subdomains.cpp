// One World spread over processes (subdomains.hpp; docs/parallel.md): the plan of the subdomains,
// the ghosts, and the gathers of records, sums and history in the serial order.
#include <dem/parallel/subdomains.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <dem/base/errors.hpp>

namespace dem::parallel {

namespace {

/// An array of elements of `size` bytes.
struct Field {
  std::byte* data;
  std::size_t size;
};

template <class T>
Field field(std::vector<T>& v, std::size_t count) {
  v.resize(count);  // a record not written yet: zero, the same on every process
  return {reinterpret_cast<std::byte*>(v.data()), sizeof(T)};
}

Field field(StateBuffer& s) { return {s.bytes.data(), s.stride}; }

/// True when every component is +0.0 (bits, so a -0.0 is sent as it is).
bool zero_bits(const Vec3& v) {
  static const Vec3 zero = Vec3::Zero();
  return std::memcmp(v.data(), zero.data(), sizeof(Vec3)) == 0;
}

/// Every process gets every process's slice [offsets[r], offsets[r + 1]) (in elements) of each
/// field, through one collective call.
void gather_slices(parallel::DomainComm& comm, const std::vector<std::size_t>& offsets,
                   std::initializer_list<Field> fields, std::vector<std::byte>& buffer) {
  std::size_t per = 0;
  for (const Field& f : fields) per += f.size;
  const int ranks = comm.ranks(), me = comm.rank();
  std::vector<std::size_t> bytes(offsets.size());
  for (std::size_t r = 0; r < offsets.size(); ++r) bytes[r] = offsets[r] * per;
  buffer.resize(bytes.back());
  const auto pack = [&](int r, bool out) {
    std::byte* at = buffer.data() + bytes[static_cast<std::size_t>(r)];
    const std::size_t first = offsets[static_cast<std::size_t>(r)], count = offsets[static_cast<std::size_t>(r) + 1] - first;
    for (const Field& f : fields) {
      if (count * f.size == 0) continue;
      if (out) std::memcpy(at, f.data + first * f.size, count * f.size);
      else std::memcpy(f.data + first * f.size, at, count * f.size);
      at += count * f.size;
    }
  };
  pack(me, true);
  comm.allgather(buffer.data(), bytes);
  for (int r = 0; r < ranks; ++r)
    if (r != me) pack(r, false);
}

/// Offsets (ranks + 1) splitting a list whose `key(k)` ascends into the subdomains' runs.
template <class Key>
std::vector<std::size_t> slices_by(std::size_t count, const std::vector<std::int64_t>& begin, const Key& key,
                                   const char* what) {
  std::vector<std::size_t> offsets(begin.size(), count);
  offsets.front() = 0;
  std::size_t r = 1;
  for (std::size_t k = 0; k < count; ++k) {
    if (k > 0 && key(k) < key(k - 1))
      throw std::logic_error(std::string("spread World: the ") + what + " list is not in storage order");
    while (r + 1 < begin.size() && key(k) >= begin[r]) offsets[r++] = k;
  }
  return offsets;
}

}  // namespace


Subdomains::Subdomains(std::shared_ptr<DomainComm> comm) : comm_(std::move(comm)) {
  require(comm_ != nullptr, "spread_over communicator", "null", "a communicator");
  ranks_ = comm_->ranks();
  rank_ = comm_->rank();
}

std::pair<std::size_t, std::size_t> Subdomains::owned_range(std::size_t particles) const {
  if (!planned_) return {0, particles};
  const auto me = static_cast<std::size_t>(rank_);
  return {static_cast<std::size_t>(begin_[me]), static_cast<std::size_t>(begin_[me + 1])};
}

void Subdomains::plan(const WorldState& state) {
  if (planned_) return;
  const ParticleStore& p = state.particles;
  const std::size_t n = p.size();
  const int me = rank_;
  const WorldContacts& contacts = state.contacts;

  // Equal work per subdomain, in separated candidates' checks: a touching contact costs about
  // four (as the thread plan weighs them), a particle's integration two, a wall candidate one per
  // closest-point search. A contact between subdomains is computed on both sides.
  std::vector<std::int64_t> work(n, 2);
  contacts.for_each_pair_set([&](const PairContacts& c) {
    for (std::size_t k = 0; k < c.size(); ++k) {
      const std::int64_t cost = k < c.touching.size() && c.touching[k] != 0 ? 4 : 1;
      work[static_cast<std::size_t>(c.first[k])] += cost;
      work[static_cast<std::size_t>(c.second[k])] += cost;
    }
  });
  contacts.for_each_wall_set([&](const WallContacts& c) {
    for (std::size_t k = 0; k < c.size(); ++k)
      work[static_cast<std::size_t>(c.ball[k])] += c.surfaces ? analytic_wall_weight : triangle_test_weight * (c.triangle_end[k] - c.triangle_begin[k]);
  });
  std::int64_t total = 0;
  for (const std::int64_t w : work) total += w;
  begin_.assign(1, 0);
  std::int64_t done = 0;
  for (std::size_t i = 0; i < n && static_cast<int>(begin_.size()) < ranks_; ++i) {
    done += work[i];
    while (static_cast<int>(begin_.size()) < ranks_ && done * ranks_ >= total * static_cast<std::int64_t>(begin_.size()))
      begin_.push_back(static_cast<std::int64_t>(i) + 1);
  }
  while (static_cast<int>(begin_.size()) <= ranks_) begin_.push_back(static_cast<std::int64_t>(n));
  begin_.back() = static_cast<std::int64_t>(n);
  range_of_.assign(n, 0);
  for (int r = 0; r < ranks_; ++r)
    for (std::int64_t i = begin_[static_cast<std::size_t>(r)]; i < begin_[static_cast<std::size_t>(r) + 1]; ++i)
      range_of_[static_cast<std::size_t>(i)] = r;

  send_.assign(static_cast<std::size_t>(ranks_), {});
  receive_.assign(static_cast<std::size_t>(ranks_), {});
  int set = 0;
  contacts.for_each_pair_set([&](const PairContacts& c) {
    std::vector<std::uint8_t>& local = local_[static_cast<std::size_t>(set)];
    local.assign(c.size(), 0);
    for (std::size_t k = 0; k < c.size(); ++k) {
      const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
      const int ri = range_of_[i], rj = range_of_[j];
      local[k] = ri == me || rj == me;
      if (ri == rj) continue;
      // Pebbles are stepped by every process: only balls travel as ghosts.
      if (ri == me && !p.is_pebble(i)) send_[static_cast<std::size_t>(rj)].push_back(static_cast<std::int32_t>(i));
      if (rj == me && !p.is_pebble(j)) send_[static_cast<std::size_t>(ri)].push_back(static_cast<std::int32_t>(j));
      if (rj == me && !p.is_pebble(i)) receive_[static_cast<std::size_t>(ri)].push_back(static_cast<std::int32_t>(i));
      if (ri == me && !p.is_pebble(j)) receive_[static_cast<std::size_t>(rj)].push_back(static_cast<std::int32_t>(j));
    }
    pair_slices_[static_cast<std::size_t>(set)] = slices_by(
        c.size(), begin_, [&c](std::size_t k) { return static_cast<std::int64_t>(std::min(c.first[k], c.second[k])); }, "pair");
    ++set;
  });
  for (auto* lists : {&send_, &receive_})
    for (auto& list : *lists) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  constexpr std::size_t ghost_bytes = 3 * sizeof(Vec3);  // x, v, w
  send_bytes_.resize(static_cast<std::size_t>(ranks_));
  receive_bytes_.resize(static_cast<std::size_t>(ranks_));
  for (std::size_t r = 0; r < send_.size(); ++r) {
    send_bytes_[r].resize(send_[r].size() * ghost_bytes);
    receive_bytes_[r].resize(receive_[r].size() * ghost_bytes);
  }

  set = 0;
  contacts.for_each_wall_set([&](const WallContacts& c) {
    wall_slices_[static_cast<std::size_t>(set++)] =
        slices_by(c.size(), begin_, [&c](std::size_t k) { return static_cast<std::int64_t>(c.ball[k]); }, "wall");
  });
  pebbles_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (p.is_pebble(i)) pebbles_.push_back(static_cast<std::int32_t>(i));
  pebble_slices_ = slices_by(
      pebbles_.size(), begin_, [this](std::size_t k) { return static_cast<std::int64_t>(pebbles_[k]); }, "pebble");
  planned_ = true;
}

void Subdomains::require_whole(const char* what) const {
  if (!planned_ || whole_) return;
  throw std::logic_error(std::string("World::") + what + " read on a World spread over " + std::to_string(ranks_) +
                         " processes between a step that ended with StepEnd::WallsAndClumps (or, during a step, from a "
                         "controller) and the next gather_state(): each process holds only its own particles then");
}

void Subdomains::keep_local_near(const WorldContacts& contacts, StepPlan& plan) const {
  int set = 0;
  contacts.for_each_pair_set([&](const PairContacts& c) {
    const std::vector<std::uint8_t>& local = local_[static_cast<std::size_t>(set++)];
    std::erase_if(plan.pairs(c.kind).near, [&local](std::int32_t k) { return local[static_cast<std::size_t>(k)] == 0; });
  });
}

void Subdomains::share_contact_results(WorldState& state, double local_worst_ratio) {
  ParticleStore& p = state.particles;
  const auto me = static_cast<std::size_t>(rank_);
  const auto ranks = static_cast<std::size_t>(ranks_);
  // Only what is not zero travels: the sums of the pebbles that touch a ball (each pebble's
  // contacts are all computed where it is stored), and the touching wall contacts (about a third
  // of the candidates).
  struct PebbleRecord {
    std::int64_t pebble;  // position in pebbles_
    Vec3 force, torque;
  };
  struct WallRecord {
    std::int64_t contact;
    Vec3 force, point, moment;
    double normal_stiffness;
  };
  std::vector<PebbleRecord> pebbles;
  for (std::size_t k = pebble_slices_[me]; k < pebble_slices_[me + 1]; ++k) {
    const auto i = static_cast<std::size_t>(pebbles_[k]);
    if (!zero_bits(p.f[i]) || !zero_bits(p.t[i])) pebbles.push_back({static_cast<std::int64_t>(k), p.f[i], p.t[i]});
  }
  std::array<std::vector<WallRecord>, 2> walls;
  int set = 0;
  state.contacts.for_each_wall_set([&](const WallContacts& c) {
    const std::vector<std::size_t>& slices = wall_slices_[static_cast<std::size_t>(set)];
    for (std::size_t k = slices[me]; k < slices[me + 1]; ++k)
      if (c.normal_stiffness[k] != 0.0)
        walls[static_cast<std::size_t>(set)].push_back({static_cast<std::int64_t>(k), c.force[k], c.point[k], c.moment[k], c.normal_stiffness[k]});
    ++set;
  });
  // One header per process (its record counts and its worst overlap), then one buffer of
  // records per process: two collective calls a step.
  struct Header {
    std::int64_t pebbles, walls[2];
    double worst_ratio;
  };
  std::vector<Header> headers(ranks);
  headers[me] = {static_cast<std::int64_t>(pebbles.size()), {static_cast<std::int64_t>(walls[0].size()),
                 static_cast<std::int64_t>(walls[1].size())}, local_worst_ratio};
  std::vector<std::size_t> offsets(ranks + 1);
  for (std::size_t r = 0; r <= ranks; ++r) offsets[r] = r * sizeof(Header);
  comm_->allgather(reinterpret_cast<std::byte*>(headers.data()), offsets);
  worst_ratio_ = 0.0;
  for (const Header& h : headers) worst_ratio_ = std::max(worst_ratio_, h.worst_ratio);
  const auto bytes_of = [](const Header& h) {
    return static_cast<std::size_t>(h.pebbles) * sizeof(PebbleRecord) +
           static_cast<std::size_t>(h.walls[0] + h.walls[1]) * sizeof(WallRecord);
  };
  offsets[0] = 0;
  for (std::size_t r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + bytes_of(headers[r]);
  std::vector<std::byte>& buffer = buffer_;
  buffer.resize(offsets.back());
  {
    std::byte* at = buffer.data() + offsets[me];
    const auto put = [&at](const auto& records) {
      if (records.empty()) return;
      std::memcpy(at, records.data(), records.size() * sizeof(records[0]));
      at += records.size() * sizeof(records[0]);
    };
    put(pebbles), put(walls[0]), put(walls[1]);
  }
  if (offsets.back() > 0) comm_->allgather(buffer.data(), offsets);
  // Every process's records of one kind, in process order.
  std::vector<PebbleRecord> all_pebbles;
  std::array<std::vector<WallRecord>, 2> all_walls;
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::byte* at = buffer.data() + offsets[r];
    const auto take = [&at](auto& into, std::int64_t count) {
      const std::size_t old = into.size();
      into.resize(old + static_cast<std::size_t>(count));
      if (count > 0) std::memcpy(static_cast<void*>(into.data() + old), at, static_cast<std::size_t>(count) * sizeof(into[0]));
      at += static_cast<std::size_t>(count) * sizeof(into[0]);
    };
    take(all_pebbles, headers[r].pebbles), take(all_walls[0], headers[r].walls[0]), take(all_walls[1], headers[r].walls[1]);
  }

  // Pebbles of other subdomains: zero unless a record says otherwise (as in one process, where
  // the sums of a pebble that touches nothing stay the zeros they started from).
  if (!pebbles_.empty()) {
    for (std::size_t r = 0; r < ranks; ++r)
      if (r != me)
        for (std::size_t k = pebble_slices_[r]; k < pebble_slices_[r + 1]; ++k)
          p.f[static_cast<std::size_t>(pebbles_[k])].setZero(), p.t[static_cast<std::size_t>(pebbles_[k])].setZero();
    for (const PebbleRecord& record : all_pebbles) {
      const auto i = static_cast<std::size_t>(pebbles_[static_cast<std::size_t>(record.pebble)]);
      p.f[i] = record.force, p.t[i] = record.torque;
    }
  }
  // Other subdomains' wall candidates: only the touching ones count in the walls' sums.
  set = 0;
  state.contacts.for_each_wall_set([&](WallContacts& c) {
    const auto s = static_cast<std::size_t>(set++);
    if (c.size() == 0) return;
    const std::vector<std::size_t>& slices = wall_slices_[s];
    for (std::size_t r = 0; r < ranks; ++r)
      if (r != me)
        std::fill(c.normal_stiffness.begin() + static_cast<std::ptrdiff_t>(slices[r]),
                  c.normal_stiffness.begin() + static_cast<std::ptrdiff_t>(slices[r + 1]), 0.0);
    for (const WallRecord& record : all_walls[s]) {
      const auto k = static_cast<std::size_t>(record.contact);
      c.force[k] = record.force, c.point[k] = record.point, c.moment[k] = record.moment;
      c.normal_stiffness[k] = record.normal_stiffness;
    }
  });
}

std::pair<int, std::int64_t> Subdomains::worst_contact(int set, const OverlapMonitor& local, WorldState& state) {
  // The first set and lowest contact that have the largest ratio: one contact for all.
  const bool contender = local.ratio == worst_ratio_ && set >= 0;
  double winner = contender ? -set : -1e300;
  max(&winner, 1);
  double contact = contender && -set == winner ? -static_cast<double>(local.contact) : -1e300;
  max(&contact, 1);
  synchronise(state);
  return {static_cast<int>(-winner), static_cast<std::int64_t>(-contact)};
}

void Subdomains::share_ghosts(ParticleStore& p) {
  for (std::size_t r = 0; r < send_.size(); ++r) {
    std::byte* at = send_bytes_[r].data();
    for (const std::int32_t i : send_[r])
      for (const Vec3* field : {&p.x[static_cast<std::size_t>(i)], &p.v[static_cast<std::size_t>(i)], &p.w[static_cast<std::size_t>(i)]}) {
        std::memcpy(at, field->data(), sizeof(Vec3));
        at += sizeof(Vec3);
      }
  }
  comm_->exchange(send_bytes_, receive_bytes_);
  for (std::size_t r = 0; r < receive_.size(); ++r) {
    const std::byte* at = receive_bytes_[r].data();
    for (const std::int32_t i : receive_[r])
      for (Vec3* field : {&p.x[static_cast<std::size_t>(i)], &p.v[static_cast<std::size_t>(i)], &p.w[static_cast<std::size_t>(i)]}) {
        std::memcpy(field->data(), at, sizeof(Vec3));
        at += sizeof(Vec3);
      }
  }
}

void Subdomains::synchronise(WorldState& state) {
  if (!planned_ || whole_) return;
  whole_ = true;
  ParticleStore& p = state.particles;
  const std::size_t n = p.size();
  std::vector<std::size_t> particle_slices(begin_.begin(), begin_.end());
  gather_slices(*comm_, particle_slices, {field(p.x, n), field(p.v, n), field(p.w, n), field(p.f, n), field(p.t, n)}, buffer_);
  int set = 0;
  state.contacts.for_each_pair_set([&](PairContacts& c) {
    const std::vector<std::size_t>& slices = pair_slices_[static_cast<std::size_t>(set++)];
    if (c.size() == 0) return;
    gather_slices(*comm_, slices, {field(c.force, c.size()), field(c.normal_force, c.size()), field(c.touching, c.size())}, buffer_);
  });
  set = 0;
  state.contacts.for_each_wall_set([&](WallContacts& c) {
    const std::vector<std::size_t>& slices = wall_slices_[static_cast<std::size_t>(set++)];
    if (c.size() == 0) return;
    gather_slices(*comm_, slices,
                  {field(c.force, c.size()), field(c.torque_ball, c.size()), field(c.point, c.size()),
                   field(c.moment, c.size()), field(c.normal_force, c.size()), field(c.normal_stiffness, c.size())},
                  buffer_);
  });
}

void Subdomains::synchronise_history(WorldState& state) {
  if (!planned_ || history_) return;
  history_ = true;
  int set = 0;
  state.contacts.for_each_pair_set([&](PairContacts& c) {
    const std::vector<std::size_t>& slices = pair_slices_[static_cast<std::size_t>(set++)];
    if (c.size() > 0) gather_slices(*comm_, slices, {field(c.state)}, buffer_);
  });
  set = 0;
  state.contacts.for_each_wall_set([&](WallContacts& c) {
    const std::vector<std::size_t>& slices = wall_slices_[static_cast<std::size_t>(set++)];
    if (c.size() > 0) gather_slices(*comm_, slices, {field(c.state)}, buffer_);
  });
}

}  // namespace dem::parallel
