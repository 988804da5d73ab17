// The lab toolkit's parts on a World the test owns: ball placement against a brute-force sampler
// fed the same random numbers, the strain of a two-leg shear path against the plate speeds, the
// Follow rings' invariant height fractions (docs/model.md 4), and a consolidation that ends on the
// servo's tolerance or reports that it did not settle, and the horizontal drive's strain path and
// stress servo.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <dem/contact/linear_law.hpp>
#include <dem/lab/toolkit/consolidation.hpp>
#include <dem/lab/toolkit/friction_schedule.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/horizontal_drive.hpp>
#include <dem/lab/toolkit/radius_expansion.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>

using namespace dem;
using namespace dem::lab;

namespace {

// The sampler of place_without_overlap without its grid: every candidate checked against every
// ball placed before it.
std::vector<Vec3> place_brute_force(const Cylinder& cavity, const std::vector<double>& radii, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double radius = cavity.radius, height = cavity.height;
  std::vector<Vec3> placed;
  for (std::size_t n = 0; n < radii.size(); ++n) {
    const double r = radii[n];
    while (true) {
      const Vec3 x((2 * unit(rng) - 1) * (radius - r), (2 * unit(rng) - 1) * (radius - r), r + unit(rng) * (height - 2 * r));
      if (x.head<2>().norm() > radius - r) continue;
      bool clear = true;
      for (std::size_t k = 0; k < placed.size() && clear; ++k) clear = !((placed[k] - x).norm() < radii[k] + r);
      if (!clear) continue;
      placed.push_back(x);
      break;
    }
  }
  return placed;
}

ShearCellSpec small_cell() {
  ShearCellSpec spec;
  spec.diameter = 0.012;
  spec.height = 0.006;
  spec.pebble_diameter = 1.4e-3;
  spec.ring_gap = 0.07e-3;
  return spec;
}

void set_laws(World& world, double friction) {
  const auto law = RollingLinearLaw::Params::deformable(1.2e7, 1.0, friction, 0.1 * friction);
  for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble})
    world.set_contact_model(kind, make_contact_model<RollingLinearLaw>(law, "law"));
}

}  // namespace

TEST_CASE("lab toolkit: balls placed on the cell grid are those a brute-force sampler places", "[lab][toolkit]") {
  const Cylinder cavity{8e-3, 6e-3};
  std::mt19937_64 sizes(3);
  std::uniform_real_distribution<double> radius(0.2e-3, 0.3e-3);
  std::vector<double> radii(3000);  // the grid is rebuilt every 1024 balls
  for (double& r : radii) r = radius(sizes);

  std::mt19937_64 rng_grid(11), rng_brute(11);
  const std::vector<Vec3> grid = place_without_overlap(cavity, radii, rng_grid);
  const std::vector<Vec3> brute = place_brute_force(cavity, radii, rng_brute);
  REQUIRE(grid.size() == radii.size());
  REQUIRE(brute.size() == radii.size());
  for (std::size_t i = 0; i < grid.size(); ++i) REQUIRE(grid[i] == brute[i]);  // same draws, same verdicts
  CHECK(rng_grid() == rng_brute());

  std::size_t outside = 0, overlapping = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (grid[i].head<2>().norm() > cavity.radius - radii[i] || grid[i].z() < radii[i] || grid[i].z() > cavity.height - radii[i])
      ++outside;
    for (std::size_t j = 0; j < i; ++j) overlapping += (grid[i] - grid[j]).norm() < radii[i] + radii[j];
  }
  CHECK(outside == 0);
  CHECK(overlapping == 0);
}

TEST_CASE("lab toolkit: a cavity too small for the balls is refused naming the ball", "[lab][toolkit]") {
  std::mt19937_64 rng(1);
  const std::vector<double> radii(40, 1e-3);  // 40 balls of 2 mm in a 6 mm x 4 mm cylinder
  CHECK_THROWS_WITH(place_without_overlap({3e-3, 4e-3}, radii, rng), Catch::Matchers::Contains("no room for ball"));
}

TEST_CASE("lab toolkit: a two-leg shear path accumulates the plate speed times time over the height", "[lab][toolkit]") {
  WorldSettings settings;
  settings.time_step = 1e-5;  // s
  World world(settings);
  const ShearCell cell = build_shear_cell(world, small_cell());
  ServoWall servo(cell.top, ServoSettings{.target_stress = 1e3, .max_speed = 0.01});
  const double speed = 0.01, height = 0.006;  // m/s, m
  ShearPath path(world, cell, height);

  start_shear_leg(world, cell, servo, {.direction_deg = 0.0, .speed = speed, .moving_plate = MovingPlate::Both});
  world.step(100);
  path.advance(world, cell);
  start_shear_leg(world, cell, servo, {.direction_deg = 90.0, .speed = speed, .mode = ShearMode::ConstantVolume});
  for (int chunk = 0; chunk < 20; ++chunk) {
    world.step(10);
    path.advance(world, cell);
  }
  stop_shear(world, cell);
  world.step(10);
  path.advance(world, cell);

  const double leg = speed * settings.time_step;  // m per step
  CHECK(path.strain() == Approx(300 * leg / height).epsilon(1e-12));
  // The net offset is the hypotenuse of the legs; the first leg moved each plate half of it.
  CHECK(plate_offset(world, cell).norm() == Approx(std::hypot(100 * leg, 200 * leg)).epsilon(1e-12));
  CHECK(world.wall(cell.top).displacement.x() == Approx(-50 * leg).epsilon(1e-12));
  CHECK(servo.holding_position());
}

TEST_CASE("lab toolkit: Follow rings keep their fraction of the height between moving plates", "[lab][toolkit]") {
  WorldSettings settings;
  settings.time_step = 1e-5;  // s
  World world(settings);
  const ShearCell cell = build_shear_cell(world, small_cell());
  REQUIRE(cell.ring_count >= 4);
  world.add_controller([&](World& w) { move_rings(w, cell, true); });
  std::vector<double> fraction;
  for (std::size_t k = cell.first_ring; k < cell.first_ring + cell.ring_count; ++k)
    fraction.push_back((world.clumps()[k].x.z() - world.wall(cell.bottom).displacement.z()) / cell.plate_gap(world));
  world.wall(cell.top).velocity = Vec3(0, 0, 0.02);      // m/s, the specimen dilates
  world.wall(cell.bottom).velocity = Vec3(0, 0, 0.005);  // and its base rises
  world.step(500);
  const double gap = cell.plate_gap(world);
  CHECK(gap == Approx(0.006 + 500 * 0.015 * settings.time_step).epsilon(1e-12));
  for (std::size_t k = 0; k < cell.ring_count; ++k) {
    const double z = world.clumps()[cell.first_ring + k].x.z() - world.wall(cell.bottom).displacement.z();
    CHECK(z / gap == Approx(fraction[k]).epsilon(1e-12));
  }
}

TEST_CASE("lab toolkit: consolidation ends within the servo tolerance of its target, or says it did not", "[lab][toolkit]") {
  World world;
  ShearCellSpec spec = small_cell();
  const ShearCell cell = build_shear_cell(world, spec);
  set_laws(world, 0.0);
  Grading grading;
  grading.scale = 2.0;  // 1.4-2.4 mm
  std::mt19937_64 rng(5);
  const std::vector<double> diameters = sample_diameters(grading, 0.6 * cell.area * spec.height, rng);
  const RadiusExpansion expansion = add_expanding_balls(world, {cell.radius, spec.height}, diameters, 2650.0, 2, rng);
  for (int stage = 1; stage <= expansion.stages; ++stage)
    for (int increment = 1; increment <= expansion.increments; ++increment) {
      set_radii(world, expansion, expansion.factor(stage, increment));
      world.step(expansion.steps_per_increment);
    }
  REQUIRE(world.particles().radius[world.particles().index_of(expansion.balls.back())] == Approx(diameters.back() / 2).epsilon(1e-15));
  release_rings(world, cell);
  set_laws(world, 0.5);

  ServoWall servo(cell.top, ServoSettings{.target_stress = 1e3, .max_speed = 0.05, .settle_tolerance = 0.01, .settle_steps = 200});
  world.add_controller([&](World& w) {
    servo(w);
    move_rings(w, cell, true);
  });
  const ConsolidationTarget hurried{.vertical_stress = 80e3, .max_steps = 20};
  start_consolidation(servo, hurried);
  const ConsolidationReport cut_short = consolidate(world, servo, hurried, world.step_count());
  CHECK_FALSE(cut_short.settled);
  CHECK(cut_short.steps == 20);

  const ConsolidationTarget target{.vertical_stress = 80e3, .max_steps = 200000};
  const ConsolidationReport report = consolidate(world, servo, target, world.step_count());
  REQUIRE(report.settled);
  CHECK(std::abs(report.stress - 80e3) <= 0.01 * 80e3);  // the servo's settle tolerance
  CHECK(report.unbalanced_ratio < target.equilibrium_ratio);
  CHECK(world.wall(cell.top).normal_stress() == Approx(report.stress));
}

TEST_CASE("lab toolkit: the friction schedule halves the friction to its floor, then zero, and stops at the porosity",
          "[lab][toolkit]") {
  const FrictionSchedule schedule{.target_porosity = 0.40, .porosity_tolerance = 0.005, .reduction = 0.5, .floor = 0.005};
  Friction now{0.5, 0.4};
  int steps = 0;
  while (const std::optional<Friction> next = next_friction(schedule, 0.45, now)) {
    now = *next;
    ++steps;
    if (now.sliding > 0) {
      CHECK(now.sliding == 0.5 * std::pow(0.5, steps));  // exact: halving is exact in binary
      CHECK(now.rolling == 0.4 * std::pow(0.5, steps));
    }
    REQUIRE(steps < 20);
  }
  // 0.5 x 0.5^7 = 0.0039 is the first below the floor: step 7 sets zero, and zero friction ends it.
  CHECK(steps == 7);
  CHECK(now.sliding == 0.0);
  CHECK(now.rolling == 0.0);
  // Within the tolerance of the target (or denser) there is no next step.
  CHECK_FALSE(next_friction(schedule, 0.405, {0.5, 0.4}));
  CHECK_FALSE(next_friction(schedule, 0.39, {0.5, 0.4}));
  CHECK(next_friction(schedule, 0.4051, {0.5, 0.4}));
}

TEST_CASE("lab toolkit: the horizontal drive puts the strain on its path and the plate stress on its target",
          "[lab][toolkit][cyclic]") {
  WorldSettings settings;
  settings.time_step = 1e-6;  // s
  settings.local_damping = 0.0;
  World world(settings);
  const ShearCell cell = build_shear_cell(world, small_cell());
  set_laws(world, 0.5);
  const double height = 0.006;  // m
  HorizontalDriveSettings s{.top = cell.top, .bottom = cell.bottom, .area = cell.area, .height = height, .max_speed = 1.0};
  auto drive = std::make_shared<HorizontalDrive>(s);
  world.add_controller([drive](World& w) { (*drive)(w); });

  SECTION("strain control: the offset over the height is the target at the end of every step") {
    const double steps_per_cycle = 200.0;
    auto target = [](double n) { return Vec3(0.01 * std::sin(2 * pi * n), 0.005 * std::sin(4 * pi * n), 0.0); };
    drive->follow_strain(target, world.step_count(), steps_per_cycle);
    for (int chunk = 0; chunk < 9; ++chunk) {
      world.step(23);
      const Vec3 strain = plate_offset(world, cell) / height;
      CHECK((strain - target(drive->cycles_at(world.step_count()))).norm() < 1e-15);
    }
    CHECK(drive->work() == 0.0);  // no balls: no stress on the top plate
  }
  SECTION("stress control: one ball pressed under the top plate; the servo reaches a force below friction") {
    // The ball is held; the plate is 5 um into it, so F_n = kn 5e-6 and the tangential spring
    // ks = kn (stiffness ratio 1) carries the plate's horizontal force. Target: 20 % of mu F_n.
    world.add_ball({.position = Vec3(0, 0, height - 0.5e-3 + 5e-6), .radius = 0.5e-3, .density = 2650, .fixed = dof_all});
    world.step(1);
    const double normal_force = world.wall(cell.top).force.z();
    REQUIRE(normal_force > 0.0);
    const Vec3 target_stress = Vec3(0.2 * 0.5 * normal_force / cell.area, 0.0, 0.0);
    drive->servo_stress([&](double) { return target_stress; }, world.step_count(), 100.0);
    world.step(20);
    const Vec3 stress = Vec3(world.wall(cell.top).force.x(), world.wall(cell.top).force.y(), 0.0) / cell.area;
    CHECK((stress - target_stress).norm() < 1e-6 * target_stress.norm());
    drive->hold();
    world.step(5);
    CHECK(world.wall(cell.top).velocity.head<2>().norm() == 0.0);
  }
  CHECK_THROWS_WITH(HorizontalDrive({.top = cell.top, .bottom = cell.bottom, .area = cell.area, .height = height}),
                    Catch::Contains("horizontal drive max_speed"));
}
