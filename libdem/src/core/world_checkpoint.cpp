// World state to and from a binary stream, for restart files. Doubles are written as their bytes,
// so a resumed run continues exactly. The framing (format version, checksum, atomic write) is
// io/checkpoint.cpp's job. The reader checks every count, index and value a later step trusts:
// the checksum only stops random damage, not a file written wrong with a matching checksum.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>

namespace dem {

namespace {

struct Writer {
  std::ostream& out;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    if constexpr (std::is_same_v<T, Vec3>) {
      for (const Vec3& x : v) pod(x.x()), pod(x.y()), pod(x.z());
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
    }
  }
  void vec3(const Vec3& x) { pod(x.x()), pod(x.y()), pod(x.z()); }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    out.write(s.data(), static_cast<std::streamsize>(s.size()));
  }
};

// Reading side: every value a later step trusts is checked here, because a restart file may
// come from a buggy or foreign writer with a valid checksum. A refusal is an InputError
// "checkpoint: <field> = <value>: must be <allowed>"; the World is left unchanged.

constexpr std::uint64_t unknown_size = std::numeric_limits<std::uint64_t>::max();
// Coordinates and radii beyond this overflow the broad phase's squared distances (~1e154 m).
constexpr double max_length = 1e100;  // m

template <class T>
[[noreturn]] void refuse(const std::string& field, const T& value, const std::string& allowed) {
  std::ostringstream msg;
  msg.precision(10);
  msg << "checkpoint: " << field << " = " << value << ": must be " << allowed;
  throw InputError(msg.str());
}

// Step and rebuild counters: beyond any run (1e15 steps take 30 years at 1 us a step) and far
// enough below INT64_MAX that counting on from them cannot overflow.
constexpr std::int64_t max_counter = 1'000'000'000'000'000;

std::string at(const std::string& field, std::size_t k) { return field + "[" + std::to_string(k) + "]"; }

struct Reader {
  std::istream& in;
  std::uint64_t remaining;  // bytes left in the stream: no count may promise more than this

  void take(void* into, std::uint64_t bytes, const std::string& field) {
    if (bytes > remaining)
      throw InputError("checkpoint: truncated data (stream ended early): " + field + " needs " +
                       std::to_string(bytes) + " bytes, " + std::to_string(remaining) + " remain");
    in.read(static_cast<char*>(into), static_cast<std::streamsize>(bytes));
    if (!in)
      throw InputError("checkpoint: truncated data (stream ended early) in " + field);
    remaining -= bytes;
  }
  template <class T>
  T pod(const std::string& field) {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>, "bools: use flag()");
    T v{};
    take(&v, sizeof(T), field);
    return v;
  }
  /// A bool written as its byte; any other byte than 0 or 1 is not a bool (and loading it as one
  /// is undefined behaviour).
  bool flag(const std::string& field) {
    const auto byte = pod<std::uint8_t>(field);
    if (byte > 1) refuse(field, static_cast<int>(byte), "0 or 1 (a bool)");
    return byte == 1;
  }
  double number(const std::string& field) {
    const double x = pod<double>(field);
    if (!std::isfinite(x)) refuse(field, x, "finite");
    return x;
  }
  /// An array length, refused before anything is allocated if the bytes left cannot hold it.
  std::uint64_t count(const std::string& field, std::uint64_t entry_bytes) {
    const auto n = pod<std::uint64_t>(field + " count");
    const std::uint64_t fit = remaining / std::max<std::uint64_t>(entry_bytes, 1);
    if (n > fit)
      refuse(field + " count", n,
             "at most " + std::to_string(fit) + " (" + std::to_string(remaining) + " bytes remain, at least " +
                 std::to_string(entry_bytes) + " per entry)");
    return n;
  }
  template <class T>
  std::vector<T> vec(const std::string& field) {
    if constexpr (std::is_same_v<T, Vec3>) {
      std::vector<Vec3> v(count(field, 3 * sizeof(double)));
      for (Vec3& x : v) x = vec3(field);
      return v;
    } else {
      static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>);
      std::vector<T> v(count(field, sizeof(T)));
      take(v.data(), v.size() * sizeof(T), field);
      return v;
    }
  }
  /// Three doubles, unchecked (a velocity or force may be anything; see check_finite).
  Vec3 vec3(const std::string& field) {
    const double x = pod<double>(field), y = pod<double>(field), z = pod<double>(field);
    return Vec3(x, y, z);
  }
  Vec3 finite3(const std::string& field) {
    const Vec3 x = vec3(field);
    if (!x.allFinite()) refuse(field, show(x), "finite");
    return x;
  }
  std::int64_t counter(const std::string& field) {
    const auto n = pod<std::int64_t>(field);
    if (n < 0 || n > max_counter) refuse(field, n, "in [0, " + std::to_string(max_counter) + "]");
    return n;
  }
  std::string text(const std::string& field) {
    std::string s(count(field, 1), '\0');
    take(s.data(), s.size(), field);
    return s;
  }
  static std::string show(const Vec3& x) {
    std::ostringstream out;
    out.precision(10);
    out << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")";
    return out.str();
  }
};

/// Bytes from the read position to the end, or unknown_size if the stream cannot seek.
std::uint64_t bytes_left(std::istream& in) {
  const auto here = in.tellg();
  if (here < 0) return unknown_size;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  if (end < here || !in) return unknown_size;
  return static_cast<std::uint64_t>(end - here);
}

void write_states(Writer& w, const StateBuffer& b) {
  w.pod<std::uint64_t>(b.stride);
  w.pod<std::uint64_t>(b.count);
  w.out.write(reinterpret_cast<const char*>(b.bytes.data()), static_cast<std::streamsize>(b.bytes.size()));
}

void write_pairs(Writer& w, const PairContacts& c) {
  w.vec(c.first);
  w.vec(c.second);
  w.vec(c.force);
  // The torques on piece 1 are scratch of the step that gathers: written before they are read,
  // and only for the contacts the current thread plan gathers. Saved, their other entries would
  // make the file depend on earlier plans, not on the state. The format keeps their place.
  w.vec(std::vector<Vec3>{});
  w.vec(std::vector<Vec3>{});  // torque_second: no longer stored (second_torque); the format keeps its place
  w.vec(c.normal_force);
  write_states(w, c.state);
}

// --- checks shared by the parts of the state ---------------------------------------------------

void check_points(const std::vector<Vec3>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite() || v[k].cwiseAbs().maxCoeff() > max_length)
      refuse(at(field, k), Reader::show(v[k]), "finite, within +-1e100 m");
}

void check_finite(const std::vector<Vec3>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite()) refuse(at(field, k), Reader::show(v[k]), "finite");
}

void check_finite(const std::vector<double>& v, const std::string& field, double low) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!(std::isfinite(v[k]) && v[k] >= low)) refuse(at(field, k), v[k], "finite and >= " + std::to_string(low));
}

void check_index(const std::vector<std::int32_t>& v, std::size_t limit, const std::string& field,
                 const std::string& limit_name) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= limit)
      refuse(at(field, k), v[k], "in [0, " + std::to_string(limit) + ") (" + limit_name + ")");
}

void check_length(std::size_t size, std::size_t expected, const std::string& field, const std::string& why) {
  if (size != expected) refuse(field + " count", size, std::to_string(expected) + " (" + why + ")");
}

/// Per-contact results are saved empty when no step has computed them since the last rebuild;
/// otherwise they have one entry per contact. Empty ones are filled with the zeros the next
/// step starts from, so that every reader can index them by contact. Vector values are not
/// checked: a ball-facet contact point stays unset (any bits, NaN too) while the contact does
/// not touch, and the next step recomputes them all before the engine uses them.
template <class T>
void fill_results(std::vector<T>& v, std::size_t contacts, const std::string& field) {
  if (!v.empty() && v.size() != contacts)
    refuse(field + " count", v.size(), "0 or " + std::to_string(contacts) + " (one per contact)");
  if constexpr (std::is_same_v<T, Vec3>) {
    v.resize(contacts, Vec3::Zero());
  } else {
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k])) refuse(at(field, k), v[k], "finite");
    v.resize(contacts, 0.0);
  }
}

// --- settings and clock -------------------------------------------------------------------------

/// The same rules as the World constructor, so that a loaded World is one that could be built.
WorldSettings read_settings(Reader& r, WorldSettings s) {
  s.time_step = r.number("settings.time_step");
  if (s.time_step < 0.0) refuse("settings.time_step", s.time_step, ">= 0 s (0: automatic)");
  s.time_step_safety = r.number("settings.time_step_safety");
  if (!(s.time_step_safety > 0.0 && s.time_step_safety <= 1.0))
    refuse("settings.time_step_safety", s.time_step_safety, "in (0, 1]");
  s.local_damping = r.number("settings.local_damping");
  if (!(s.local_damping >= 0.0 && s.local_damping < 1.0)) refuse("settings.local_damping", s.local_damping, "in [0, 1)");
  s.gravity = r.finite3("settings.gravity");
  s.skin = r.number("settings.skin");
  if (!(s.skin >= 0.0 && s.skin <= max_length)) refuse("settings.skin", s.skin, "in [0, 1e100] m (0: automatic)");
  s.sort_every = r.pod<int>("settings.sort_every");  // any value: <= 0 means never
  s.max_overlap_ratio = r.number("settings.max_overlap_ratio");
  if (!(s.max_overlap_ratio > 0.0)) refuse("settings.max_overlap_ratio", s.max_overlap_ratio, "> 0");
  s.max_step_travel_ratio = r.number("settings.max_step_travel_ratio");
  if (!(s.max_step_travel_ratio > 0.0)) refuse("settings.max_step_travel_ratio", s.max_step_travel_ratio, "> 0");
  s.pebble_pebble_contacts = r.flag("settings.pebble_pebble_contacts");
  return s;
}

// --- particles and clumps -----------------------------------------------------------------------

void check_particle_arrays(const ParticleStore& p) {
  const std::size_t n = p.id.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<ParticleId>::max()))
    refuse("particles.id count", n, "<= 2147483647 (ids are 32-bit)");
  const std::string why = "one per particle, as particles.id";
  check_length(p.x.size(), n, "particles.x", why), check_length(p.v.size(), n, "particles.v", why);
  check_length(p.w.size(), n, "particles.w", why), check_length(p.f.size(), n, "particles.f", why);
  check_length(p.t.size(), n, "particles.t", why), check_length(p.radius.size(), n, "particles.radius", why);
  check_length(p.mass.size(), n, "particles.mass", why), check_length(p.inv_mass.size(), n, "particles.inv_mass", why);
  check_length(p.inv_inertia.size(), n, "particles.inv_inertia", why);
  check_length(p.group.size(), n, "particles.group", why), check_length(p.clump.size(), n, "particles.clump", why);
  check_length(p.fixed.size(), n, "particles.fixed", why);
}

void check_particle_values(const ParticleStore& p) {
  check_points(p.x, "particles.x");
  check_finite(p.v, "particles.v"), check_finite(p.w, "particles.w");
  check_finite(p.f, "particles.f"), check_finite(p.t, "particles.t");
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!(p.radius[i] > 0.0 && p.radius[i] <= max_length)) refuse(at("particles.radius", i), p.radius[i], "in (0, 1e100] m");
  check_finite(p.mass, "particles.mass", 0.0);
  check_finite(p.inv_mass, "particles.inv_mass", 0.0);
  check_finite(p.inv_inertia, "particles.inv_inertia", 0.0);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed[i] > dof_all) refuse(at("particles.fixed", i), static_cast<int>(p.fixed[i]), "Dof bits (0..63)");
  // Stable ids are a permutation of [0, n): the id -> index map and contact history rely on it.
  std::vector<bool> seen(p.size(), false);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const ParticleId pid = p.id[i];
    if (pid < 0 || static_cast<std::size_t>(pid) >= p.size())
      refuse(at("particles.id", i), pid, "in [0, " + std::to_string(p.size()) + ") (the particle count)");
    if (seen[static_cast<std::size_t>(pid)]) refuse(at("particles.id", i), pid, "unique (it appears twice)");
    seen[static_cast<std::size_t>(pid)] = true;
  }
}

ParticleStore read_particles(Reader& r) {
  ParticleStore p;
  p.x = r.vec<Vec3>("particles.x"), p.v = r.vec<Vec3>("particles.v"), p.w = r.vec<Vec3>("particles.w");
  p.f = r.vec<Vec3>("particles.f"), p.t = r.vec<Vec3>("particles.t");
  p.radius = r.vec<double>("particles.radius"), p.mass = r.vec<double>("particles.mass");
  p.inv_mass = r.vec<double>("particles.inv_mass"), p.inv_inertia = r.vec<double>("particles.inv_inertia");
  p.id = r.vec<ParticleId>("particles.id"), p.group = r.vec<int>("particles.group");
  p.clump = r.vec<std::int32_t>("particles.clump"), p.fixed = r.vec<std::uint8_t>("particles.fixed");
  check_particle_arrays(p);
  check_particle_values(p);
  p.restore_index();
  return p;
}

// The smallest a saved clump can be (no pebbles): mass, x, v, w, orientation, inertia, fixed,
// two counts, five vectors. Bounds the clump count by the bytes that remain.
constexpr std::uint64_t min_clump_bytes = 8 + 3 * 24 + 4 * 8 + 9 * 8 + 1 + 2 * 8 + 5 * 24;

Clump read_clump(Reader& r, const std::string& name) {
  Clump c;
  c.mass = r.number(name + ".mass");
  if (!(c.mass > 0.0)) refuse(name + ".mass", c.mass, "> 0 kg");
  c.x = r.finite3(name + ".x");
  if (c.x.cwiseAbs().maxCoeff() > max_length) refuse(name + ".x", Reader::show(c.x), "within +-1e100 m");
  c.v = r.finite3(name + ".v"), c.w = r.finite3(name + ".w");
  const double qw = r.number(name + ".orientation"), qx = r.number(name + ".orientation");
  const double qy = r.number(name + ".orientation"), qz = r.number(name + ".orientation");
  c.orientation = Quat(qw, qx, qy, qz);
  if (std::abs(c.orientation.norm() - 1.0) > 1e-6) refuse(name + ".orientation |q|", c.orientation.norm(), "1 (a unit quaternion)");
  for (int i = 0; i < 9; ++i) c.inertia_body.data()[i] = r.number(name + ".inertia_body");
  const Mat3& j = c.inertia_body;
  if (!((j - j.transpose()).norm() <= 1e-9 * j.norm() && j.ldlt().isPositive() && j.determinant() > 0.0))
    refuse(name + ".inertia_body", "(not symmetric positive definite)", "a symmetric positive definite tensor");
  c.inv_inertia_body = j.inverse();
  c.fixed = r.pod<std::uint8_t>(name + ".fixed");
  if (c.fixed > dof_all) refuse(name + ".fixed", static_cast<int>(c.fixed), "Dof bits (0..63)");
  c.pebbles = r.vec<ParticleId>(name + ".pebbles");
  if (c.pebbles.empty()) refuse(name + ".pebbles count", 0, "> 0 (a clump is made of pebbles)");
  c.pebble_offsets = r.vec<Vec3>(name + ".pebble_offsets");
  check_length(c.pebble_offsets.size(), c.pebbles.size(), name + ".pebble_offsets", "one per pebble");
  check_points(c.pebble_offsets, name + ".pebble_offsets");
  c.force = r.finite3(name + ".force"), c.torque = r.finite3(name + ".torque");
  c.applied_force = r.finite3(name + ".applied_force"), c.applied_torque = r.finite3(name + ".applied_torque");
  c.displacement = r.finite3(name + ".displacement");
  return c;
}

/// Clump membership both ways: particles.clump[i] = c exactly for the pebbles clump c lists.
void check_membership(const std::vector<Clump>& clumps, const ParticleStore& p) {
  const std::size_t n = p.size();
  std::vector<std::size_t> members(clumps.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t c = p.clump[i];
    if (c < -1 || (c >= 0 && static_cast<std::size_t>(c) >= clumps.size()))
      refuse(at("particles.clump", i), c, "-1 (a free ball) or in [0, " + std::to_string(clumps.size()) + ") (the clump count)");
    if (c >= 0) ++members[static_cast<std::size_t>(c)];
  }
  std::vector<bool> listed(n, false);
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const std::string name = at("clumps", c) + ".pebbles";
    const auto& pebbles = clumps[c].pebbles;
    for (std::size_t k = 0; k < pebbles.size(); ++k) {
      const ParticleId pid = pebbles[k];
      if (pid < 0 || static_cast<std::size_t>(pid) >= n)
        refuse(at(name, k), pid, "in [0, " + std::to_string(n) + ") (a particle id)");
      const std::size_t i = p.index_of(pid);
      if (p.clump[i] != static_cast<std::int32_t>(c))
        refuse(at(name, k), pid, "a pebble of this clump (that particle has particles.clump = " + std::to_string(p.clump[i]) + ")");
      if (listed[i]) refuse(at(name, k), pid, "listed once (it appears twice)");
      listed[i] = true;
    }
    if (pebbles.size() != members[c])
      refuse(name + " count", pebbles.size(), std::to_string(members[c]) + " (the particles with particles.clump = " + std::to_string(c) + ")");
  }
}

std::vector<Clump> read_clumps(Reader& r, const ParticleStore& p) {
  std::vector<Clump> clumps(r.count("clumps", min_clump_bytes));
  for (std::size_t c = 0; c < clumps.size(); ++c) clumps[c] = read_clump(r, at("clumps", c));
  check_membership(clumps, p);
  return clumps;
}

// --- walls ----------------------------------------------------------------------------------------

// name, vertices and triangles counts, four vectors, area, two vectors, contact count, stiffness.
constexpr std::uint64_t min_wall_bytes = 3 * 8 + 4 * 24 + 8 + 2 * 24 + 4 + 8;

FacetWall read_wall(Reader& r, const std::string& name) {
  FacetWall wall;
  wall.name = r.text(name + ".name");
  wall.mesh.vertices = r.vec<Vec3>(name + ".mesh.vertices");
  check_points(wall.mesh.vertices, name + ".mesh.vertices");
  wall.mesh.triangles = r.vec<std::array<int, 3>>(name + ".mesh.triangles");
  const std::size_t vertices = wall.mesh.vertices.size();
  for (std::size_t t = 0; t < wall.mesh.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = wall.mesh.triangles[t][k];
      if (v < 0 || static_cast<std::size_t>(v) >= vertices)
        refuse(at(name + ".mesh.triangles", t) + " vertex " + std::to_string(k), v,
               "in [0, " + std::to_string(vertices) + ") (the wall's vertex count)");
    }
  wall.velocity = r.finite3(name + ".velocity"), wall.displacement = r.finite3(name + ".displacement");
  wall.reference_point = r.finite3(name + ".reference_point"), wall.outward_normal = r.finite3(name + ".outward_normal");
  wall.area = r.number(name + ".area");
  if (wall.area < 0.0) refuse(name + ".area", wall.area, ">= 0 m^2");
  wall.force = r.finite3(name + ".force"), wall.moment = r.finite3(name + ".moment");
  wall.contact_count = r.pod<int>(name + ".contact_count");
  if (wall.contact_count < 0) refuse(name + ".contact_count", wall.contact_count, ">= 0");
  wall.stiffness_sum = r.number(name + ".stiffness_sum");
  if (wall.stiffness_sum < 0.0) refuse(name + ".stiffness_sum", wall.stiffness_sum, ">= 0 N/m");
  return wall;
}

std::vector<FacetWall> read_walls(Reader& r) {
  std::vector<FacetWall> walls(r.count("walls", min_wall_bytes));
  for (std::size_t w = 0; w < walls.size(); ++w) walls[w] = read_wall(r, at("walls", w));
  return walls;
}

// --- contacts ---------------------------------------------------------------------------------------

/// The law history: `contacts` States of the model's size (none without a model).
void read_states(Reader& r, const ContactModel* model, StateBuffer& b, std::size_t contacts, const std::string& name) {
  const auto stride = r.pod<std::uint64_t>(name + ".state stride");
  if (model == nullptr) {
    const auto count = r.pod<std::uint64_t>(name + ".state count");
    if (count != 0) refuse(name + ".state count", count, "0 (no contact model is set for them)");
    b = StateBuffer{};
    return;
  }
  model->reset_states(b, 0);  // learns the law's State size
  const std::size_t size = b.stride;
  const auto count = r.count(name + ".state", size);
  if (count != contacts) refuse(name + ".state count", count, std::to_string(contacts) + " (one per contact)");
  if (count > 0 && stride != size)
    refuse(name + ".state stride", stride, std::to_string(size) + " bytes (this contact law's history; another law wrote it)");
  model->reset_states(b, count);  // typed construction; the saved bytes then restore the values
  r.take(b.bytes.data(), b.bytes.size(), name + ".state");
}

/// Pieces of each pair: in range, distinct, of the kinds the broad phase puts in this list.
void check_pair_pieces(const PairContacts& c, const ParticleStore& p, bool pebble_pebble, const std::string& name) {
  const std::size_t n = p.size();
  check_index(c.first, n, name + ".first", "the particle count");
  check_index(c.second, n, name + ".second", "the particle count");
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
    if (i == j) refuse(at(name + ".second", k), c.second[k], "another particle than first");
    if (c.kind == ContactKind::BallBall) {
      if (p.is_pebble(i) || p.is_pebble(j))
        refuse(at(name + ".first/second", k), std::to_string(c.first[k]) + "/" + std::to_string(c.second[k]), "two balls (not pebbles)");
    } else if (!p.is_pebble(j) || (p.is_pebble(i) && (!pebble_pebble || p.clump[i] == p.clump[j]))) {
      refuse(at(name + ".first/second", k), std::to_string(c.first[k]) + "/" + std::to_string(c.second[k]),
             "a ball (or, with pebble_pebble_contacts, a pebble of another clump) and a pebble");
    }
  }
}

PairContacts read_pairs(Reader& r, const ContactModel* model, ContactKind kind, const ParticleStore& p,
                        bool pebble_pebble) {
  const std::string name = std::string(to_string(kind)) + " contacts";
  PairContacts c;
  c.kind = kind;
  c.first = r.vec<std::int32_t>(name + ".first");
  c.second = r.vec<std::int32_t>(name + ".second");
  c.force = r.vec<Vec3>(name + ".force");
  std::vector<Vec3> torque_first = r.vec<Vec3>(name + ".torque_first");  // older files: checked, not kept
  std::vector<Vec3> torque_second = r.vec<Vec3>(name + ".torque_second");  // older files: checked, not kept
  c.normal_force = r.vec<double>(name + ".normal_force");
  const std::size_t count = c.size();
  check_length(c.second.size(), count, name + ".second", "one per contact, as first");
  check_pair_pieces(c, p, pebble_pebble, name);
  // The rebuild assigns normal forces to every candidate; the other results may still be empty.
  check_length(c.normal_force.size(), count, name + ".normal_force", "one per contact");
  fill_results(c.normal_force, count, name + ".normal_force");
  fill_results(c.force, count, name + ".force");
  fill_results(torque_first, count, name + ".torque_first");
  fill_results(torque_second, count, name + ".torque_second");
  read_states(r, model, c.state, count, name);
  mark_touching(c);
  return c;
}

/// Each (ball, wall) contact: a ball, a wall, and a range of that wall's triangles.
void check_wall_contacts(const WallContacts& c, const ParticleStore& p, const std::vector<FacetWall>& walls) {
  const std::string name = "ball-facet contacts";
  const std::size_t count = c.size();
  check_length(c.wall.size(), count, name + ".wall", "one per contact, as ball");
  check_length(c.triangle_begin.size(), count, name + ".triangle_begin", "one per contact");
  check_length(c.triangle_end.size(), count, name + ".triangle_end", "one per contact");
  check_index(c.ball, p.size(), name + ".ball", "the particle count");
  check_index(c.wall, walls.size(), name + ".wall", "the wall count");
  for (std::size_t k = 0; k < count; ++k) {
    if (p.is_pebble(static_cast<std::size_t>(c.ball[k]))) refuse(at(name + ".ball", k), c.ball[k], "a ball (not a pebble)");
    const std::int32_t begin = c.triangle_begin[k], end = c.triangle_end[k];
    if (begin < 0 || begin > end || static_cast<std::size_t>(end) > c.triangles.size())
      refuse(at(name + ".triangle_begin/end", k), std::to_string(begin) + "/" + std::to_string(end),
             "a range within [0, " + std::to_string(c.triangles.size()) + "] (the triangles list)");
    const std::size_t triangles = walls[static_cast<std::size_t>(c.wall[k])].mesh.triangles.size();
    for (std::int32_t t = begin; t < end; ++t) {
      const std::int32_t tri = c.triangles[static_cast<std::size_t>(t)];
      if (tri < 0 || static_cast<std::size_t>(tri) >= triangles)
        refuse(at(name + ".triangles", static_cast<std::size_t>(t)), tri,
               "in [0, " + std::to_string(triangles) + ") (the triangle count of wall " + std::to_string(c.wall[k]) + ")");
    }
  }
}

WallContacts read_wall_contacts(Reader& r, const ContactModel* model, const ParticleStore& p,
                                const std::vector<FacetWall>& walls) {
  const std::string name = "ball-facet contacts";
  WallContacts c;
  c.ball = r.vec<std::int32_t>(name + ".ball"), c.wall = r.vec<std::int32_t>(name + ".wall");
  c.triangle_begin = r.vec<std::int32_t>(name + ".triangle_begin");
  c.triangle_end = r.vec<std::int32_t>(name + ".triangle_end");
  c.triangles = r.vec<std::int32_t>(name + ".triangles");
  c.force = r.vec<Vec3>(name + ".force"), c.torque_ball = r.vec<Vec3>(name + ".torque_ball");
  c.point = r.vec<Vec3>(name + ".point"), c.moment = r.vec<Vec3>(name + ".moment");
  c.normal_force = r.vec<double>(name + ".normal_force"), c.normal_stiffness = r.vec<double>(name + ".normal_stiffness");
  check_wall_contacts(c, p, walls);
  const std::size_t count = c.size();
  check_length(c.normal_force.size(), count, name + ".normal_force", "one per contact");
  fill_results(c.normal_force, count, name + ".normal_force");
  fill_results(c.force, count, name + ".force"), fill_results(c.torque_ball, count, name + ".torque_ball");
  fill_results(c.point, count, name + ".point"), fill_results(c.moment, count, name + ".moment");
  fill_results(c.normal_stiffness, count, name + ".normal_stiffness");
  read_states(r, model, c.state, count, name);
  return c;
}

/// The per-particle incidence lists (CSR) that World::rebuild builds from a contact list.
std::pair<std::vector<std::int32_t>, std::vector<std::int32_t>> incidence(const PairContacts& c, std::size_t particles) {
  std::vector<std::int32_t> offsets(particles + 1, 0), entries(2 * c.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    ++offsets[static_cast<std::size_t>(c.first[k]) + 1];
    ++offsets[static_cast<std::size_t>(c.second[k]) + 1];
  }
  for (std::size_t i = 0; i < particles; ++i) offsets[i + 1] += offsets[i];
  std::vector<std::int32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::size_t k = 0; k < c.size(); ++k) {
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.first[k])]++)] = static_cast<std::int32_t>(2 * k);
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.second[k])]++)] = static_cast<std::int32_t>(2 * k + 1);
  }
  return {std::move(offsets), std::move(entries)};
}

/// Without a pending rebuild the next step uses the incidence lists as they are: they must be
/// exactly those of the contact list, or the force gather reads outside its arrays.
void check_incidence(const PairContacts& c, std::size_t particles, const std::vector<std::int32_t>& offsets,
                     const std::vector<std::int32_t>& entries, const std::string& name) {
  const auto expected = incidence(c, particles);
  if (offsets != expected.first || entries != expected.second)
    refuse(name + " incidence lists", std::to_string(offsets.size()) + " offsets, " + std::to_string(entries.size()) + " entries",
           "those of the contact list (" + std::to_string(particles + 1) + " offsets, " +
               std::to_string(expected.second.size()) + " entries) while need_rebuild = 0");
}

}  // namespace

void World::save_state(std::ostream& out) const {
  Writer w{out};
  for (const auto& m : models_) w.text(m ? m->law_name() : "");
  w.pod(time_);
  w.pod(steps_);
  w.pod(dt_);
  // Every setting that shapes the trajectory (threads do not: results are thread-count independent).
  w.pod(settings_.time_step), w.pod(settings_.time_step_safety), w.pod(settings_.local_damping);
  w.vec3(settings_.gravity);
  w.pod(settings_.skin), w.pod(settings_.sort_every), w.pod(settings_.max_overlap_ratio);
  w.pod(settings_.max_step_travel_ratio), w.pod(settings_.pebble_pebble_contacts);
  const ParticleStore& p = particles_;
  w.vec(p.x), w.vec(p.v), w.vec(p.w), w.vec(p.f), w.vec(p.t);
  w.vec(p.radius), w.vec(p.mass), w.vec(p.inv_mass), w.vec(p.inv_inertia);
  w.vec(p.id), w.vec(p.group), w.vec(p.clump), w.vec(p.fixed);
  w.pod<std::uint64_t>(clumps_.size());
  for (const Clump& c : clumps_) {
    w.pod(c.mass);
    w.vec3(c.x), w.vec3(c.v), w.vec3(c.w);
    w.pod(c.orientation.w()), w.pod(c.orientation.x()), w.pod(c.orientation.y()), w.pod(c.orientation.z());
    for (int i = 0; i < 9; ++i) w.pod(c.inertia_body.data()[i]);
    w.pod(c.fixed);
    w.vec(c.pebbles);
    w.vec(c.pebble_offsets);
    w.vec3(c.force), w.vec3(c.torque), w.vec3(c.applied_force), w.vec3(c.applied_torque), w.vec3(c.displacement);
  }
  w.pod<std::uint64_t>(walls_.size());
  for (const FacetWall& wall : walls_) {
    w.text(wall.name);
    w.vec(wall.mesh.vertices);
    w.vec(wall.mesh.triangles);
    w.vec3(wall.velocity), w.vec3(wall.displacement), w.vec3(wall.reference_point), w.vec3(wall.outward_normal);
    w.pod(wall.area);
    w.vec3(wall.force), w.vec3(wall.moment);
    w.pod(wall.contact_count), w.pod(wall.stiffness_sum);
  }
  write_pairs(w, ball_ball_);
  write_pairs(w, ball_pebble_);
  const WallContacts& c = wall_contacts_;
  w.vec(c.ball), w.vec(c.wall), w.vec(c.triangle_begin), w.vec(c.triangle_end), w.vec(c.triangles);
  w.vec(c.force), w.vec(c.torque_ball), w.vec(c.point), w.vec(c.moment), w.vec(c.normal_force), w.vec(c.normal_stiffness);
  write_states(w, c.state);
  w.vec(bb_offsets_), w.vec(bb_entries_), w.vec(bp_offsets_), w.vec(bp_entries_);
  w.vec(x_at_rebuild_), w.vec(wall_disp_at_rebuild_);
  w.pod(need_rebuild_), w.pod(rebuilds_), w.pod(max_travel_sq_), w.pod(max_wall_travel_), w.pod(skin_);
  if (!out) throw std::runtime_error("checkpoint: writing the world state failed");
}

void World::load_state(std::istream& in) {
  const std::uint64_t size = bytes_left(in);
  if (size == unknown_size) {
    // Counts are bounded by the bytes that remain, so a stream that cannot tell its size is
    // read into memory first.
    std::ostringstream copy;
    copy << in.rdbuf();
    std::istringstream whole(copy.str());
    load_state(whole);
    return;
  }
  Reader r{in, size};
  for (int k = 0; k < contact_kind_count; ++k) {
    const auto kind = static_cast<ContactKind>(k);
    const std::string saved = r.text(std::string(to_string(kind)) + " law");
    const std::string now = models_[static_cast<std::size_t>(k)] ? models_[static_cast<std::size_t>(k)]->law_name() : "";
    if (saved != now)
      throw InputError(std::string("checkpoint: ") + to_string(kind) + " law = '" + saved + "' in the file but '" + now +
                       "' is set: must be the same law");
  }
  // Everything is read into locals and checked; the World changes only once all of it is valid.
  const double time = r.number("time");
  if (time < 0.0) refuse("time", time, ">= 0 s");
  const std::int64_t steps = r.counter("steps");
  const double dt = r.number("dt");
  if (dt < 0.0) refuse("dt", dt, ">= 0 s (0: not yet estimated)");
  const WorldSettings settings = read_settings(r, settings_);
  ParticleStore p = read_particles(r);
  std::vector<Clump> clumps = read_clumps(r, p);
  std::vector<FacetWall> walls = read_walls(r);
  const bool pebble_pebble = settings.pebble_pebble_contacts;
  PairContacts bb = read_pairs(r, contact_model(ContactKind::BallBall), ContactKind::BallBall, p, pebble_pebble);
  PairContacts bp = read_pairs(r, contact_model(ContactKind::BallPebble), ContactKind::BallPebble, p, pebble_pebble);
  WallContacts wc = read_wall_contacts(r, contact_model(ContactKind::BallFacet), p, walls);
  auto bb_offsets = r.vec<std::int32_t>("ball-ball incidence offsets");
  auto bb_entries = r.vec<std::int32_t>("ball-ball incidence entries");
  auto bp_offsets = r.vec<std::int32_t>("ball-pebble incidence offsets");
  auto bp_entries = r.vec<std::int32_t>("ball-pebble incidence entries");
  auto x_at_rebuild = r.vec<Vec3>("x_at_rebuild");
  auto wall_disp_at_rebuild = r.vec<Vec3>("wall_disp_at_rebuild");
  const bool need_rebuild = r.flag("need_rebuild");
  const std::int64_t rebuilds = r.counter("rebuilds");
  const double max_travel_sq = r.number("max_travel_sq");
  if (max_travel_sq < 0.0) refuse("max_travel_sq", max_travel_sq, ">= 0 m^2");
  const double max_wall_travel = r.number("max_wall_travel");
  if (max_wall_travel < 0.0) refuse("max_wall_travel", max_wall_travel, ">= 0 m");
  const double skin = r.number("skin");
  if (skin < 0.0) refuse("skin", skin, ">= 0 m");
  // A pending rebuild replaces the lists below before anything reads them (a state saved after
  // adding particles or walls has stale ones); otherwise the next step trusts them as they are.
  if (!need_rebuild) {
    check_incidence(bb, p.size(), bb_offsets, bb_entries, "ball-ball");
    check_incidence(bp, p.size(), bp_offsets, bp_entries, "ball-pebble");
    check_length(x_at_rebuild.size(), p.size(), "x_at_rebuild", "one per particle while need_rebuild = 0");
    check_length(wall_disp_at_rebuild.size(), walls.size(), "wall_disp_at_rebuild", "one per wall while need_rebuild = 0");
  }
  check_finite(x_at_rebuild, "x_at_rebuild");
  check_finite(wall_disp_at_rebuild, "wall_disp_at_rebuild");

  time_ = time, steps_ = steps, dt_ = dt;
  settings_ = settings;
  particles_ = std::move(p);
  clumps_ = std::move(clumps);
  walls_ = std::move(walls);
  ball_ball_ = std::move(bb);
  ball_pebble_ = std::move(bp);
  wall_contacts_ = std::move(wc);
  bb_offsets_ = std::move(bb_offsets), bb_entries_ = std::move(bb_entries);
  bp_offsets_ = std::move(bp_offsets), bp_entries_ = std::move(bp_entries);
  x_at_rebuild_ = std::move(x_at_rebuild), wall_disp_at_rebuild_ = std::move(wall_disp_at_rebuild);
  need_rebuild_ = need_rebuild, rebuilds_ = rebuilds;
  max_travel_sq_ = max_travel_sq, max_wall_travel_ = max_wall_travel, skin_ = skin;
  gather_plan_stale_ = true;  // the loaded contact lists are not those the plan was made for
  near_stale_ = true;
  // The file's time step belongs to the stiffness it was written with. Contact models that are
  // stiffer (another E*) need a shorter one; the same models keep the file's (the estimate moves by
  // far less than the margin between rebuilds), so a resumed run stays the same run.
  if (settings_.time_step <= 0.0 && dt_ > 0.0 && dt_ > 1.1 * settings_.time_step_safety * critical_time_step())
    update_time_step();
}

}  // namespace dem
