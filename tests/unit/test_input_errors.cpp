// Bad input throws InputError naming the quantity and the value.
#include <catch2/catch.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

TEST_CASE("input: bad ball, law and world parameters are refused with the key and value", "[input]") {
  World world;
  BallSpec b = ball_at(Vec3::Zero());
  b.radius = 0.0;
  CHECK_THROWS_WITH(world.add_ball(b), Contains("radius") && Contains("= 0"));
  b = ball_at(Vec3::Zero());
  b.density = -2650.0;
  CHECK_THROWS_WITH(world.add_ball(b), Contains("density") && Contains("-2650"));
  CHECK_THROWS_WITH(make_contact_model<LinearLaw>(LinearParams::deformable(-5e7, 1.0, 0.5), "ball-ball"),
                    Contains("ball-ball.effective_modulus") && Contains("-50000000"));
  CHECK_THROWS_WITH(make_contact_model<LinearLaw>(LinearParams::deformable(5e7, 1.0, -0.1), "ball-ball"),
                    Contains("friction") && Contains("-0.1"));
  CHECK_THROWS_WITH(make_contact_model<RollingLinearLaw>(RollingLinearLaw::Params::deformable(5e7, 1.0, 0.5, -1.0)),
                    Contains("rolling_friction") && Contains("-1"));
  WorldSettings s;
  s.time_step = -1e-6;
  CHECK_THROWS_WITH(World(s), Contains("time_step") && Contains("-1e-06"));
  CHECK_THROWS_WITH(world.set_time_step(0.0), Contains("time_step") && Contains("> 0"));
  s = WorldSettings{};
  s.local_damping = 1.5;
  CHECK_THROWS_WITH(World(s), Contains("local_damping") && Contains("1.5"));
  CHECK_THROWS_AS(world.add_ball(b), InputError);
}

TEST_CASE("input: contacts without a contact model stop the run with a clear message", "[input]") {
  World world(dynamic_settings(1e-7));
  world.add_ball(ball_at(Vec3::Zero()));
  world.add_ball(ball_at(Vec3(1.5 * radius, 0, 0)));
  CHECK_THROWS_WITH(world.step(), Contains("no contact model set for ball-ball"));
}
