// Analytic walls (boundary/wall.hpp): an infinite plane or cylinder whose closest point is exact.
// They use the ball-facet law, so a ball on a plane must get the forces of a facet floor at the
// same height (the facet's closest point is computed through barycentric coordinates: the two
// differ by round-off only); a ball pressed against a cylinder carries k_n delta along the radius;
// servos drive them as facet walls; restart files carry them and resume bit for bit.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include <dem/control/servo_wall.hpp>
#include <dem/io/world_state.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double kn_wall = pi * radius * modulus_wall;  // N/m, ball-facet stiffness (docs/model.md T0)
constexpr double floor_half = 5e-3;                     // m

void set_wall_law(World& world, double friction) {
  const auto p = RollingLinearLaw::Params::deformable(modulus_wall, 1.0, friction, 0.1);
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
}

/// A ball sliding and spinning on a floor at z = 0 under gravity, from about its resting overlap
/// (m g / k_n = 4.3e-10 m), with a skin small enough that the lists are remade every few hundred
/// steps (history carried across rebuilds).
World rolling_ball(bool analytic) {
  WorldSettings s = dynamic_settings(2e-7);
  s.gravity = Vec3(0, 0, -9.81);
  s.skin = 5e-6;
  World world(s);
  BallSpec b = ball_at(Vec3(1e-4, 2e-4, radius - 5e-10), Vec3(0.05, 0.02, 0.0));
  b.angular_velocity = Vec3(10, -5, 3);
  world.add_ball(b);
  world.add_wall(analytic ? make_plane_wall("floor", Vec3::Zero(), -Vec3::UnitZ(), 4 * floor_half * floor_half)
                          : floor_wall(0.0, floor_half));
  set_wall_law(world, 0.5);
  return world;
}

}  // namespace

TEST_CASE("analytic walls: a ball bouncing and sliding on a plane gets the forces of a facet floor", "[physics][walls]") {
  World plane = rolling_ball(true), facets = rolling_ball(false);
  double worst_x = 0.0, worst_force = 0.0, largest_force = 0.0;
  int touching = 0;
  for (int k = 0; k < 40; ++k) {
    plane.step(100);
    facets.step(100);
    worst_x = std::max(worst_x, (plane.particles().x[0] - facets.particles().x[0]).norm());
    worst_force = std::max(worst_force, (plane.wall(0).force - facets.wall(0).force).norm());
    largest_force = std::max(largest_force, facets.wall(0).force.norm());
    touching += facets.wall(0).contact_count;
    REQUIRE(plane.wall(0).contact_count == facets.wall(0).contact_count);
  }
  REQUIRE(touching == 40);             // it stays on the floor
  REQUIRE(plane.rebuild_count() > 5);  // and its history crossed rebuilds
  // Round-off of one closest-point formula against the other, carried through 4000 steps of a
  // non-chaotic motion: a few ulps of the position (radius 5e-4 m: 1 ulp is 1e-19 m) and of the
  // force (measured: 1.4e-20 m and 4e-15 of the force).
  CAPTURE(worst_x, worst_force, largest_force);
  CHECK(worst_x < 1e-18);
  CHECK(worst_force < 1e-12 * largest_force);
  CHECK(plane.contact_count(ContactKind::BallFacet) == facets.contact_count(ContactKind::BallFacet));
}

TEST_CASE("analytic walls: a ball pressed into a cylinder from inside or outside carries k_n delta along the radius",
          "[physics][walls]") {
  const double cylinder_radius = 5e-3, delta = 1e-5;  // m
  const Vec3 axis_point(1e-3, -2e-3, 0.0);
  const Vec3 radial = Vec3(std::cos(0.7), std::sin(0.7), 0.0);
  for (const double side : {-1.0, 1.0}) {  // -1: inside, +1: outside
    World world(dynamic_settings(1e-7));
    BallSpec b = ball_at(axis_point + (cylinder_radius + side * (radius - delta)) * radial + Vec3(0, 0, 3e-3));
    b.fixed = dof_all;
    world.add_ball(b);
    const WallId side_wall = world.add_wall(make_cylinder_wall("side", axis_point, Vec3::UnitZ(), cylinder_radius, 1e-4));
    set_wall_law(world, 0.5);
    world.step(1);
    const Wall& wall = world.wall(side_wall);
    REQUIRE(wall.contact_count == 1);
    // The ball pushes the wall away from itself: outwards from inside, inwards from outside.
    const Vec3 expected = -side * kn_wall * delta * radial;
    CHECK((wall.force - expected).norm() < 1e-9 * expected.norm());
    CHECK(wall.stiffness_sum == Approx(kn_wall).epsilon(1e-12));
    CHECK(world.contact_count(ContactKind::BallFacet) == 1);
    world.for_each_contact([&](const ContactView& c) {
      // The contact point is in the overlap's middle, delta/2 beyond the surface on the wall's side.
      CHECK(std::abs((c.point - axis_point).head<2>().norm() - (cylinder_radius - side * delta / 2)) < 1e-14);
    });
  }
}

TEST_CASE("analytic walls: a servo holds a plane plate on a ball at F*(1/k_top + 1/k_bottom)", "[physics][walls][servo]") {
  WorldSettings s = dynamic_settings(2e-7);
  s.local_damping = 0.7;
  World world(s);
  const double plate_area = 16e-6, gap = 0.02 * radius;  // m^2, m
  world.add_ball(ball_at(Vec3(0, 0, radius)));
  world.add_wall(make_plane_wall("bottom", Vec3::Zero(), -Vec3::UnitZ(), plate_area));
  const WallId top = world.add_wall(make_plane_wall("top", Vec3(0, 0, 2 * radius + gap), Vec3::UnitZ(), plate_area));
  set_wall_law(world, 0.5);
  const double force = 1.0;  // N
  ServoSettings settings;
  settings.target_stress = force / plate_area;
  settings.max_speed = 0.5;
  settings.settle_tolerance = 1e-4;
  auto servo = add_servo_wall(world, top, settings);
  world.step(20000);
  // As the facet plate of test_servo.cpp: the same law, the same gain, the same equilibrium.
  const double overlap_sum = 2 * radius - world.wall(top).reference_point.z();
  CHECK(overlap_sum == Approx(force * 2 / kn_wall).epsilon(1e-3));
  CHECK(servo->settled());
  CHECK(world.wall(top).normal_stress() == Approx(settings.target_stress).epsilon(1e-4));
}

TEST_CASE("analytic walls: a saved state resumes bit for bit; a state of format 1 still reads", "[physics][walls][checkpoint]") {
  World a = rolling_ball(true);
  a.add_wall(make_cylinder_wall("side", Vec3::Zero(), Vec3::UnitZ(), 2e-4 + radius * 1.01, 1e-4));
  a.step(1500);
  std::stringstream state;
  io::write_world_state(state, a);
  World b = rolling_ball(true);  // the same models; its state is replaced
  io::read_world_state(state, b);
  a.step(1500);
  b.step(1500);
  CHECK(a.particles().x[0] == b.particles().x[0]);
  CHECK(a.particles().w[0] == b.particles().w[0]);
  CHECK(a.wall(0).force == b.wall(0).force);
  CHECK(a.wall(1).force == b.wall(1).force);
  REQUIRE(a.wall(1).contact_count + a.wall(0).contact_count > 0);

  // Format 1 had no surfaces: a facet-only state without its last section reads as format 1, and
  // as format 2 it is refused as truncated.
  World facets = rolling_ball(false);
  facets.step(700);
  std::ostringstream written;
  io::write_world_state(written, facets);
  const std::string bytes = written.str();
  // Per wall a surface (shape byte, point, axis, radius: 57 bytes); then an empty contact list:
  // eleven array counts, the law's State size and count (8 bytes each).
  const std::size_t tail = facets.walls().size() * 57 + 13 * 8;
  std::istringstream format1(bytes.substr(0, bytes.size() - tail));
  World resumed = rolling_ball(false);
  io::read_world_state(format1, resumed, 1);
  std::istringstream truncated(bytes.substr(0, bytes.size() - tail));
  World refused = rolling_ball(false);
  CHECK_THROWS_AS(io::read_world_state(truncated, refused, 2), InputError);
  facets.step(500);
  resumed.step(500);
  CHECK(facets.particles().x[0] == resumed.particles().x[0]);
  CHECK(facets.wall(0).force == resumed.wall(0).force);
}

TEST_CASE("analytic walls: bad shapes are refused naming the wall and the value", "[physics][walls]") {
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(make_plane_wall("top", Vec3::Zero(), Vec3::Zero(), 1.0), Contains("wall 'top' outward_normal"));
  CHECK_THROWS_WITH(make_plane_wall("top", Vec3::Zero(), Vec3::UnitZ(), 0.0), Contains("wall 'top' area"));
  CHECK_THROWS_WITH(make_cylinder_wall("side", Vec3::Zero(), Vec3::UnitZ(), -1.0, 1.0), Contains("wall 'side' radius"));
  CHECK_THROWS_WITH(make_cylinder_wall("side", Vec3(NAN, 0, 0), Vec3::UnitZ(), 1.0, 1.0), Contains("wall 'side' axis_point"));
}
