// Time integration: local damping (docs/model.md T7), free flight, and the instability stop.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

TEST_CASE("integration: local damping 0.7 leaves (1 - 0.7) of a constant force", "[physics][integration]") {
  WorldSettings s;
  s.time_step = 1e-5;
  s.local_damping = 0.7;
  s.gravity = Vec3(0, 0, -9.81);
  World world(s);
  world.add_ball(ball_at(Vec3::Zero()));
  world.step(1);  // from rest the force does no work yet: undamped first kick
  const double v1 = world.particles().v[0].z();
  world.step(1000);
  // a = (1 - alpha) g exactly once the ball moves along the force.
  CHECK((world.particles().v[0].z() - v1) / (1000 * s.time_step) == Approx(-0.3 * 9.81).epsilon(1e-12));
}

TEST_CASE("integration: free flight under gravity is exact for leapfrog", "[physics][integration]") {
  WorldSettings s = dynamic_settings(1e-5);
  s.gravity = Vec3(0, 0, -9.81);
  World world(s);
  world.add_ball(ball_at(Vec3::Zero(), Vec3(1.0, 0, 0.2)));
  world.step(1000);
  const double t = world.time();
  CHECK(world.particles().x[0].x() == Approx(1.0 * t).epsilon(1e-12));
  // leapfrog with v(-dt/2) = v0: z = v0 t - g t^2/2 - g t dt/2
  CHECK(world.particles().x[0].z() == Approx(0.2 * t - 0.5 * 9.81 * t * t - 0.5 * 9.81 * t * 1e-5).epsilon(1e-10));
}

TEST_CASE("instability: a time step far above the stable one stops the run with a diagnosis", "[physics][integration]") {
  World world(dynamic_settings(1e-3));  // ~100x the critical step of these contacts
  world.add_ball(ball_at(Vec3::Zero(), Vec3(0.5, 0, 0)));
  world.add_ball(ball_at(Vec3(2.1 * radius, 0, 0), Vec3(-0.5, 0, 0)));
  world.set_contact_model(ContactKind::BallBall,
                          make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1, 0.5), "ball-ball"));
  try {
    world.step(20);
    FAIL("the run should have stopped");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK_THAT(msg, Contains("ball id") && Contains("step") && Contains("time step") && Contains("stable estimate"));
    CHECK(world.step_count() < 5);
  }
}

TEST_CASE("instability: the overlap limit is a setting that a loaded world can raise", "[physics][integration]") {
  // Two balls at rest, overlapping by 0.4 of their radius, with the contact law switched off
  // (zero stiffness is not allowed, so a tiny one): nothing moves, only the limit decides.
  WorldSettings s = dynamic_settings(1e-6);
  s.max_overlap_ratio = 0.3;
  World world(s);
  world.add_ball(ball_at(Vec3::Zero()));
  world.add_ball(ball_at(Vec3(1.6 * radius, 0, 0)));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(LinearParams::constant(1e-12, 1e-12, 0.5), "ball-ball"));
  CHECK_THROWS_AS(world.step(1), InstabilityError);
  world.set_max_overlap_ratio(0.5);
  CHECK_NOTHROW(world.step(10));
  CHECK_THROWS_WITH(world.set_max_overlap_ratio(0.0), Contains("max_overlap_ratio"));
  CHECK_THROWS_WITH(world.set_max_overlap_ratio(std::nan("")), Contains("max_overlap_ratio"));
}
