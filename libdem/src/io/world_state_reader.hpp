// The reading side of io::read_world_state: a bounded reader of the binary state and the readers
// and checks of each part (settings, particles, clumps, walls, contacts). Private to libdem/src/io.
#pragma once

#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <dem/base/errors.hpp>
#include <dem/core/contact_model.hpp>
#include <dem/core/world_state.hpp>

namespace dem::checkpoint {

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

inline std::string at(const std::string& field, std::size_t k) { return field + "[" + std::to_string(k) + "]"; }

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
std::uint64_t bytes_left(std::istream& in);
void check_finite(const std::vector<Vec3>& v, const std::string& field);
void check_length(std::size_t size, std::size_t expected, const std::string& field, const std::string& why);
WorldSettings read_settings(Reader& r, WorldSettings s);
ParticleStore read_particles(Reader& r);
std::vector<Clump> read_clumps(Reader& r, const ParticleStore& p);
std::vector<Wall> read_walls(Reader& r);
PairContacts read_pairs(Reader& r, const ContactModel* model, ContactKind kind, const ParticleStore& p, bool pebble_pebble);
/// The walls' analytic surfaces (format 2), one per wall in order.
void read_surfaces(Reader& r, std::vector<Wall>& walls);
/// Ball-wall contacts: with facets, or with the walls' analytic surfaces (`surfaces`).
WallContacts read_wall_contacts(Reader& r, const ContactModel* model, const ParticleStore& p, const std::vector<Wall>& walls,
                                bool surfaces);
/// The bonds (format 4), checked against the particles `p` (world_state_bonds.cpp).
BondStore read_bonds(Reader& r, const ParticleStore& p);
/// Refuses incidence lists that are not those of the contact list `c`.
void check_incidence(const PairContacts& c, std::size_t particles, const std::vector<std::int32_t>& offsets,
                     const std::vector<std::int32_t>& entries, const std::string& name);

}  // namespace dem::checkpoint
