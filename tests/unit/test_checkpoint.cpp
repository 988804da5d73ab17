// Restart files: a run resumed from a checkpoint continues bit for bit; damaged files are refused.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include <dem/io/checkpoint.hpp>
#include <dem/io/world_state.hpp>

#include "fuzz/checkpoint_world.hpp"
#include "support/scenes.hpp"
#include "support/temp_dir.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

void set_models(World& world) {
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
}

World falling_pile() {
  WorldSettings s;
  s.gravity = Vec3(0, 0, -2000.0);
  s.sort_every = 3;  // re-sorting in the run must not break resuming
  World world(s);
  for (auto b : separated_balls(200, 4e-3, 0.25e-3, 0.4e-3, 8)) {
    b.position.z() += 0.5e-3;
    world.add_ball(b);
  }
  world.add_wall(floor_wall(0.0, 0.01));
  set_models(world);
  return world;
}

/// A compressed lattice of spinning balls with random sizes on a floor, springing apart: over
/// min_parallel_items pair candidates, so that two threads take the gathered paths.
World springing_lattice(int threads) {
  WorldSettings s;
  s.threads = threads;
  s.adapt_threads = false;  // the deferred parts counted below are those of a two-thread step
  s.gravity = Vec3(0, 0, -9.81);
  World world(s);
  for (const BallSpec& b : spinning_lattice(12, 5)) world.add_ball(b);
  world.add_wall(floor_wall(-0.28e-3, 0.02));  // the bottom layer touches it
  set_models(world);
  return world;
}

/// A file in this test process's own folder: CTest runs the test cases side by side, and several
/// write and remove files of the same name (a shared folder made one case read "cannot be
/// opened" after another removed its file).
fs::path temp_file(const std::string& name) {
  static const dem::testing::TempDir folder("checkpoint");
  return folder.path / name;
}

std::string state_of(const World& world) {
  std::ostringstream out(std::ios::binary);
  io::write_world_state(out, world);
  return out.str();
}

/// Where two saved states first differ ("same" if they do not): readable where bytes are not.
std::string first_difference(const std::string& a, const std::string& b) {
  const auto [at_a, at_b] = std::mismatch(a.begin(), a.end(), b.begin(), b.end());
  if (at_a == a.end() && at_b == b.end()) return "same";
  return "byte " + std::to_string(at_a - a.begin()) + " of " + std::to_string(a.size()) + " and " +
         std::to_string(b.size());
}

/// The parts of particles' sums the last step's threads left for afterwards: the later shares'
/// shared particles, and the chunks a thread took from another's share (which may be all of a
/// share whose thread got no core).
std::size_t deferred_sums(const World& world) {
  std::size_t count = 0;
  const PairPlan& plan = world.pair_plan(ContactKind::BallBall);
  for (const auto& later : plan.deferred) count += later.size();
  for (const auto& later : plan.taken) count += later.size();
  return count;
}

}  // namespace

TEST_CASE("checkpoint: a resumed run equals the uninterrupted one bit for bit", "[checkpoint]") {
  World world = falling_pile();
  world.step(3000);
  const fs::path file = temp_file("resume.ckpt");
  io::save_checkpoint(file, world, "stage=consolidation");
  world.step(2000);

  World resumed(WorldSettings{});
  set_models(resumed);
  CHECK(io::load_checkpoint(file, resumed) == "stage=consolidation");
  resumed.step(2000);
  REQUIRE(resumed.particles().size() == world.particles().size());
  CHECK(resumed.step_count() == world.step_count());
  CHECK(resumed.time() == world.time());
  CHECK(resumed.particles().x == world.particles().x);  // exact equality of every coordinate
  CHECK(resumed.particles().w == world.particles().w);
  CHECK(world.contact_count(ContactKind::BallBall) > 50);
  fs::remove(file);
}

TEST_CASE("checkpoint: a loaded state saves the same bytes, and a resumed run ends in the same state",
          "[checkpoint]") {
  // The whole state, not only positions: a restart file of the resumed run must equal the
  // uninterrupted run's, whether or not a rebuild came between. Scratch that the loops keep
  // between steps (the threads' deferred sums, which depend on when the threads' work was last
  // planned) must not reach the file, nor be sized by the load.
  const int threads = GENERATE(1, 2);
  CAPTURE(threads);
  World world = springing_lattice(threads);
  world.step(300);
  REQUIRE(world.pair_contacts(ContactKind::BallBall).size() > static_cast<std::size_t>(min_parallel_items));
  CHECK((deferred_sums(world) > 0) == (threads == 2));  // shared particles or not
  const std::string saved = state_of(world);
  World resumed(WorldSettings{.threads = threads});
  set_models(resumed);
  std::istringstream in(saved, std::ios::binary);
  io::read_world_state(in, resumed);
  CHECK(first_difference(state_of(resumed), saved) == "same");
  const std::int64_t rebuilds = world.rebuild_count();
  world.step(3), resumed.step(3);
  CHECK(world.rebuild_count() == rebuilds);  // the lazily sized records survive these steps
  CHECK(first_difference(state_of(resumed), state_of(world)) == "same");
  world.step(300), resumed.step(300);
  CHECK(world.rebuild_count() > rebuilds);
  CHECK(first_difference(state_of(resumed), state_of(world)) == "same");
}

TEST_CASE("checkpoint: the saved state does not depend on the thread count", "[checkpoint]") {
  // Results do not depend on the threads; neither may a restart file, or a run resumed on
  // another thread count would write a different one. The two-thread run really defers sums.
  World one = springing_lattice(1), two = springing_lattice(2);
  one.step(300), two.step(300);
  REQUIRE(deferred_sums(two) > 0);
  CHECK(first_difference(state_of(one), state_of(two)) == "same");
}

TEST_CASE("checkpoint: truncated, corrupted and mismatched files are refused clearly", "[checkpoint]") {
  World world = falling_pile();
  world.step(200);
  const fs::path file = temp_file("damaged.ckpt");
  io::save_checkpoint(file, world, "");
  const auto size = fs::file_size(file);

  World target(WorldSettings{});
  set_models(target);
  fs::resize_file(file, size - 100);
  CHECK_THROWS_WITH(io::load_checkpoint(file, target), Contains("truncated") && Contains(file.string()));

  io::save_checkpoint(file, world, "");
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
  }
  CHECK_THROWS_WITH(io::load_checkpoint(file, target), Contains("checksum"));

  io::save_checkpoint(file, world, "");
  World other_law(WorldSettings{});
  other_law.set_contact_model(ContactKind::BallBall,
                              make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1, 0.5), "ball-ball"));
  CHECK_THROWS_WITH(io::load_checkpoint(file, other_law), Contains("ball-ball law") && Contains("rolling-linear"));
  CHECK_THROWS_WITH(io::load_checkpoint(temp_file("missing.ckpt"), target), Contains("does not exist"));
  fs::remove(file);
}

// --- files from a buggy or foreign writer ---------------------------------------------------------
// The checksum only stops random damage: these files carry a valid frame and checksum around a
// world state with one field wrong, and each must be refused with an InputError naming the field.

namespace {

void set_all_models(World& world) {
  const auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble})
    world.set_contact_model(kind, make_contact_model<RollingLinearLaw>(p, to_string(kind)));
}

/// Three balls on a floor, a fixed two-pebble clump and a ball resting on it, after a few steps:
/// every part of the state (ball-ball, ball-facet and ball-pebble contacts, a clump, a wall) is
/// present. Built afresh for each altered file.
World small_scene(bool pebble_pebble = false) {
  WorldSettings s;
  s.gravity = Vec3(0, 0, -9.81);
  s.pebble_pebble_contacts = pebble_pebble;
  World world(s);
  world.add_wall(floor_wall(0.0, 0.01));
  world.add_ball({.position = {0, 0, 0.49e-3}, .radius = 0.5e-3, .density = 2650.0});
  world.add_ball({.position = {0, 0, 1.48e-3}, .radius = 0.5e-3, .density = 2650.0});
  world.add_ball({.position = {0.99e-3, 0, 0.49e-3}, .radius = 0.5e-3, .density = 2650.0});
  ClumpSpec clump;
  clump.pebbles = {{Vec3(4e-3, 0, 1e-3), 0.4e-3}, {Vec3(4.6e-3, 0, 1e-3), 0.4e-3}};
  clump.with_pebble_mass(2650.0);
  clump.fixed = dof_all;
  world.add_clump(clump);
  world.add_ball({.position = {4e-3, 0, 1.79e-3}, .radius = 0.4e-3, .density = 2650.0});
  set_all_models(world);
  world.step(20);
  return world;
}

/// The payload of a restart file: an empty protocol state, then the world state.
std::string payload_of(const World& world) {
  std::ostringstream state(std::ios::binary);
  io::write_world_state(state, world);
  std::string payload;
  fuzz::append_raw(payload, std::uint64_t{0});
  return payload + state.str();
}

/// Loads a payload framed with a valid checksum into a World with the same laws; returns the
/// InputError message, or "accepted".
std::string refusal(const std::string& payload) {
  const fs::path file = temp_file("altered.ckpt");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    const std::string bytes = fuzz::frame_checkpoint(payload);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  World target{WorldSettings{}};
  set_all_models(target);
  try {
    io::load_checkpoint(file, target);
  } catch (const InputError& e) {
    fs::remove(file);
    return e.what();
  }
  fs::remove(file);
  return "accepted";
}

std::string refusal(const World& world) { return refusal(payload_of(world)); }

// Byte offsets in the payload of small_scene(), from the format in io::write_world_state.
constexpr std::size_t state_start = 8 + 3 * (8 + 14);  // protocol size, three "rolling-linear" law names
constexpr std::size_t pebble_pebble_at = state_start + 3 * 8 + 3 * 8 + 24 + 8 + 4 + 2 * 8;
std::size_t particle_id_count_at(std::size_t n) { return pebble_pebble_at + 1 + 5 * (8 + 24 * n) + 4 * (8 + 8 * n); }
std::size_t clump_count_at(std::size_t n) { return particle_id_count_at(n) + 3 * (8 + 4 * n) + (8 + n); }

/// Bytes after the rebuild record (format 2): per wall its surface (shape byte, point, axis,
/// radius), then an empty ball-surface contact list (eleven array counts, State size and count);
/// then (format 3) the periodic cell's flag, 0 here; then (format 4) no bonds (thirteen array counts).
std::size_t surface_section_bytes(const World& world) { return world.walls().size() * 57 + 13 * 8 + 1 + 13 * 8; }

template <class T>
T read_at(const std::string& bytes, std::size_t at) {
  T v{};
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

template <class T>
std::string written_at(std::string bytes, std::size_t at, const T& v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
  return bytes;
}

// Test access to the World's contact lists, as a buggy writer would have left them.
PairContacts& pairs(World& world, ContactKind kind) { return const_cast<PairContacts&>(world.pair_contacts(kind)); }
WallContacts& wall_pairs(World& world) { return const_cast<WallContacts&>(world.wall_contacts()); }

}  // namespace

TEST_CASE("checkpoint: the altered-file scene is complete and loads as saved", "[checkpoint]") {
  World world = small_scene();
  CHECK(world.pair_contacts(ContactKind::BallBall).size() > 0);
  CHECK(world.pair_contacts(ContactKind::BallPebble).size() > 0);
  CHECK(world.wall_contacts().size() > 0);
  const std::string payload = payload_of(world);
  CHECK(read_at<std::uint8_t>(payload, pebble_pebble_at) == 0);
  CHECK(read_at<std::uint64_t>(payload, particle_id_count_at(6)) == 6);
  CHECK(read_at<std::uint64_t>(payload, clump_count_at(6)) == 1);
  CHECK(refusal(payload) == "accepted");
}

TEST_CASE("checkpoint: unset per-contact results, as real runs leave them, are accepted", "[checkpoint]") {
  // compute_walls leaves the contact point of a non-touching ball-facet contact unset: any bits.
  World world = small_scene();
  auto& walls = wall_pairs(world);
  walls.point.back() = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  CHECK(refusal(world) == "accepted");
}

TEST_CASE("checkpoint: bool fields other than 0 or 1 are refused", "[checkpoint]") {
  const World world = small_scene();
  const std::string payload = payload_of(world);
  CHECK_THAT(refusal(written_at(payload, pebble_pebble_at, std::uint8_t{2})),
             Contains("checkpoint: settings.pebble_pebble_contacts = 2") && Contains("0 or 1"));
  // need_rebuild is followed by rebuilds, max_travel_sq, max_wall_travel and skin (8 bytes each).
  const std::size_t need_rebuild_at = payload.size() - surface_section_bytes(world) - 33;
  CHECK_THAT(refusal(written_at(payload, need_rebuild_at, std::uint8_t{7})),
             Contains("checkpoint: need_rebuild = 7") && Contains("0 or 1"));
}

TEST_CASE("checkpoint: counts larger than the bytes left are refused before allocating", "[checkpoint]") {
  const std::string payload = payload_of(small_scene());
  const std::string ids = refusal(written_at(payload, particle_id_count_at(6), std::uint64_t{1} << 30));
  CHECK_THAT(ids, Contains("checkpoint: particles.id count = 1073741824") && Contains("bytes remain"));
  const std::string clumps = refusal(written_at(payload, clump_count_at(6), std::uint64_t{1} << 24));
  CHECK_THAT(clumps, Contains("checkpoint: clumps count = 16777216") && Contains("bytes remain"));
  CHECK_THAT(refusal(payload + "xy"), Contains("2 bytes after the world state"));
}

TEST_CASE("checkpoint: particle arrays of another length and bad ids are refused", "[checkpoint]") {
  World empty_forces = small_scene();
  empty_forces.particles().f.clear();
  CHECK_THAT(refusal(empty_forces), Contains("checkpoint: particles.f count = 0") && Contains("must be 6"));

  World twice = small_scene();
  twice.particles().id[1] = twice.particles().id[0];
  CHECK_THAT(refusal(twice), Contains("checkpoint: particles.id[1]") && Contains("unique"));

  World negative_radius = small_scene();
  negative_radius.particles().radius[2] = -1.0;
  CHECK_THAT(refusal(negative_radius), Contains("checkpoint: particles.radius[2] = -1") && Contains("(0, 1e100] m"));

  World nan_position = small_scene();
  nan_position.particles().x[0].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THAT(refusal(nan_position), Contains("checkpoint: particles.x[0]") && Contains("finite"));
}

TEST_CASE("checkpoint: clump membership must match both ways", "[checkpoint]") {
  World outside = small_scene();
  outside.clumps()[0].pebbles[0] = 1000;
  CHECK_THAT(refusal(outside), Contains("checkpoint: clumps[0].pebbles[0] = 1000") && Contains("[0, 6)"));

  World ball_as_pebble = small_scene();
  ball_as_pebble.clumps()[0].pebbles[0] = 0;  // id 0 is a free ball
  CHECK_THAT(refusal(ball_as_pebble), Contains("checkpoint: clumps[0].pebbles[0] = 0") && Contains("a pebble of this clump"));

  World bad_owner = small_scene();
  bad_owner.particles().clump[0] = 5;
  CHECK_THAT(refusal(bad_owner), Contains("checkpoint: particles.clump[0] = 5") && Contains("the clump count"));

  World no_offsets = small_scene();
  no_offsets.clumps()[0].pebble_offsets.pop_back();
  CHECK_THAT(refusal(no_offsets), Contains("checkpoint: clumps[0].pebble_offsets count = 1") && Contains("one per pebble"));
}

TEST_CASE("checkpoint: wall meshes and wall contacts must index inside their arrays", "[checkpoint]") {
  World vertex = small_scene();
  vertex.wall(0).mesh.triangles[0][1] = 100000000;
  CHECK_THAT(refusal(vertex), Contains("checkpoint: walls[0].mesh.triangles[0] vertex 1 = 100000000") &&
                                  Contains("vertex count"));

  World wall_index = small_scene();
  wall_pairs(wall_index).wall[0] = 3;
  CHECK_THAT(refusal(wall_index), Contains("checkpoint: ball-facet contacts.wall[0] = 3") && Contains("the wall count"));

  World triangle = small_scene();
  wall_pairs(triangle).triangles[0] = 99;
  CHECK_THAT(refusal(triangle), Contains("checkpoint: ball-facet contacts.triangles[0] = 99") && Contains("triangle count"));
}

TEST_CASE("checkpoint: contact endpoints, results, history and incidence lists are checked", "[checkpoint]") {
  World endpoint = small_scene();
  pairs(endpoint, ContactKind::BallBall).second[0] = 1000;
  CHECK_THAT(refusal(endpoint), Contains("checkpoint: ball-ball contacts.second[0] = 1000") && Contains("particle count"));

  World pebble_side = small_scene();
  pairs(pebble_side, ContactKind::BallPebble).second[0] = 0;  // a free ball where a pebble belongs
  CHECK_THAT(refusal(pebble_side), Contains("checkpoint: ball-pebble contacts.first/second[0]") && Contains("a pebble"));

  World results = small_scene();
  auto& bb = pairs(results, ContactKind::BallBall);
  bb.force.resize(bb.size() + 1);
  CHECK_THAT(refusal(results), Contains("checkpoint: ball-ball contacts.force count") && Contains("one per contact"));

  World history = small_scene();
  ++pairs(history, ContactKind::BallBall).state.count;
  CHECK_THAT(refusal(history), Contains("checkpoint: ball-ball contacts.state count") && Contains("one per contact"));

  World swapped = small_scene();
  auto& c = pairs(swapped, ContactKind::BallBall);
  std::swap(c.first[0], c.second[0]);  // still two valid balls, but the incidence lists no longer match
  CHECK_THAT(refusal(swapped), Contains("checkpoint: ball-ball incidence lists") && Contains("need_rebuild = 0"));
}

TEST_CASE("checkpoint: a refused file leaves the World as it was, and an unstepped World loads", "[checkpoint]") {
  World broken = small_scene();
  broken.particles().f.clear();
  const fs::path file = temp_file("refused.ckpt");
  io::save_checkpoint(file, broken, "");
  World target = small_scene();
  const auto before = target.particles().x;
  CHECK_THROWS_AS(io::load_checkpoint(file, target), InputError);
  CHECK(target.particles().x == before);
  CHECK(target.step_count() == 20);

  // Saved before its first step: the neighbour lists are still empty and a rebuild is pending.
  World fresh{WorldSettings{}};
  fresh.add_ball({.position = {0, 0, 1e-3}, .radius = 0.5e-3, .density = 2650.0});
  set_all_models(fresh);
  io::save_checkpoint(file, fresh, "");
  World resumed{WorldSettings{}};
  set_all_models(resumed);
  CHECK_NOTHROW(io::load_checkpoint(file, resumed));
  CHECK_NOTHROW(resumed.step(2));
  fs::remove(file);
}

TEST_CASE("checkpoint: step and rebuild counters outside [0, 1e15] are refused", "[checkpoint]") {
  // INT64_MAX rebuilds was accepted and overflowed at the next rebuild (UBSan).
  const World world = small_scene();
  const std::string payload = payload_of(world);
  constexpr std::int64_t huge = std::numeric_limits<std::int64_t>::max();
  constexpr std::size_t steps_at = state_start + 8;  // after the time
  // rebuilds is followed by max_travel_sq, max_wall_travel and skin (8 bytes each).
  const std::size_t rebuilds_at = payload.size() - surface_section_bytes(world) - 32;
  REQUIRE(read_at<std::int64_t>(payload, steps_at) == world.step_count());
  REQUIRE(read_at<std::int64_t>(payload, rebuilds_at) == world.rebuild_count());
  CHECK_THAT(refusal(written_at(payload, rebuilds_at, huge)),
             Contains("checkpoint: rebuilds = 9223372036854775807") && Contains("in [0, 1000000000000000]"));
  CHECK_THAT(refusal(written_at(payload, rebuilds_at, std::int64_t{-1})), Contains("checkpoint: rebuilds = -1"));
  CHECK_THAT(refusal(written_at(payload, steps_at, huge)),
             Contains("checkpoint: steps = 9223372036854775807") && Contains("in [0, 1000000000000000]"));
  CHECK_THAT(refusal(written_at(payload, state_start, -1.0)), Contains("checkpoint: time = -1") && Contains(">= 0 s"));
  CHECK(refusal(written_at(payload, rebuilds_at, std::int64_t{1'000'000'000'000'000})) == "accepted");
}

TEST_CASE("checkpoint: bytes after the end are too long and a short file is truncated", "[checkpoint]") {
  const World world = small_scene();
  const fs::path file = temp_file("length.ckpt");
  World target{WorldSettings{}};
  set_all_models(target);
  io::save_checkpoint(file, world, "");
  const auto size = fs::file_size(file);
  std::ofstream(file, std::ios::binary | std::ios::app) << "abc";
  const std::string appended = [&] {
    try {
      io::load_checkpoint(file, target);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  }();
  CHECK_THAT(appended, Contains(file.string()) && Contains("too long") && Contains("3 bytes past the end") &&
                           !Contains("truncated"));

  for (const std::uintmax_t keep : {std::uintmax_t{12}, size - 1}) {
    io::save_checkpoint(file, world, "");
    fs::resize_file(file, keep);
    CHECK_THROWS_WITH(io::load_checkpoint(file, target), Contains("truncated") && !Contains("too long"));
  }
  // A payload size near 2^64 in the header.
  io::save_checkpoint(file, world, "");
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(12);  // after the magic and the format version
    const std::uint64_t huge = std::numeric_limits<std::uint64_t>::max() - 7;
    f.write(reinterpret_cast<const char*>(&huge), sizeof huge);
  }
  CHECK_THROWS_WITH(io::load_checkpoint(file, target),
                    Contains("truncated") && Contains("payload of 18446744073709551608 bytes"));
  fs::remove(file);
}
