// A World spread over processes (World::spread_over) is the serial World bit for bit: the same
// trajectories, wall and clump motion, contact lists and contact history, for 1, 2 and 3
// processes (threads of this program standing in for MPI ranks: tests/support/thread_domains.hpp;
// the MPI ranks themselves: tests/ctest/mpi.cmake). The serial engine is the reference, checked
// against analytic results by the physics tests.
#include <catch2/catch.hpp>

#include <cstring>
#include <mutex>

#include <dem/dem.hpp>

#include "support/scenes.hpp"
#include "support/thread_domains.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double cell_radius = 4e-3;  // m
constexpr double cell_height = 5e-3;  // m

/// A small simple-shear cell: a compressed lattice of balls (neighbours overlap, so it springs
/// apart: contacts from the first step) in a ring stack on a facet floor, under a
/// servo-controlled facet plate (or, `servo` false, a plate moving down at 10 mm/s), with gravity
/// and local damping; re-sorted at every rebuild, so that particles change storage index and
/// subdomain again and again.
void build_cell(World& world, bool servo) {
  for (const BallSpec& b : spinning_lattice(14, 17)) {
    BallSpec ball = b;
    ball.position += Vec3(-6.5 * 0.62e-3, -6.5 * 0.62e-3, 0.28e-3);
    if (ball.position.head<2>().norm() < cell_radius - 0.35e-3 && ball.position.z() < cell_height) world.add_ball(ball);
  }
  RingStackSpec rings;
  rings.inner_radius = cell_radius;
  rings.height = cell_height + 0.5e-3;
  rings.ring_height = 0.5e-3;
  rings.pebble_radius = 0.25e-3;
  rings.gap = 0.02e-3;
  for (const ClumpSpec& ring : make_ring_stack(rings)) world.add_clump(ring);
  world.add_wall(make_facet_wall("floor", geometry::make_disc(Vec3::Zero(), cell_radius + 1e-3, -Vec3::UnitZ(), 24), -Vec3::UnitZ()));
  const WallId top = world.add_wall(
      make_facet_wall("top", geometry::make_disc(Vec3(0, 0, 7 * 0.62e-3 + 0.28e-3 * 2), cell_radius + 1e-3, Vec3::UnitZ(), 24), Vec3::UnitZ()));
  const auto law = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble})
    world.set_contact_model(k, make_contact_model<RollingLinearLaw>(law, to_string(k)));
  if (!servo) {
    world.wall(top).velocity = Vec3(0, 0, -0.01);
    return;
  }
  ServoSettings settings;
  settings.target_stress = 2e3;
  settings.max_speed = 0.05;
  add_servo_wall(world, top, settings);
}

WorldSettings cell_settings() {
  WorldSettings s;
  s.gravity = Vec3(0, 0, -9.81);
  s.local_damping = 0.3;
  s.sort_every = 1;
  s.threads = 1;
  return s;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// Everything a restart file holds, compared byte for byte where it is data.
void require_same_state(const WorldState& a, const WorldState& b) {
  REQUIRE(a.clock.steps == b.clock.steps);
  CHECK(a.clock.time == b.clock.time);
  CHECK(same_bytes(a.particles.id, b.particles.id));
  CHECK(same_bytes(a.particles.x, b.particles.x));
  CHECK(same_bytes(a.particles.v, b.particles.v));
  CHECK(same_bytes(a.particles.w, b.particles.w));
  CHECK(same_bytes(a.particles.f, b.particles.f));
  CHECK(same_bytes(a.particles.t, b.particles.t));
  REQUIRE(a.clumps.size() == b.clumps.size());
  for (std::size_t c = 0; c < a.clumps.size(); ++c) {
    CHECK(a.clumps[c].x == b.clumps[c].x);
    CHECK(a.clumps[c].v == b.clumps[c].v);
    CHECK(a.clumps[c].force == b.clumps[c].force);
  }
  for (std::size_t w = 0; w < a.walls.size(); ++w) {
    CHECK(a.walls[w].force == b.walls[w].force);
    CHECK(a.walls[w].displacement == b.walls[w].displacement);
    CHECK(a.walls[w].velocity == b.walls[w].velocity);
  }
  for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallPebble}) {
    const PairContacts& ca = a.contacts.pairs(kind);
    const PairContacts& cb = b.contacts.pairs(kind);
    CHECK(same_bytes(ca.first, cb.first));
    CHECK(same_bytes(ca.second, cb.second));
    CHECK(same_bytes(ca.state.bytes, cb.state.bytes));  // the contact history
    CHECK(same_bytes(ca.force, cb.force));
    CHECK(same_bytes(ca.normal_force, cb.normal_force));
  }
  CHECK(same_bytes(a.contacts.ball_facet.ball, b.contacts.ball_facet.ball));
  CHECK(same_bytes(a.contacts.ball_facet.state.bytes, b.contacts.ball_facet.state.bytes));
  CHECK(same_bytes(a.contacts.ball_facet.force, b.contacts.ball_facet.force));
  CHECK(a.rebuild.rebuilds == b.rebuild.rebuilds);
}

struct SpreadRun {
  WorldState state;                 // rank 0's, after the run
  std::size_t owned_total = 0;      // particles owned over the ranks at the last check
  bool owners_changed = false;      // some subdomain boundary moved between checks
  std::int64_t touching_contacts = 0;
};

/// Runs the cell for `steps` steps on `ranks` processes (threads), from `start` if given (the
/// servo's own state is not in a WorldState: a resumed cell has none).
SpreadRun run_spread(int ranks, std::int64_t steps, const WorldState* start = nullptr) {
  ThreadDomains hub(ranks);
  SpreadRun out;
  std::mutex m;
  hub.run([&](const std::shared_ptr<parallel::DomainComm>& comm) {
    World world(cell_settings());
    build_cell(world, start == nullptr);
    if (start) world.restore(*start);
    world.spread_over(comm);
    std::pair<std::size_t, std::size_t> last{0, 0};
    bool changed = false;
    world.add_callback(25, [&](World& w) {
      if (last.second > 0 && w.owned_range() != last) changed = true;
      last = w.owned_range();
    });
    world.step(steps);
    const WorldState& state = world.state();  // collective: every process asks
    std::lock_guard lock(m);
    out.owned_total += last.second - last.first;
    out.owners_changed = out.owners_changed || changed;
    if (comm->rank() == 0) {
      out.state = state;
      out.touching_contacts = static_cast<std::int64_t>(world.contact_count(ContactKind::BallBall));
    }
  });
  return out;
}

}  // namespace

TEST_CASE("subdomains: 1, 2 and 3 processes give the serial run bit for bit, with history carried through migration",
          "[subdomains][determinism]") {
  constexpr std::int64_t steps = 3000;
  World serial(cell_settings());
  build_cell(serial, true);
  serial.step(steps);
  const std::size_t n = serial.particles().size();
  REQUIRE(serial.clumps().size() > 5);
  REQUIRE(serial.rebuild_count() > 10);  // each a re-sort: storage indices and subdomains move
  REQUIRE(serial.contact_count(ContactKind::BallBall) > 500);
  REQUIRE(serial.contact_count(ContactKind::BallPebble) > 20);

  for (int ranks : {1, 2, 3}) {
    INFO(ranks << " processes");
    const SpreadRun run = run_spread(ranks, steps);
    CHECK(run.owned_total == n);  // each particle owned by exactly one process
    if (ranks > 1) CHECK(run.owners_changed);
    CHECK(run.touching_contacts == static_cast<std::int64_t>(serial.contact_count(ContactKind::BallBall)));
    require_same_state(run.state, serial.state());
  }
}

TEST_CASE("subdomains: a state saved on 2 processes continues on 3 as the serial run", "[subdomains][determinism]") {
  World fresh(cell_settings());
  build_cell(fresh, false);
  const WorldState fresh_cell = fresh.state();
  World serial(cell_settings());
  build_cell(serial, false);
  serial.step(1500);
  const SpreadRun first = run_spread(2, 1000, &fresh_cell);
  const SpreadRun second = run_spread(3, 500, &first.state);
  require_same_state(second.state, serial.state());
}

TEST_CASE("subdomains: a step that leaves only walls whole refuses particle reads until the state is gathered",
          "[subdomains]") {
  World half(cell_settings()), serial(cell_settings());
  build_cell(half, false);
  build_cell(serial, false);
  half.step(100);
  serial.step(200);
  ThreadDomains hub(2);
  std::mutex m;
  std::vector<Vec3> positions;
  int refused = 0, refused_in_controller = 0, walls_ok = 0;
  hub.run([&](const std::shared_ptr<parallel::DomainComm>& comm) {
    World world(cell_settings());
    build_cell(world, false);
    world.spread_over(comm);
    world.step(100, World::StepEnd::WallsAndClumps);
    bool threw = false;
    try {
      (void)world.particles();
    } catch (const std::logic_error&) {
      threw = true;
    }
    const bool walls_whole = world.wall(1).force == half.wall(1).force && world.wall(1).displacement == half.wall(1).displacement;
    world.gather_state();
    world.step(100);
    const std::vector<Vec3> x = world.particles().x;
    // A controller reads particles during a step, where each process holds only its own.
    bool controller_threw = false;
    world.add_controller([&controller_threw](World& w) {
      try {
        (void)w.particles();
      } catch (const std::logic_error&) {
        controller_threw = true;
      }
    });
    world.step(2);
    std::lock_guard lock(m);
    refused += threw;
    refused_in_controller += controller_threw;
    walls_ok += walls_whole;
    if (comm->rank() == 0) positions = x;
  });
  CHECK(refused == 2);
  CHECK(walls_ok == 2);  // walls and clumps are whole on every process
  CHECK(refused_in_controller == 2);
  CHECK(positions == serial.particles().x);
}
