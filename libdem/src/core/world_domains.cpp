// One World spread over processes (World::spread_over; docs/parallel.md).
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
#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>
#include <dem/parallel/domain_comm.hpp>

namespace dem {

namespace detail {

/// The plan of a spread World, remade after every rebuild or load.
struct Subdomains {
  int ranks = 1, rank = 0;
  bool planned = false;
  bool whole = false;    // every process holds every particle and contact record (since the last step)
  bool history = false;  // ... and every contact's history
  double worst_ratio = 0.0;  // the step's worst overlap ratio over all processes
  std::vector<std::int64_t> begin;  // ranks + 1: process r owns particles [begin[r], begin[r + 1])
  std::vector<std::int32_t> range_of;  // per particle: the process whose subdomain holds it
  // Per pair set (ball-ball, ball-pebble), per candidate: 1 where this process computes it.
  std::array<std::vector<std::uint8_t>, 2> local;
  // Slices (in contacts) that each process holds the current records of: pair candidates by the
  // owner of their lower storage index (the lists are in that order), wall candidates by the
  // owner of their ball.
  std::array<std::vector<std::size_t>, 2> pair_slices, wall_slices;
  // The pebbles in storage order, and the slice of them in each subdomain.
  std::vector<std::int32_t> pebbles;
  std::vector<std::size_t> pebble_slices;
  // Ghosts: send[r] are this process's balls that r computes contacts of; receive[r] are r's that
  // this process does (storage indices, ascending).
  std::vector<std::vector<std::int32_t>> send, receive;
  std::vector<std::vector<std::byte>> send_bytes, receive_bytes;
  std::vector<std::byte> buffer;
};

}  // namespace detail

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

void World::spread_over(std::shared_ptr<parallel::DomainComm> comm) {
  require(comm != nullptr, "spread_over communicator", "null", "a communicator");
  if (comm->ranks() <= 1) {
    comm_.reset();
    domains_.reset();
    return;
  }
  comm_ = std::move(comm);
  domains_ = std::make_shared<detail::Subdomains>();
  domains_->ranks = comm_->ranks();
  domains_->rank = comm_->rank();
}

int World::ranks() const { return domains_ ? domains_->ranks : 1; }
int World::rank() const { return domains_ ? domains_->rank : 0; }

std::pair<std::size_t, std::size_t> World::owned_range() const {
  if (!domains_ || !domains_->planned) return {0, state_.particles.size()};
  const auto me = static_cast<std::size_t>(domains_->rank);
  return {static_cast<std::size_t>(domains_->begin[me]), static_cast<std::size_t>(domains_->begin[me + 1])};
}

void World::plan_domains() {
  if (!spread() || domains_->planned) return;
  detail::Subdomains& d = *domains_;
  const ParticleStore& p = state_.particles;
  const std::size_t n = p.size();
  const int me = d.rank;
  WorldContacts& contacts = state_.contacts;

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
  d.begin.assign(1, 0);
  std::int64_t done = 0;
  for (std::size_t i = 0; i < n && static_cast<int>(d.begin.size()) < d.ranks; ++i) {
    done += work[i];
    while (static_cast<int>(d.begin.size()) < d.ranks && done * d.ranks >= total * static_cast<std::int64_t>(d.begin.size()))
      d.begin.push_back(static_cast<std::int64_t>(i) + 1);
  }
  while (static_cast<int>(d.begin.size()) <= d.ranks) d.begin.push_back(static_cast<std::int64_t>(n));
  d.begin.back() = static_cast<std::int64_t>(n);
  d.range_of.assign(n, 0);
  for (int r = 0; r < d.ranks; ++r)
    for (std::int64_t i = d.begin[static_cast<std::size_t>(r)]; i < d.begin[static_cast<std::size_t>(r) + 1]; ++i)
      d.range_of[static_cast<std::size_t>(i)] = r;

  d.send.assign(static_cast<std::size_t>(d.ranks), {});
  d.receive.assign(static_cast<std::size_t>(d.ranks), {});
  int set = 0;
  contacts.for_each_pair_set([&](const PairContacts& c) {
    std::vector<std::uint8_t>& local = d.local[static_cast<std::size_t>(set)];
    local.assign(c.size(), 0);
    for (std::size_t k = 0; k < c.size(); ++k) {
      const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
      const int ri = d.range_of[i], rj = d.range_of[j];
      local[k] = ri == me || rj == me;
      if (ri == rj) continue;
      // Pebbles are stepped by every process: only balls travel as ghosts.
      if (ri == me && !p.is_pebble(i)) d.send[static_cast<std::size_t>(rj)].push_back(static_cast<std::int32_t>(i));
      if (rj == me && !p.is_pebble(j)) d.send[static_cast<std::size_t>(ri)].push_back(static_cast<std::int32_t>(j));
      if (rj == me && !p.is_pebble(i)) d.receive[static_cast<std::size_t>(ri)].push_back(static_cast<std::int32_t>(i));
      if (ri == me && !p.is_pebble(j)) d.receive[static_cast<std::size_t>(rj)].push_back(static_cast<std::int32_t>(j));
    }
    d.pair_slices[static_cast<std::size_t>(set)] = slices_by(
        c.size(), d.begin, [&c](std::size_t k) { return static_cast<std::int64_t>(std::min(c.first[k], c.second[k])); }, "pair");
    ++set;
  });
  for (auto* lists : {&d.send, &d.receive})
    for (auto& list : *lists) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  constexpr std::size_t ghost_bytes = 3 * sizeof(Vec3);  // x, v, w
  d.send_bytes.resize(static_cast<std::size_t>(d.ranks));
  d.receive_bytes.resize(static_cast<std::size_t>(d.ranks));
  for (std::size_t r = 0; r < d.send.size(); ++r) {
    d.send_bytes[r].resize(d.send[r].size() * ghost_bytes);
    d.receive_bytes[r].resize(d.receive[r].size() * ghost_bytes);
  }

  set = 0;
  contacts.for_each_wall_set([&](const WallContacts& c) {
    d.wall_slices[static_cast<std::size_t>(set++)] =
        slices_by(c.size(), d.begin, [&c](std::size_t k) { return static_cast<std::int64_t>(c.ball[k]); }, "wall");
  });
  d.pebbles.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (p.is_pebble(i)) d.pebbles.push_back(static_cast<std::int32_t>(i));
  d.pebble_slices = slices_by(
      d.pebbles.size(), d.begin, [&d](std::size_t k) { return static_cast<std::int64_t>(d.pebbles[k]); }, "pebble");
  d.planned = true;
}

void World::require_whole(const char* what) const {
  if (!domains_ || !domains_->planned || domains_->whole) return;
  throw std::logic_error(std::string("World::") + what + " read on a World spread over " + std::to_string(domains_->ranks) +
                         " processes between a step that ended with StepEnd::WallsAndClumps (or, during a step, from a "
                         "controller) and the next gather_state(): each process holds only its own particles then");
}

void World::forget_domains() {
  if (domains_) domains_->planned = false;
}

void World::copies_go_stale() {
  if (domains_) domains_->whole = domains_->history = false;
}

void World::keep_local_near() {
  if (!spread()) return;
  int set = 0;
  state_.contacts.for_each_pair_set([&](const PairContacts& c) {
    const std::vector<std::uint8_t>& local = domains_->local[static_cast<std::size_t>(set++)];
    std::erase_if(plan_.pairs(c.kind).near, [&local](std::int32_t k) { return local[static_cast<std::size_t>(k)] == 0; });
  });
}

void World::share_contact_results(double local_worst_ratio) {
  if (!spread()) return;
  detail::Subdomains& d = *domains_;
  ParticleStore& p = state_.particles;
  const auto me = static_cast<std::size_t>(d.rank);
  const auto ranks = static_cast<std::size_t>(d.ranks);
  // Only what is not zero travels: the sums of the pebbles that touch a ball (each pebble's
  // contacts are all computed where it is stored), and the touching wall contacts (about a third
  // of the candidates).
  struct PebbleRecord {
    std::int64_t pebble;  // position in d.pebbles
    Vec3 force, torque;
  };
  struct WallRecord {
    std::int64_t contact;
    Vec3 force, point, moment;
    double normal_stiffness;
  };
  std::vector<PebbleRecord> pebbles;
  for (std::size_t k = d.pebble_slices[me]; k < d.pebble_slices[me + 1]; ++k) {
    const auto i = static_cast<std::size_t>(d.pebbles[k]);
    if (!zero_bits(p.f[i]) || !zero_bits(p.t[i])) pebbles.push_back({static_cast<std::int64_t>(k), p.f[i], p.t[i]});
  }
  std::array<std::vector<WallRecord>, 2> walls;
  int set = 0;
  state_.contacts.for_each_wall_set([&](const WallContacts& c) {
    const std::vector<std::size_t>& slices = d.wall_slices[static_cast<std::size_t>(set)];
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
  d.worst_ratio = 0.0;
  for (const Header& h : headers) d.worst_ratio = std::max(d.worst_ratio, h.worst_ratio);
  const auto bytes_of = [](const Header& h) {
    return static_cast<std::size_t>(h.pebbles) * sizeof(PebbleRecord) +
           static_cast<std::size_t>(h.walls[0] + h.walls[1]) * sizeof(WallRecord);
  };
  offsets[0] = 0;
  for (std::size_t r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + bytes_of(headers[r]);
  std::vector<std::byte>& buffer = d.buffer;
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
  if (!d.pebbles.empty()) {
    for (std::size_t r = 0; r < ranks; ++r)
      if (r != me)
        for (std::size_t k = d.pebble_slices[r]; k < d.pebble_slices[r + 1]; ++k)
          p.f[static_cast<std::size_t>(d.pebbles[k])].setZero(), p.t[static_cast<std::size_t>(d.pebbles[k])].setZero();
    for (const PebbleRecord& record : all_pebbles) {
      const auto i = static_cast<std::size_t>(d.pebbles[static_cast<std::size_t>(record.pebble)]);
      p.f[i] = record.force, p.t[i] = record.torque;
    }
  }
  // Other subdomains' wall candidates: only the touching ones count in the walls' sums.
  set = 0;
  state_.contacts.for_each_wall_set([&](WallContacts& c) {
    const auto s = static_cast<std::size_t>(set++);
    if (c.size() == 0) return;
    const std::vector<std::size_t>& slices = d.wall_slices[s];
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

void World::share_ghosts() {
  if (!spread()) return;
  detail::Subdomains& d = *domains_;
  ParticleStore& p = state_.particles;
  for (std::size_t r = 0; r < d.send.size(); ++r) {
    std::byte* at = d.send_bytes[r].data();
    for (const std::int32_t i : d.send[r])
      for (const Vec3* field : {&p.x[static_cast<std::size_t>(i)], &p.v[static_cast<std::size_t>(i)], &p.w[static_cast<std::size_t>(i)]}) {
        std::memcpy(at, field->data(), sizeof(Vec3));
        at += sizeof(Vec3);
      }
  }
  comm_->exchange(d.send_bytes, d.receive_bytes);
  for (std::size_t r = 0; r < d.receive.size(); ++r) {
    const std::byte* at = d.receive_bytes[r].data();
    for (const std::int32_t i : d.receive[r])
      for (Vec3* field : {&p.x[static_cast<std::size_t>(i)], &p.v[static_cast<std::size_t>(i)], &p.w[static_cast<std::size_t>(i)]}) {
        std::memcpy(field->data(), at, sizeof(Vec3));
        at += sizeof(Vec3);
      }
  }
}

void World::synchronise() {
  if (!spread() || !domains_->planned || domains_->whole) return;
  detail::Subdomains& d = *domains_;
  d.whole = true;
  ParticleStore& p = state_.particles;
  const std::size_t n = p.size();
  std::vector<std::size_t> particle_slices(d.begin.begin(), d.begin.end());
  gather_slices(*comm_, particle_slices, {field(p.x, n), field(p.v, n), field(p.w, n), field(p.f, n), field(p.t, n)}, d.buffer);
  int set = 0;
  state_.contacts.for_each_pair_set([&](PairContacts& c) {
    const std::vector<std::size_t>& slices = d.pair_slices[static_cast<std::size_t>(set++)];
    if (c.size() == 0) return;
    gather_slices(*comm_, slices, {field(c.force, c.size()), field(c.normal_force, c.size()), field(c.touching, c.size())}, d.buffer);
  });
  set = 0;
  state_.contacts.for_each_wall_set([&](WallContacts& c) {
    const std::vector<std::size_t>& slices = d.wall_slices[static_cast<std::size_t>(set++)];
    if (c.size() == 0) return;
    gather_slices(*comm_, slices,
                  {field(c.force, c.size()), field(c.torque_ball, c.size()), field(c.point, c.size()),
                   field(c.moment, c.size()), field(c.normal_force, c.size()), field(c.normal_stiffness, c.size())},
                  d.buffer);
  });
}

void World::synchronise_history() {
  if (!spread() || !domains_->planned || domains_->history) return;
  detail::Subdomains& d = *domains_;
  d.history = true;
  int set = 0;
  state_.contacts.for_each_pair_set([&](PairContacts& c) {
    const std::vector<std::size_t>& slices = d.pair_slices[static_cast<std::size_t>(set++)];
    if (c.size() > 0) gather_slices(*comm_, slices, {field(c.state)}, d.buffer);
  });
  set = 0;
  state_.contacts.for_each_wall_set([&](WallContacts& c) {
    const std::vector<std::size_t>& slices = d.wall_slices[static_cast<std::size_t>(set++)];
    if (c.size() > 0) gather_slices(*comm_, slices, {field(c.state)}, d.buffer);
  });
}

const WorldState& World::state() const {
  require_whole("state()");
  require_pair_records("state()");  // a restart file's touching contacts are those with records
  // The history is a restart file's alone (and a rebuild's): gathered when asked for.
  if (spread() && !domains_->history) const_cast<World*>(this)->synchronise_history();
  return state_;
}

void World::global_max(double* values, std::size_t count) {
  if (spread()) comm_->max(values, count);
}

World::WorstOverlap World::global_worst(const WorstOverlap& local) {
  if (!spread()) return local;
  // The largest ratio (gathered with the contact results), then the first set and lowest contact
  // that has it: one contact for all.
  const double ratio = domains_->worst_ratio;
  if (ratio <= state_.settings.max_overlap_ratio) return local;
  int set = 0, found = -1;
  state_.contacts.for_each_set([&](const auto& c) {
    if (const auto* const* mine = std::get_if<std::remove_cvref_t<decltype(&c)>>(&local.set); mine && *mine == &c) found = set;
    ++set;
  });
  const bool contender = local.monitor.ratio == ratio && found >= 0;
  double winner = contender ? -found : -1e300;
  global_max(&winner, 1);
  double contact = contender && -found == winner ? -static_cast<double>(local.monitor.contact) : -1e300;
  global_max(&contact, 1);
  synchronise();
  WorstOverlap worst;
  worst.monitor = OverlapMonitor{ratio, static_cast<std::int64_t>(-contact)};
  set = 0;
  state_.contacts.for_each_set([&](const auto& c) {
    if (set++ == static_cast<int>(-winner)) worst.set = &c;
  });
  return worst;
}

}  // namespace dem
