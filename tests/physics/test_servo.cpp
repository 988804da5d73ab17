// Servo-controlled walls (docs/model.md 5, T10). A plate on one ball over a fixed floor settles where
// both contacts carry the target force, i.e. at the overlap sum F* (1/k_top + 1/k_bot), and each
// step of servo motion removes between 0 and alpha_s of the stress error (exactly alpha_s when the
// speed cap is not active). Packings in boxes of facet walls reach, hold and follow targets with
// one and with six servo walls.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include <dem/control/servo_wall.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

namespace {

constexpr double plate_half = 2e-3;                         // m, half side of the square plates
constexpr double plate_area = 4 * plate_half * plate_half;  // m^2
constexpr double kn_wall = pi * radius * modulus_wall;      // N/m, ball-facet (docs/model.md T0), 31415.9

/// One ball resting on a floor at z = 0, a free plate `gap` above it; returns the plate's id.
WallId ball_between_plates(World& world, double gap, double wall_friction) {
  world.add_ball(ball_at(Vec3(0, 0, radius)));
  world.add_wall(floor_wall(0.0, plate_half));
  const WallId top = world.add_wall(make_facet_wall(
      "top", geometry::make_rectangle(Vec3(0, 0, 2 * radius + gap), Vec3(plate_half, 0, 0), Vec3(0, plate_half, 0)),
      Vec3::UnitZ()));
  const auto p = RollingLinearLaw::Params::deformable(modulus_wall, 1.0, wall_friction, 0.1);
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
  return top;
}

/// Overlap sum of the ball with the floor and the plate (both start at zero overlap), m.
double overlap_sum(const World& world, WallId top) { return 2 * radius - world.wall(top).reference_point.z(); }

/// Balls of radius 0.4-0.5 mm on a jittered nx x ny x nz lattice in the box [0, L]^3 spanned by it,
/// and six square walls around the box with outward normals; wall 2 * axis + (side > 0).
void lattice_in_box(World& world, int nx, int ny, int nz, unsigned seed) {
  const double spacing = 1.02e-3;  // m, > the largest diameter: no initial overlaps
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const double r = 0.4e-3 + 0.1e-3 * unit(rng);
        const Vec3 jitter = Vec3(unit(rng), unit(rng), unit(rng)) * (spacing - 2 * r) - Vec3::Constant(spacing / 2 - r);
        world.add_ball(ball_at(Vec3(i + 0.5, j + 0.5, k + 0.5) * spacing + jitter, Vec3::Zero(), r));
      }
  const Vec3 size = Vec3(nx, ny, nz) * spacing;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 n = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero();
      n[axis] = side;
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      // Walls 20 % wider than the box overlap at the edges, so no ball escapes when they move.
      u[a1] = 0.6 * size[a1];
      v[a2] = 0.6 * size[a2];
      Vec3 centre = size / 2;
      centre[axis] = side > 0 ? size[axis] : 0.0;
      world.add_wall(make_facet_wall("box", geometry::make_rectangle(centre, u, v), n, size[a1] * size[a2]));
    }
  const auto sand = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.1);
  // Frictionless walls: then the walls alone balance each other's normal forces in equilibrium.
  const auto smooth = RollingLinearLaw::Params::deformable(modulus_wall, 1.0, 0.0, 0.0);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(sand, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(smooth, "ball-facet"));
  world.update_time_step();
}

/// Largest |stress - target| / target of the servos over the next `steps` steps.
double worst_error_over(World& world, const std::vector<std::shared_ptr<ServoWall>>& servos, int steps) {
  double worst = 0.0;
  for (int s = 0; s < steps; ++s) {
    world.step();
    for (const auto& servo : servos)
      worst = std::max(worst, std::abs(servo->achieved_stress() - servo->target()) / servo->target());
  }
  return worst;
}

}  // namespace

TEST_CASE("servo: a plate on one ball settles at F*(1/k_top + 1/k_bot) without overshoot", "[physics][servo]") {
  WorldSettings s = dynamic_settings(2e-7);  // s; sqrt(m / 2 kn) = 4.7e-6 s
  s.local_damping = 0.7;
  World world(s);
  const WallId top = ball_between_plates(world, 0.02 * radius, 0.5);
  const double force = 1.0;  // N, F*
  ServoSettings settings;
  settings.target_stress = force / plate_area;  // 62500 Pa
  settings.max_speed = 0.5;                     // m/s: 1e-7 m = 2e-4 R per step
  settings.settle_tolerance = 1e-4;
  auto servo = add_servo_wall(world, top, settings);

  // Per step, the stress change is the plate's (servo) part plus the ball's: the ball moving up
  // by dz raises the top overlap by dz. Removing the ball's part leaves the servo's, which must
  // oppose the error and remove at most alpha_s of it (exactly alpha_s when uncapped).
  const double alpha = settings.relaxation;
  double previous_error = 0.0, previous_z = 0.0;
  bool previous_touching = false, previous_capped = true;
  double least_removed = 1.0, most_removed = 0.0, worst_uncapped = 0.0;
  int compared = 0, uncapped = 0;
  for (int k = 0; k < 20000; ++k) {
    const double z = world.particles().x[0].z();  // m, where this step's forces are computed
    world.step();
    const double error = servo->achieved_stress() - settings.target_stress;  // Pa
    const bool touching = world.wall(top).contact_count == 1;
    // Below 1e-3 Pa (1.6e-8 relative) the ratio is round-off.
    if (touching && previous_touching && std::abs(previous_error) > 1e-3) {
      const double servo_part = error - previous_error - kn_wall / plate_area * (z - previous_z);
      const double removed = -servo_part / previous_error;  // fraction of the error removed by the plate
      least_removed = std::min(least_removed, removed);
      most_removed = std::max(most_removed, removed);
      ++compared;
      if (!previous_capped) {
        worst_uncapped = std::max(worst_uncapped, std::abs(removed - alpha));
        ++uncapped;
      }
    }
    previous_error = error;
    previous_z = z;
    previous_touching = touching;
    previous_capped = std::abs(servo->normal_speed()) >= settings.max_speed;
  }
  const double expected = force * (1 / kn_wall + 1 / kn_wall);  // m, 6.37e-5 (= 0.13 R)
  // Local damping removes the ball's oscillation (period 3e-5 s) over 4e-3 s: round-off is left.
  CHECK(overlap_sum(world, top) == Approx(expected).epsilon(1e-3));
  CHECK(servo->achieved_stress() == Approx(settings.target_stress).epsilon(1e-4));
  CHECK(servo->settled());
  CHECK(servo->gain() == Approx(alpha * plate_area / (kn_wall * world.time_step())).epsilon(1e-12));
  CHECK(servo->normal_displacement() == Approx(-(0.02 * radius + expected)).epsilon(1e-3));
  REQUIRE(compared > 1000);
  REQUIRE(uncapped > 1000);
  // The plate never pushes the error past zero; 1e-6 is round-off in the ball's part.
  CHECK(least_removed >= -1e-6);
  CHECK(most_removed <= alpha + 1e-6);
  CHECK(worst_uncapped < 1e-6);
}

TEST_CASE("servo: a target given as a function of time is tracked during a slow ramp", "[physics][servo]") {
  WorldSettings s = dynamic_settings(2e-7);  // s
  s.local_damping = 0.7;
  World world(s);
  const WallId top = ball_between_plates(world, 0.0, 0.5);
  const double force = 1.0, ramp = 2e-3;  // N, s; the ramp is ~70 ball oscillation periods
  auto servo = add_servo_wall(world, top, {.target_stress = 0.0, .max_speed = 0.5});
  servo->set_target_function([&](double t) { return force / plate_area * std::min(t / ramp, 1.0); });
  for (double fraction : {0.25, 0.5, 0.75, 1.0}) {
    world.step(static_cast<std::int64_t>(0.25 * ramp / world.time_step()));
    const double target_force = force * std::min(world.time() / ramp, 1.0);  // N
    // The plate and the ball lag the ramp by a few steps of a 10^4-step ramp and by the damped
    // ball's response; 1 % bounds both.
    INFO("ramp fraction " << fraction);
    CHECK(servo->target() * plate_area == Approx(target_force).epsilon(1e-3));
    CHECK(overlap_sum(world, top) == Approx(2 * target_force / kn_wall).epsilon(0.01));
  }
}

TEST_CASE("servo: hold_position keeps the plate height while a tangential velocity shears it", "[physics][servo]") {
  WorldSettings s = dynamic_settings(2e-7);  // s
  s.local_damping = 0.7;
  World world(s);
  const WallId top = ball_between_plates(world, 0.0, 0.5);
  const double stress = 1.0 / plate_area;  // Pa, F* = 1 N
  auto servo = add_servo_wall(world, top, {.target_stress = stress, .max_speed = 0.5});
  world.step(10000);
  REQUIRE(servo->settled());
  const double height = world.wall(top).reference_point.z();
  const double shear_speed = 0.01;  // m/s
  world.wall(top).velocity = Vec3(shear_speed, 0, 0);
  servo->hold_position(true);
  servo->set_target(2 * stress);  // ignored while holding
  const int steps = 2000;
  world.step(steps);
  // Holding sets the normal speed to exactly zero; the shear motion is the user's velocity.
  CHECK(world.wall(top).reference_point.z() == height);
  CHECK(world.wall(top).displacement.x() == Approx(shear_speed * steps * world.time_step()).epsilon(1e-12));
  CHECK(world.wall(top).velocity.x() == shear_speed);
  CHECK_FALSE(servo->settled());
  // Released, the servo reaches the doubled target: both contacts then carry 2 N.
  servo->hold_position(false);
  world.step(10000);
  CHECK(servo->settled());
  CHECK(servo->achieved_stress() == Approx(2 * stress).epsilon(0.01));
  CHECK(overlap_sum(world, top) == Approx(2 * 2.0 / kn_wall).epsilon(0.01));
  CHECK(world.wall(top).velocity.x() == shear_speed);
}

TEST_CASE("servo: a top plate on a packing reaches, holds and follows its target", "[physics][servo]") {
  World world;
  lattice_in_box(world, 6, 6, 8, 3);  // 288 balls
  const WallId top = 5, bottom = 4;   // +z and -z walls
  const double target = 100e3;        // Pa
  ServoSettings settings;
  settings.target_stress = target;
  settings.max_speed = 0.2;  // m/s, ~2e-7 m per step against radii of 4e-4 m
  auto servo = add_servo_wall(world, top, settings);
  // The loose lattice collapses in bursts while it is pushed: "done" is on target and static.
  const auto settled = [&](const World& w) { return servo->settled() && w.unbalanced_force_ratio() < 1e-3; };

  REQUIRE(world.run_until(settled, 100, 200000));
  // settled() means 100 steps within 1 %; the static packing must stay within 1 % from then on.
  CHECK(worst_error_over(world, {servo}, 2000) < 0.01);
  // Frictionless side walls: in equilibrium the floor carries the plate's force (no gravity).
  CHECK(-world.wall(bottom).force.z() / world.wall(bottom).area == Approx(target).epsilon(0.02));
  const double compaction = servo->normal_displacement();

  servo->set_target(2 * target);
  CHECK_FALSE(servo->settled());
  REQUIRE(world.run_until(settled, 100, 200000));
  CHECK(worst_error_over(world, {servo}, 2000) < 0.01);
  CHECK(-world.wall(bottom).force.z() / world.wall(bottom).area == Approx(2 * target).epsilon(0.02));
  CHECK(servo->normal_displacement() < compaction);  // a higher stress compresses further
}

TEST_CASE("servo: six servo walls bring a cube of balls to a hydrostatic stress", "[physics][servo]") {
  World world;
  lattice_in_box(world, 6, 6, 6, 5);  // 216 balls
  const double target = 100e3;        // Pa
  std::vector<std::shared_ptr<ServoWall>> servos;
  for (WallId w = 0; w < 6; ++w)
    servos.push_back(add_servo_wall(world, w, {.target_stress = target, .max_speed = 0.1}));
  const auto all_settled = [&](const World& w) {
    return w.unbalanced_force_ratio() < 1e-3 &&
           std::all_of(servos.begin(), servos.end(), [](const auto& s) { return s->settled(); });
  };
  REQUIRE(world.run_until(all_settled, 100, 200000));
  CHECK(worst_error_over(world, servos, 2000) < 0.01);
  for (const auto& servo : servos) {
    INFO("wall " << servo->wall());
    CHECK(servo->achieved_stress() == Approx(target).epsilon(0.01));
  }
}

TEST_CASE("servo: bad settings are refused with the key and the value", "[servo][input]") {
  World world;
  world.add_wall(floor_wall(0.0, 1e-3));
  const ServoSettings good{.target_stress = 1e5, .max_speed = 0.1};
  auto bad = good;
  bad.target_stress = -1.0;
  CHECK_THROWS_WITH(add_servo_wall(world, 0, bad), Contains("target_stress") && Contains("-1"));
  bad = good;
  bad.relaxation = 0.0;
  CHECK_THROWS_WITH(add_servo_wall(world, 0, bad), Contains("relaxation") && Contains("(0, 1]"));
  bad.relaxation = 1.5;
  CHECK_THROWS_WITH(add_servo_wall(world, 0, bad), Contains("relaxation") && Contains("1.5"));
  bad = good;
  bad.max_speed = 0.0;
  CHECK_THROWS_WITH(ServoWall(0, bad), Contains("max_speed") && Contains("> 0"));
  bad = good;
  bad.gain_update_every = 0;
  CHECK_THROWS_WITH(ServoWall(0, bad), Contains("gain_update_every"));
  bad = good;
  bad.settle_steps = 0;
  CHECK_THROWS_WITH(ServoWall(0, bad), Contains("settle_steps"));
  CHECK_THROWS_WITH(add_servo_wall(world, 3, good), Contains("wall id") && Contains("3"));
  auto servo = add_servo_wall(world, 0, good);
  CHECK_THROWS_WITH(servo->set_target(-5.0), Contains("target_stress") && Contains("-5"));
  CHECK_THROWS_WITH(servo->set_target_function(nullptr), Contains("target function"));
  servo->set_target_function([](double) { return -2.0; });
  world.add_ball(ball_at(Vec3(0, 0, 2 * radius)));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<LinearLaw>(
                                                      LinearParams::deformable(modulus_wall, 1.0, 0.5), "ball-facet"));
  world.set_time_step(1e-7);
  CHECK_THROWS_WITH(world.step(), Contains("target function") && Contains("-2"));
}
