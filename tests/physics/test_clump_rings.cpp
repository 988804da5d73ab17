// Ring stacks (docs/model.md 4): the geometry, mass and inertia built by make_ring_stack against the
// thick-cylinder formulas, its input checks, and a small NGI-type specimen: a few hundred balls
// inside a stack of pebble rings between two facet plates, compressed by the top plate. The rings
// must move horizontally only, keep every ball in, and be pushed outwards by the sand.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <dem/boundary/clump_ring.hpp>
#include <dem/core/parallel.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

namespace {

/// 20 mm inner diameter, 1 mm rings of 0.5 mm pebbles, 0.2 mm apart, covering 8 mm.
RingStackSpec small_stack() {
  RingStackSpec s;
  s.base_centre = Vec3(1e-3, -2e-3, 0.5e-3);
  s.inner_radius = 10e-3;
  s.height = 8e-3;
  s.ring_height = 1e-3;
  s.pebble_radius = 0.5e-3;
  s.gap = 0.2e-3;
  return s;
}

double radial_distance(const Vec3& x, const Vec3& axis_point) { return (x - axis_point).head<2>().norm(); }

}  // namespace

TEST_CASE("ring stack: pebbles tangent to the specimen, ring count, thick-cylinder mass and inertia", "[rings]") {
  const RingStackSpec spec = small_stack();
  const auto stack = make_ring_stack(spec);
  // Fewest rings covering 8 mm at a 1.2 mm pitch: 7 (6.83 rounded up), covering 8.2 mm.
  REQUIRE(stack.size() == 7U);
  CHECK(ring_stack_count(spec) == 7);
  // Fewest pebbles with centres at most r_peb apart on the 10.5 mm circle: pi / asin(r / 2R) =
  // 131.93, so 132 (chord 0.49975 mm; 131 would give 0.50357 mm).
  CHECK(ring_pebble_count(spec) == 132);
  CHECK(ring_layer_count(spec) == 1);

  // Thick cylinder a = 10 mm, b = 11 mm, h = 1 mm, rho = 2700 (values worked out by hand).
  const double mass = 1.7812830e-4, i_axial = 1.9683178e-8, i_radial = 9.8564328e-9;
  const RingMass solid = thick_ring_mass(10e-3, 11e-3, 1e-3, 2700.0);
  CHECK(solid.mass == Approx(mass).epsilon(1e-7));  // 8 digits quoted
  CHECK(solid.axial_inertia == Approx(i_axial).epsilon(1e-7));
  CHECK(solid.radial_inertia == Approx(i_radial).epsilon(1e-7));

  for (std::size_t k = 0; k < stack.size(); ++k) {
    const ClumpSpec& ring = stack[k];
    REQUIRE(ring.pebbles.size() == 132U);
    CHECK(ring.mass == Approx(mass).epsilon(1e-7));
    CHECK(ring.inertia(2, 2) == Approx(i_axial).epsilon(1e-7));
    CHECK(ring.inertia(0, 0) == Approx(i_radial).epsilon(1e-7));
    CHECK(ring.inertia(1, 1) == Approx(i_radial).epsilon(1e-7));
    CHECK(ring.inertia(0, 1) == 0.0);
    CHECK(ring.fixed == (dof_z | dof_rotation));
    // Centre on the axis at mid-height of ring k: z0 + k (1.2 mm) + 0.5 mm (round-off only).
    const double mid = spec.base_centre.z() + static_cast<double>(k) * 1.2e-3 + 0.5e-3;
    CHECK((ring.centre_of_mass - Vec3(spec.base_centre.x(), spec.base_centre.y(), mid)).norm() < 1e-15);
    double inner_min = 1.0, inner_max = 0.0, chord_max = 0.0;
    for (std::size_t j = 0; j < ring.pebbles.size(); ++j) {
      const PebbleSpec& p = ring.pebbles[j];
      CHECK(p.radius == 0.5e-3);
      CHECK(p.position.z() == Approx(mid).epsilon(1e-12));  // one layer, at mid-height
      const double inner = radial_distance(p.position, spec.base_centre) - p.radius;
      inner_min = std::min(inner_min, inner);
      inner_max = std::max(inner_max, inner);
      const PebbleSpec& next = ring.pebbles[(j + 1) % ring.pebbles.size()];
      chord_max = std::max(chord_max, (next.position - p.position).norm());
    }
    // Inner surfaces tangent to the 10 mm specimen radius (round-off of ~1e-2 m coordinates).
    CHECK(inner_min == Approx(10e-3).epsilon(1e-12));
    CHECK(inner_max == Approx(10e-3).epsilon(1e-12));
    CHECK(chord_max <= 0.5e-3);
    CHECK(chord_max == Approx(0.4997516e-3).epsilon(1e-6));
  }
  // The stack covers the specimen: bottom pebbles touch its base, the top ring reaches 8.2 mm.
  CHECK(stack.front().pebbles.front().position.z() - 0.5e-3 == Approx(spec.base_centre.z()).epsilon(1e-12));
  CHECK(stack.back().pebbles.front().position.z() + 0.5e-3 - spec.base_centre.z() == Approx(8.2e-3).epsilon(1e-12));
}

TEST_CASE("ring stack: tall rings stack pebble layers, openings are what a ball can pass", "[rings]") {
  RingStackSpec spec = small_stack();
  spec.ring_height = 2e-3;
  spec.ring_count = 4;
  // Layers from 0.5 to 1.5 mm above each ring's base, at most r_peb apart: 3 layers, 0.5 mm apart.
  REQUIRE(ring_layer_count(spec) == 3);
  const auto stack = make_ring_stack(spec);
  REQUIRE(stack.size() == 4U);
  REQUIRE(stack[1].pebbles.size() == 3U * 132U);
  for (int layer = 0; layer < 3; ++layer)
    CHECK(stack[1].pebbles[static_cast<std::size_t>(layer) * 132U].position.z() - spec.base_centre.z() ==
          Approx(2.2e-3 + 0.5e-3 + 0.5e-3 * layer).epsilon(1e-12));
  const RingMass solid = thick_ring_mass(10e-3, 11e-3, 2e-3, 2700.0);
  CHECK(stack[1].mass == Approx(solid.mass).epsilon(1e-14));
  CHECK(stack[1].inertia(0, 0) == Approx(solid.radial_inertia).epsilon(1e-14));

  // Within a ring every hole is closed (chord and layer spacing <= r_peb); between rings the
  // widest hole is the one between two pebbles of a top layer and the two above them across the
  // gap: a ball of diameter sqrt(chord^2 + (2 r_peb + gap)^2) - 2 r_peb = 0.29990 mm.
  const double opening = ring_stack_opening(spec);
  CHECK(opening == Approx(0.2999045e-3).epsilon(1e-6));
  // Check it on the real pebbles: a probe ball at the middle of that hole (azimuth pi/132, radius
  // R cos(pi/132), mid-gap height) just fits with diameter 0.999 x opening, and not at 1.001 x.
  const double azimuth = pi / 132.0, along = 10.5e-3 * std::cos(azimuth);
  const Vec3 probe = spec.base_centre + Vec3(along * std::cos(azimuth), along * std::sin(azimuth), 2.0e-3 + 0.1e-3);
  double clearance = 1.0;  // m, from the probe's centre to the nearest pebble surface
  for (const ClumpSpec& ring : stack)
    for (const PebbleSpec& p : ring.pebbles) clearance = std::min(clearance, (p.position - probe).norm() - p.radius);
  CHECK(2.0 * clearance > 0.999 * opening);
  CHECK(2.0 * clearance < 1.001 * opening);

  // max_opening: accepted above the widest opening, refused at or below it.
  spec.max_opening = 1.001 * opening;
  CHECK_NOTHROW(make_ring_stack(spec));
  spec.max_opening = 0.999 * opening;
  CHECK_THROWS_WITH(make_ring_stack(spec), Contains("max_opening") && Contains("0.0002996") && Contains("0.000299905"));
  // No gap and a single ring: nothing opens at all.
  spec.gap = 0.0;
  spec.ring_count = 1;
  spec.height = 2e-3;
  CHECK(ring_stack_opening(spec) == 0.0);
}

TEST_CASE("ring stack: bad input is refused with the key and the value", "[rings]") {
  auto with = [](auto change) {
    RingStackSpec s = small_stack();
    change(s);
    return s;
  };
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.inner_radius = -1e-3; })),
                    Contains("inner_radius") && Contains("-0.001"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.pebble_radius = 0.0; })),
                    Contains("pebble_radius") && Contains("= 0"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.height = 0.0; })), Contains("height"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.ring_height = 0.8e-3; })),
                    Contains("ring_height") && Contains("0.0008") && Contains("pebble diameter"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.gap = -0.1e-3; })),
                    Contains("gap") && Contains("-0.0001"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.ring_count = -2; })),
                    Contains("ring_count") && Contains("-2"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.ring_density = 0.0; })),
                    Contains("ring_density"));
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.base_centre.x() = std::nan(""); })),
                    Contains("base_centre"));
  // 6 rings at a 1.2 mm pitch cover 7.0 mm, not the 8 mm asked for.
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.ring_count = 6; })),
                    Contains("ring_count") && Contains("= 6") && Contains("cover 0.007"));
  // 10 nm pebbles: 6e6 per layer and 1e5 layers per ring, a unit mistake.
  CHECK_THROWS_WITH(make_ring_stack(with([](RingStackSpec& s) { s.pebble_radius = 1e-8; })),
                    Contains("pebble count"));
  CHECK_THROWS_AS(thick_ring_mass(11e-3, 10e-3, 1e-3, 2700.0), InputError);
  CHECK_NOTHROW(make_ring_stack(with([](RingStackSpec& s) { s.ring_count = 7; })));
}

namespace {

/// Specimen by radius expansion (docs/model.md 7): balls of final radii drawn uniformly in
/// [r_min, r_max] until their volume is `solid` of the cylinder (radius a, height h), placed at
/// random without overlap at half their radii; returns the balls at half size and their final radii.
std::vector<BallSpec> half_size_specimen(double a, double h, double r_min, double r_max, double solid, unsigned seed,
                                         std::vector<double>& final_radii) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double volume = 0.0;
  while (volume < solid * pi * a * a * h) {
    final_radii.push_back(r_min + (r_max - r_min) * unit(rng));
    volume += 4.0 / 3.0 * pi * std::pow(final_radii.back(), 3);
  }
  std::vector<BallSpec> balls;
  for (double r : final_radii) {
    const double half = 0.5 * r;
    for (int attempt = 0; attempt < 100000; ++attempt) {
      const Vec3 x((2 * unit(rng) - 1) * a, (2 * unit(rng) - 1) * a, half + (h - 2 * half) * unit(rng));
      if (x.head<2>().norm() > a - half) continue;
      bool clear = true;
      for (const BallSpec& b : balls) clear = clear && (b.position - x).norm() >= b.radius + half;
      if (!clear) continue;
      balls.push_back(ball_at(x, Vec3::Zero(), half));
      break;
    }
  }
  REQUIRE(balls.size() == final_radii.size());  // 0.42 / 8 of the volume: always room at half size
  return balls;
}

}  // namespace

TEST_CASE("ring stack confining a specimen: rings move horizontally only, hold the balls, take radial push",
          "[rings]") {
  // A 20 mm x 6 mm specimen of 262 balls (radii 0.8-1.0 mm, 42 % of the volume) inside a stack of
  // six 1 mm rings, between facet plates 11 mm in radius. The balls grow from half size to fill
  // the stack, then the top plate, servo-controlled, loads them to 50 kPa.
  const double a = 10e-3, h = 6e-3, r_min = 0.8e-3, r_max = 1.0e-3;
  std::vector<double> final_radii;
  const auto balls = half_size_specimen(a, h, r_min, r_max, 0.42, 5, final_radii);

  World world;  // automatic time step, local damping 0.7, no gravity
  for (const BallSpec& b : balls) world.add_ball(b);
  RingStackSpec spec;
  spec.inner_radius = a;
  spec.height = h;
  spec.ring_height = 1e-3;
  spec.pebble_radius = 0.5e-3;
  spec.gap = 0.2e-3;
  spec.max_opening = 2.0 * r_min;  // no ball can slip between the rings
  for (const ClumpSpec& ring : make_ring_stack(spec)) world.add_clump(ring);
  REQUIRE(world.clumps().size() == 6U);
  world.add_wall(
      make_facet_wall("bottom", geometry::make_disc(Vec3::Zero(), a + 1e-3, Vec3::UnitZ(), 64), -Vec3::UnitZ()));
  const WallId top = world.add_wall(
      make_facet_wall("top", geometry::make_disc(Vec3(0, 0, h), a + 1e-3, -Vec3::UnitZ(), 64), Vec3::UnitZ()));
  using Params = RollingLinearLaw::Params;
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(
                                                     Params::deformable(modulus_ball, 1.0, 0.45, 0.18), "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(
                                                      Params::deformable(modulus_wall, 1.0, 0.45, 0.18), "ball-facet"));
  // The study's membrane-like ball-pebble friction of 0.1.
  world.set_contact_model(ContactKind::BallPebble, make_contact_model<RollingLinearLaw>(
                                                       Params::deformable(modulus_wall, 1.0, 0.1, 0.0), "ball-pebble"));
  world.update_time_step();

  std::vector<double> ring_z, pebble_z;  // initial heights, compared bit for bit at the end
  for (const Clump& c : world.clumps()) {
    ring_z.push_back(c.x.z());
    for (ParticleId id : c.pebbles) pebble_z.push_back(world.particles().x[world.particles().index_of(id)].z());
  }

  // Radius expansion in 200 increments of 10 steps, then 1000 steps to settle. The balls were
  // added first, so a ball's id is its index in final_radii.
  for (int increment = 1; increment <= 200; ++increment) {
    ParticleStore& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (!p.is_pebble(i)) p.set_radius(i, (0.5 + 0.5 * increment / 200.0) * final_radii[static_cast<std::size_t>(p.id[i])]);
    world.invalidate_contacts();
    world.step(10);
  }
  world.step(1000);

  // Top plate servo: speed proportional to the force error, at most 0.1 m/s.
  const double target_force = 50e3 * pi * a * a;  // N
  world.add_controller([&](World& w) {
    Wall& plate = w.wall(top);
    plate.velocity = Vec3(0, 0, -0.1 * std::clamp(1.0 - plate.force.z() / target_force, -1.0, 1.0));
  });
  world.step(6000);

  // Rings: horizontal motion only, bit-exact.
  std::size_t k = 0;
  double shift_max = 0.0;
  for (std::size_t ring = 0; ring < world.clumps().size(); ++ring) {
    const Clump& c = world.clumps()[ring];
    CHECK(c.x.z() == ring_z[ring]);
    CHECK(c.v.z() == 0.0);
    CHECK(c.w == Vec3::Zero());
    CHECK(c.orientation.coeffs() == Quat::Identity().coeffs());
    for (ParticleId id : c.pebbles) CHECK(world.particles().x[world.particles().index_of(id)].z() == pebble_z[k++]);
    shift_max = std::max(shift_max, c.displacement.head<2>().norm());
  }
  CHECK(shift_max > 0.05e-3);  // the sand did push the rings about

  // Balls: all inside. The deepest seat in the wall (between two pebbles of each of two aligned
  // neighbouring rings) holds the centre of the smallest ball 9.37 mm from the axis of the ring at
  // its height; a centre at 10 mm would be half through the wall. Vertically the plates hold
  // them, up to the contact overlap (about 1 % of a radius at 50 kPa).
  const ParticleStore& p = world.particles();
  const double plate_z = world.wall(top).mesh.vertices.front().z();
  double centre_max = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i)) continue;
    for (const Clump& c : world.clumps())
      if (std::abs(p.x[i].z() - c.x.z()) <= 0.5 * (spec.ring_height + spec.gap))
        centre_max = std::max(centre_max, radial_distance(p.x[i], c.x));
    CHECK(p.x[i].z() > 0.9 * p.radius[i]);
    CHECK(p.x[i].z() < plate_z - 0.9 * p.radius[i]);
  }
  CHECK(centre_max < a);
  CHECK(centre_max > a - r_max - 0.1e-3);  // and the sand does reach the wall

  // Forces: the sand pushes the rings outwards, with less than the vertical stress: a frictional
  // packing compressed one-dimensionally has K0 = 1 - sin(phi), about 0.4-0.5, below 1.
  double radial = 0.0;
  int ring_contacts = 0;
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallPebble) return;
    const Vec3 outward = (p.x[static_cast<std::size_t>(c.second)] - world.clumps()[static_cast<std::size_t>(
                                                                         p.clump[static_cast<std::size_t>(c.second)])]
                                                                         .x)
                             .cwiseProduct(Vec3(1, 1, 0))
                             .normalized();
    radial += c.force.dot(outward);
    ++ring_contacts;
  });
  const double top_force = world.wall(top).force.z();
  const double lateral_stress = radial / (2.0 * pi * a * plate_z);  // Pa, over the loaded wall height
  const double vertical_stress = top_force / (pi * a * a);
  INFO("ring contacts " << ring_contacts << ", radial force " << radial << " N, top force " << top_force
                        << " N, height " << plate_z << " m, K = " << lateral_stress / vertical_stress);
  CHECK(top_force > 0.8 * target_force);  // loaded (the servo closes in on 15.7 N from below)
  CHECK(ring_contacts > 20);
  CHECK(radial > 0.0);
  CHECK(lateral_stress < vertical_stress);
}

TEST_CASE("ring stack: one and two threads move free rings and their pebbles bit for bit alike", "[rings][determinism]") {
  // Balls thrown outwards at a stack of rings free in every degree of freedom: the rings are
  // pushed, tilted and turned. With more pebbles than a loop needs to run on threads, two threads
  // find each pebble's share of its clump's force and torque and place the pebbles by where
  // they are stored, where one thread does both clump by clump: the same bits either way.
  RingStackSpec spec;
  spec.inner_radius = 20e-3;
  spec.height = 3e-3;
  spec.ring_height = 0.5e-3;
  spec.pebble_radius = 0.25e-3;
  spec.gap = 0.1e-3;
  spec.fixed = 0;
  const auto rings = make_ring_stack(spec);
  std::int64_t contact_steps = 0;  // ball-pebble contacts summed over the one-thread run's steps
  auto make = [&](int threads) {
    WorldSettings s;
    s.threads = threads;
    s.adapt_threads = false;  // a busy machine must not leave the two-thread paths untried
    World world(s);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    // 0.4 mm balls 0.05 mm inside the wall, 6 heights x 120 angles, moving outwards and spinning.
    for (int layer = 0; layer < 6; ++layer)
      for (int k = 0; k < 120; ++k) {
        const double angle = 2 * pi * (k + 0.5 * (layer % 2)) / 120;
        const Vec3 out(std::cos(angle), std::sin(angle), 0.0);
        BallSpec b = ball_at(Vec3(0, 0, (0.25 + 0.5 * layer) * 1e-3) + (20e-3 - 0.25e-3) * out,
                             (0.2 + 0.1 * unit(rng)) * out + 0.05 * Vec3(unit(rng), unit(rng), unit(rng)), 0.2e-3);
        b.angular_velocity = 200.0 * Vec3(unit(rng), unit(rng), unit(rng));
        world.add_ball(b);
      }
    for (const ClumpSpec& ring : rings) world.add_clump(ring);
    using Params = RollingLinearLaw::Params;
    const auto p = Params::deformable(modulus_wall, 1.0, 0.3, 0.1);
    world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
    world.set_contact_model(ContactKind::BallPebble, make_contact_model<RollingLinearLaw>(p, "ball-pebble"));
    world.update_time_step();
    if (threads == 1) world.add_callback(1, [&](World& w) { contact_steps += w.contact_count(ContactKind::BallPebble); });
    world.step(1500);
    return world;
  };
  const World one = make(1), two = make(2);
  std::int64_t pebbles = 0;
  for (const Clump& c : one.clumps()) pebbles += static_cast<std::int64_t>(c.pebbles.size());
  REQUIRE(pebbles >= min_parallel_items);  // so that the two-thread run splits the clumps' loops
  REQUIRE(two.threads() == 2);
  double turned = 0.0, pushed = 0.0;
  for (std::size_t k = 0; k < one.clumps().size(); ++k) {
    const Clump& a = one.clumps()[k];
    const Clump& b = two.clumps()[k];
    CHECK(a.x == b.x);
    CHECK(a.v == b.v);
    CHECK(a.w == b.w);
    CHECK(a.orientation.coeffs() == b.orientation.coeffs());
    CHECK(a.force == b.force);
    CHECK(a.torque == b.torque);
    turned = std::max(turned, a.w.norm());
    pushed = std::max(pushed, a.displacement.norm());
  }
  CHECK(contact_steps > 1000);  // the balls did push the pebbles (about 5,700 contact-steps)
  CHECK(turned > 0.0);         // the torques' path ran
  CHECK(pushed > 0.0);
  CHECK(one.particles().x == two.particles().x);
  CHECK(one.particles().v == two.particles().v);
  CHECK(one.particles().w == two.particles().w);
}
