// Local damping against a moving frame (docs/model.md 3.1, DampingFrame): the sign that decides
// between (1 - alpha) and (1 + alpha) is that of the force times the velocity relative to the
// frame, for balls, clumps and spins. Each check is the exact leapfrog increment of a constant
// force, as test T7.
#include <catch2/catch.hpp>

#include <dem/lab/toolkit/shear_cell.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

WorldSettings damped_settings(const Vec3& gravity) {
  WorldSettings s;
  s.time_step = 1e-5;
  s.local_damping = 0.7;
  s.gravity = gravity;
  return s;
}

}  // namespace

TEST_CASE("damping frame: a uniform frame moving faster than a ball brakes its fall by (1 + alpha)",
          "[physics][integration]") {
  World world(damped_settings(Vec3(0, 0, -9.81)));
  world.add_ball(ball_at(Vec3::Zero()));
  DampingFrame frame;
  frame.velocity = Vec3(0, 0, -1.0);  // the ball moves up relative to it while slower than 1 m/s
  world.set_damping_frame(frame);
  world.step(1000);
  // Gravity opposes the relative velocity from the first step: a = (1 + alpha) g exactly.
  CHECK(world.particles().v[0].z() == Approx(-1.7 * 9.81 * 1000 * 1e-5).epsilon(1e-12));
  // The fixed frame again: the ball moves along gravity, (1 - alpha) g (test T7).
  world.set_damping_frame({});
  const double v0 = world.particles().v[0].z();
  world.step(1000);
  CHECK((world.particles().v[0].z() - v0) / (1000 * 1e-5) == Approx(-0.3 * 9.81).epsilon(1e-12));
}

TEST_CASE("damping frame: in a sheared frame each ball is damped against the field at its height",
          "[physics][integration]") {
  World world(damped_settings(Vec3(9.81, 0, 0)));  // a constant force along +x on every ball
  const ParticleId ahead = world.add_ball(ball_at(Vec3(0, 0, 0.01)));    // the frame moves at -1 m/s here
  const ParticleId behind = world.add_ball(ball_at(Vec3(0, 0.1, -0.01)));  // +1 m/s here
  DampingFrame frame;
  frame.height = 0.0;
  frame.velocity_gradient = Vec3(-100.0, 0, 0);  // 1/s
  world.set_damping_frame(frame);
  world.step(1000);
  const double t = 1000 * 1e-5;
  // Relative speeds stay well inside +-1 m/s, so each sign holds for every step.
  const ParticleStore& p = world.particles();
  CHECK(p.v[p.index_of(ahead)].x() == Approx(0.3 * 9.81 * t).epsilon(1e-12));
  CHECK(p.v[p.index_of(behind)].x() == Approx(1.7 * 9.81 * t).epsilon(1e-12));
}

TEST_CASE("damping frame: clumps are damped against the field, and spins against half its vorticity",
          "[physics][integration]") {
  World world(damped_settings(Vec3::Zero()));
  ClumpSpec spec;
  spec.pebbles = {{Vec3(0, 0, 0.01), 1e-3}};  // one pebble: isotropic inertia, no gyroscopic term
  spec.with_pebble_mass(2650.0);
  world.add_clump(spec);
  Clump& clump = world.clumps()[0];
  clump.applied_force = Vec3(1e-3, 0, 0);
  clump.applied_torque = Vec3(0, 1e-9, 0);
  DampingFrame frame;
  frame.velocity_gradient = Vec3(-100.0, 0, 0);  // the field moves at -1 m/s at the clump, spins at -50 rad/s about y
  REQUIRE(frame.spin().isApprox(Vec3(0, -50.0, 0)));
  world.set_damping_frame(frame);
  world.step(1000);
  const double t = 1000 * 1e-5;
  const Clump& c = world.clumps()[0];
  const double inertia = c.inertia_body(1, 1);
  // Force and torque both point along the motion relative to the field: (1 - alpha) of each.
  CHECK(c.v.x() == Approx(0.3 * 1e-3 / c.mass * t).epsilon(1e-12));
  CHECK(c.w.y() == Approx(0.3 * 1e-9 / inertia * t).epsilon(1e-12));
}

TEST_CASE("damping frame: non-finite frames are refused naming the setting", "[physics][integration]") {
  World world;
  DampingFrame frame;
  frame.height = std::nan("");
  CHECK_THROWS_WITH(world.set_damping_frame(frame), Catch::Matchers::Contains("damping frame"));
}

TEST_CASE("damping frame: the plates' field takes each plate's velocity at its height", "[lab][integration]") {
  World world(damped_settings(Vec3::Zero()));
  lab::ShearCellSpec spec;
  const lab::ShearCell cell = lab::build_shear_cell(world, spec);
  world.wall(cell.bottom).velocity = Vec3(0.02, 0.01, 0.001);
  world.wall(cell.top).velocity = Vec3(-0.01, 0, 0.003);
  world.step(10);  // both plates move, up too: the field is taken where they are now
  const DampingFrame frame = lab::plate_damping_frame(world, cell);
  const double z_bottom = world.wall(cell.bottom).displacement.z();
  const double z_top = z_bottom + cell.plate_gap(world);
  REQUIRE(z_bottom == Approx(0.001 * 10 * 1e-5).epsilon(1e-12));
  CHECK((frame.velocity_at(Vec3(0.01, 0, z_bottom)) - Vec3(0.02, 0.01, 0.001)).norm() < 1e-15);
  CHECK((frame.velocity_at(Vec3(0, -0.02, z_top)) - Vec3(-0.01, 0, 0.003)).norm() < 1e-15);
  const Vec3 middle = frame.velocity_at(Vec3(0, 0, 0.5 * (z_bottom + z_top)));
  CHECK((middle - Vec3(0.005, 0.005, 0.002)).norm() < 1e-15);
}
