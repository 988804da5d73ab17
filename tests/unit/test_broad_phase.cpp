// The neighbour search finds exactly the pairs a brute-force O(N^2) search finds, and the
// contact history survives neighbour-list rebuilds and re-sorting of the particles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <set>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

TEST_CASE("broad phase: cell-grid pairs equal brute-force pairs for random polydisperse sets", "[grid]") {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const double skin = 0.05e-3 * seed;
    const auto balls = random_balls(400 + 50 * seed, 0.01, 0.1e-3, 0.2e-3 + 0.1e-3 * seed, seed);
    std::vector<Vec3> x;
    std::vector<double> r;
    for (const auto& b : balls) {
      x.push_back(b.position);
      r.push_back(b.radius);
    }
    std::set<std::pair<int, int>> brute;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = i + 1; j < x.size(); ++j)
        if ((x[i] - x[j]).norm() < r[i] + r[j] + skin) brute.emplace(static_cast<int>(i), static_cast<int>(j));
    for (int threads : {1, 2}) {
      CellGrid grid;
      std::vector<std::int32_t> first, second;
      find_pairs(x, r, skin, threads, grid, first, second);
      std::set<std::pair<int, int>> found;
      for (std::size_t k = 0; k < first.size(); ++k) found.emplace(first[k], second[k]);
      CHECK(found.size() == first.size());  // no duplicates
      CHECK(found == brute);
      CHECK(std::is_sorted(first.begin(), first.end()));

      // The same points re-sorted by cells, as the engine stores them: the search then skips the
      // earlier stencil rows whole. The pairs must be the same ones, renumbered.
      const std::vector<std::int32_t> order = grid.cell_order();
      std::vector<Vec3> sorted_x;
      std::vector<double> sorted_r;
      for (const std::int32_t i : order) {
        sorted_x.push_back(x[static_cast<std::size_t>(i)]);
        sorted_r.push_back(r[static_cast<std::size_t>(i)]);
      }
      find_pairs(sorted_x, sorted_r, skin, threads, grid, first, second);
      std::set<std::pair<int, int>> renumbered;
      for (std::size_t k = 0; k < first.size(); ++k) {
        CHECK(first[k] < second[k]);
        const int a = order[static_cast<std::size_t>(first[k])], b = order[static_cast<std::size_t>(second[k])];
        renumbered.emplace(std::min(a, b), std::max(a, b));
      }
      CHECK(renumbered.size() == first.size());
      CHECK(renumbered == brute);
    }
  }
}

namespace {

/// A small loaded packing: balls dropped into a box under strong gravity, with friction and
/// rolling resistance so that contacts carry shear and rolling history.
World settled_pile(int sort_every) {
  WorldSettings s;
  s.gravity = Vec3(0, 0, -5000.0);
  s.sort_every = sort_every;
  World world(s);
  for (auto b : separated_balls(250, 5e-3, 0.25e-3, 0.4e-3, 21)) {
    b.position.z() += 0.5e-3;  // clear of the floor
    world.add_ball(b);
  }
  world.add_wall(floor_wall(0.0, 0.01));
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
  world.step(10000);
  return world;
}

std::map<std::pair<int, int>, Vec3> shear_history(const World& world) {
  std::map<std::pair<int, int>, Vec3> out;
  const auto& c = world.pair_contacts(ContactKind::BallBall);
  const auto& p = world.particles();
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    const auto* state = reinterpret_cast<const RollingLinearLaw::State*>(c.state.at(k));
    out[{p.id[static_cast<std::size_t>(c.first[k])], p.id[static_cast<std::size_t>(c.second[k])]}] = to_vec3(state->shear_force);
  }
  return out;
}

}  // namespace

TEST_CASE("contacts: history survives neighbour-list rebuilds and particle re-sorting", "[grid][contact]") {
  World world = settled_pile(0);
  const auto before = shear_history(world);
  REQUIRE(before.size() > 200);
  std::size_t loaded = 0;
  for (const auto& [key, f] : before) loaded += f.norm() > 0.0;
  REQUIRE(loaded > 100);  // the history is not trivially zero
  world.rebuild_now(true);
  CHECK(shear_history(world) == before);
  // A copy that is re-sorted now follows the same trajectory as the original, up to the
  // summation order of the forces (round-off, ~1e-19 m per step); lost history would show as
  // micrometre differences within a few steps.
  World unsorted = settled_pile(0);
  World sorted = unsorted;
  sorted.rebuild_now(true);
  sorted.step(100);
  unsorted.step(100);
  const auto& ps = sorted.particles();
  const auto& pu = unsorted.particles();
  double worst = 0.0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const auto pid = static_cast<ParticleId>(i);
    worst = std::max(worst, (ps.x[ps.index_of(pid)] - pu.x[pu.index_of(pid)]).norm());
  }
  CHECK(worst < 1e-12);  // m
  CHECK(ps.id != pu.id);  // the storage order really differs
}

namespace {

/// A square plate of n x n cells (two triangles each) at height z, pushing along `normal`: a
/// fine mesh, so that each ball near it tests several triangles.
Wall tiled_plate(const char* name, double z, double size, int n, const Vec3& normal) {
  geometry::TriangleMesh mesh;
  const double cell = size / n;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const Vec3 centre((a + 0.5) * cell, (b + 0.5) * cell, z);
      const auto tile = geometry::make_rectangle(centre, Vec3(0.5 * cell, 0, 0), Vec3(0, 0.5 * cell, 0));
      mesh = geometry::merge(mesh, tile);
    }
  return make_facet_wall(name, mesh, normal);
}

}  // namespace

TEST_CASE("determinism: one and two threads give bit-identical trajectories", "[grid][determinism]") {
  // A compressed lattice with random sizes and spins between two finely tiled plates: thousands
  // of contacts from the first step, enough pairs (> 4096) and triangle tests that the two-thread
  // run takes the parallel paths.
  std::size_t contact_steps = 0;
  // Pair-loop chunks that a thread took from another thread's share, over the run.
  std::size_t taken_chunks = 0;
  auto make = [&](int threads) {
    WorldSettings s;
    s.threads = threads;
    s.adapt_threads = false;  // the plan inspected below is that of every step's team
    World world(s);
    for (const BallSpec& b : spinning_lattice(16, 9)) world.add_ball(b);
    // the bottom and top layers' centres are 0.28 mm from the plates: every one of them touches
    const double span = 15 * 0.62e-3;
    world.add_wall(tiled_plate("bottom", -0.28e-3, span, 24, -Vec3::UnitZ()));
    world.add_wall(tiled_plate("top", span + 0.28e-3, span, 24, Vec3::UnitZ()));
    auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
    world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
    world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
    world.add_callback(1, [&](World& w) {
      contact_steps += w.contact_count(ContactKind::BallBall);
      for (const auto& later : w.pair_plan(ContactKind::BallBall).taken) taken_chunks += !later.empty();
    });
    world.step(300);
    return world;
  };
  const World one = make(1), two = make(2);
  SECTION("and so do more threads than cores, whose shares other threads finish") {
    // Four threads on fewer cores: a thread that waits for a core leaves its share to the others,
    // which take it chunk by chunk from its end and defer every sum of those chunks.
    taken_chunks = 0;
    const World four = make(4);
    REQUIRE(four.threads() == 4);
    CHECK(taken_chunks > 0);  // the taken chunks' path ran
    CHECK(one.particles().x == four.particles().x);
    CHECK(one.particles().w == four.particles().w);
    // The walls' totals, which each thread adds for its share in turn.
    for (WallId w = 0; w < 2; ++w) {
      CHECK(one.wall(w).force == four.wall(w).force);
      CHECK(one.wall(w).moment == four.wall(w).moment);
      CHECK(one.wall(w).contact_count == four.wall(w).contact_count);
      CHECK(one.wall(w).stiffness_sum == four.wall(w).stiffness_sum);
    }
  }
  REQUIRE(two.threads() == 2);
  REQUIRE(static_cast<std::int64_t>(two.pair_contacts(ContactKind::BallBall).size()) > min_parallel_items);
  const auto triangle_tests = static_cast<std::int64_t>(two.wall_contacts().triangles.size());
  REQUIRE(triangle_test_weight * triangle_tests > min_parallel_items);  // compute_walls on two threads
  CHECK(two.wall(0).contact_count > 200);
  CHECK(one.wall(0).force == two.wall(0).force);
  CHECK(one.wall(1).force == two.wall(1).force);
  CHECK(contact_steps > 2 * 300 * 1000);  // on average > 1000 touching contacts per step
  CHECK(one.particles().x == two.particles().x);
  CHECK(one.particles().w == two.particles().w);

  // The second share adds the sums of its unshared run directly: no particle of that run may be
  // touched by a contact of the other share, and the run holds most of the share (only the
  // particles near the cut between the shares are shared).
  const PairContacts& c = two.pair_contacts(ContactKind::BallBall);
  const PairPlan& plan = two.pair_plan(ContactKind::BallBall);
  REQUIRE(plan.shares.size() == 3);
  REQUIRE(plan.unshared_run.size() == 2);
  std::vector<int> touched_by(two.particles().size(), 0);  // bit t: share t touches it
  for (int t = 0; t < 2; ++t)
    for (std::int64_t k = plan.shares[t]; k < plan.shares[t + 1]; ++k)
      for (const std::int32_t piece : {c.first[k], c.second[k]}) touched_by[piece] |= 1 << t;
  const auto [run_begin, run_end] = plan.unshared_run[1];
  CHECK(run_begin >= plan.shares[1]);
  CHECK(run_end <= plan.shares[2]);
  CHECK(run_end - run_begin > (plan.shares[2] - plan.shares[1]) / 2);
  std::int64_t touched_by_both = 0;
  for (std::int64_t k = run_begin; k < run_end; ++k)
    for (const std::int32_t piece : {c.first[k], c.second[k]}) touched_by_both += touched_by[piece] == 3;
  CHECK(touched_by_both == 0);
}

namespace {

/// Two rebuilds left the same candidates, incidence lists and history, byte for byte.
void check_same_lists(const PairContacts& a, const PairContacts& b) {
  CHECK(a.first == b.first);
  CHECK(a.second == b.second);
  CHECK(a.touching == b.touching);
  CHECK(a.normal_force == b.normal_force);
  CHECK(a.state.bytes == b.state.bytes);
  CHECK(a.incidence_offsets == b.incidence_offsets);
  CHECK(a.incidence_entries == b.incidence_entries);
}
void check_same_lists(const WallContacts& a, const WallContacts& b) {
  CHECK(a.ball == b.ball);
  CHECK(a.wall == b.wall);
  CHECK(a.triangles == b.triangles);
  CHECK(a.triangle_begin == b.triangle_begin);
  CHECK(a.triangle_end == b.triangle_end);
  CHECK(a.normal_force == b.normal_force);
  CHECK(a.state.bytes == b.state.bytes);
}

}  // namespace

TEST_CASE("rebuild: one, two and three threads make the same lists, history and storage order", "[grid][determinism]") {
  // A compressed lattice pushing out against a stack of fixed rings, resting on an analytic plane
  // under a tiled facet plate: every list the rebuild makes (ball-ball, ball-pebble, facet and
  // surface candidates) is long enough to be made in ranges on several threads, and carries
  // history that the rebuild must hand on to the re-sorted lists.
  RingStackSpec spec;
  spec.base_centre = Vec3(7.5 * 0.62e-3, 7.5 * 0.62e-3, -0.3e-3);
  spec.inner_radius = 6.95e-3;
  spec.height = 10.5e-3;
  spec.ring_height = 0.5e-3;
  spec.pebble_radius = 0.25e-3;
  spec.gap = 0.1e-3;
  const auto rings = make_ring_stack(spec);
  auto make = [&](int threads) {
    WorldSettings s;
    s.threads = threads;
    World world(s);
    for (const BallSpec& b : spinning_lattice(16, 5)) world.add_ball(b);
    for (const ClumpSpec& ring : rings) world.add_clump(ring);
    const double span = 15 * 0.62e-3;
    world.add_wall(make_plane_wall("bottom", Vec3(0, 0, -0.28e-3), -Vec3::UnitZ(), span * span));
    world.add_wall(tiled_plate("top", span + 0.28e-3, span, 24, Vec3::UnitZ()));
    auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
    for (const ContactKind kind : {ContactKind::BallBall, ContactKind::BallPebble, ContactKind::BallFacet})
      world.set_contact_model(kind, make_contact_model<RollingLinearLaw>(p, "law"));
    world.step(100);  // contacts with shear and rolling history
    world.rebuild_now(true);
    return world;
  };
  const World one = make(1);
  const WorldState& a = one.state();
  REQUIRE(static_cast<std::int64_t>(a.contacts.ball_ball.size()) > 2 * min_parallel_items);
  REQUIRE(a.contacts.ball_pebble.size() > 100);
  REQUIRE(a.contacts.ball_facet.size() > 100);
  REQUIRE(a.contacts.ball_surface.size() > 200);
  std::size_t carried = 0;  // contacts whose history the rebuild handed on
  for (const std::uint8_t t : a.contacts.ball_ball.touching) carried += t;
  REQUIRE(carried > static_cast<std::size_t>(min_parallel_items));
  for (const int threads : {2, 3}) {
    const World more = make(threads);
    REQUIRE(more.threads() == threads);
    const WorldState& b = more.state();
    CHECK(a.particles.id == b.particles.id);  // the same re-sorted storage
    CHECK(a.particles.x == b.particles.x);
    check_same_lists(a.contacts.ball_ball, b.contacts.ball_ball);
    check_same_lists(a.contacts.ball_pebble, b.contacts.ball_pebble);
    check_same_lists(a.contacts.ball_facet, b.contacts.ball_facet);
    check_same_lists(a.contacts.ball_surface, b.contacts.ball_surface);
  }
}
