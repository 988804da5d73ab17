// Rolling resistance (docs/model.md T4, T5): the rolling spring and its cap at the law level, and a
// ball rolling on a facet under gravity that decelerates at (5/7) mu_r g and stops at
// v0^2 / (2 a). With mu_r = 0 rolling is not resisted by the law.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

TEST_CASE("rolling-linear law: moment grows as kr theta up to mu_r Rbar Fn, twist is free", "[physics][contact]") {
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.18);
  ContactKinematics k{};
  k.normal = Vec3::UnitX();
  k.radius_1 = k.radius_2 = radius;
  k.effective_radius = radius / 2;  // 2.5e-4 m
  k.effective_mass = ball_mass() / 2;
  k.kind = ContactKind::BallBall;
  const double kn = pi * radius * modulus_ball / 2;
  k.overlap = 1.0 / kn;  // Fn = 1 N
  k.relative_velocity = Vec3::Zero();
  const double kr = kn * k.effective_radius * k.effective_radius;  // 2.60163e-3 N m/rad
  const double cap = 0.18 * k.effective_radius * 1.0;               // 4.5e-5 N m
  CHECK(kr == Approx(2.60163e-3).epsilon(1e-5));
  const double dtheta = 1e-4, dt = 1e-6;
  k.dt = dt;
  k.relative_angular_velocity = Vec3(0, dtheta / dt, 0);  // bend, perpendicular to n
  RollingLinearLaw::State state;
  double theta = 0.0;
  for (int s = 0; s < 400; ++s) {
    const ContactForce f = RollingLinearLaw::force(p, k, state);
    theta += dtheta;
    const double m = -f.moment.y();
    if (theta < cap / kr - dtheta) CHECK(m == Approx(kr * theta).epsilon(1e-9));
    if (theta > cap / kr + dtheta) CHECK(m == Approx(cap).epsilon(1e-12));
    CHECK(std::abs(f.moment.x()) < 1e-20);
  }
  RollingLinearLaw::State twist;
  k.relative_angular_velocity = Vec3(5.0, 0, 0);  // about n
  CHECK(RollingLinearLaw::force(p, k, twist).moment.norm() == 0.0);
}

namespace {

struct RollResult {
  double stop_time;  // s, first time the speed reaches zero
  double distance;   // m
  double speed_at_end;
};

RollResult roll_on_floor(double mu_r, double duration) {
  const double dt = 5e-7, g = 9.81, v0 = 0.1;
  WorldSettings s = dynamic_settings(dt);
  s.gravity = Vec3(0, 0, -g);
  World world(s);
  const double kn = pi * radius * modulus_wall;
  const double rest_overlap = ball_mass() * g / kn;  // start in normal equilibrium
  BallSpec b = ball_at(Vec3(0, 0, radius - rest_overlap), Vec3(v0, 0, 0));
  b.angular_velocity = Vec3(0, v0 / radius, 0);  // pure rolling along +x
  world.add_ball(b);
  world.add_wall(floor_wall(0.0, 0.05));
  auto p = RollingLinearLaw::Params::deformable(modulus_wall, 1.0, 0.9, mu_r);
  p.normal_damping_ratio = 0.5;
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
  RollResult r{-1.0, 0.0, 0.0};
  const auto steps = static_cast<std::int64_t>(duration / dt);
  for (std::int64_t k = 0; k < steps; ++k) {
    world.step();
    if (r.stop_time < 0 && world.particles().v[0].x() <= 0.0) {
      r.stop_time = world.time();
      r.distance = world.particles().x[0].x();
    }
  }
  r.speed_at_end = world.particles().v[0].x();
  if (r.stop_time < 0) r.distance = world.particles().x[0].x();
  return r;
}

}  // namespace

TEST_CASE("rolling-linear law: a rolling ball stops after v0^2/(2 (5/7) mu_r g)", "[physics][contact]") {
  const double g = 9.81, v0 = 0.1;
  for (double mu_r : {0.4, 0.9}) {
    const double a = 5.0 / 7.0 * mu_r * g;  // 2.80286 / 6.30643 m/s^2
    const RollResult r = roll_on_floor(mu_r, 1.2 * v0 / a);
    // The elastic pre-yield rotation is ~1e-10 rad, so the stop follows the rigid-plastic result;
    // 1 % covers the time step (5e-7 s against a 0.016-0.036 s stop time).
    CHECK(r.stop_time == Approx(v0 / a).epsilon(0.01));
    CHECK(r.distance == Approx(v0 * v0 / (2 * a)).epsilon(0.01));
  }
}

TEST_CASE("rolling-linear law: with mu_r = 0 a rolling ball keeps rolling", "[physics][contact]") {
  const RollResult r = roll_on_floor(0.0, 0.02);
  CHECK(r.stop_time < 0);
  // Only the contact-point offset (overlap/2 ~ 2e-10 m against R = 5e-4 m) perturbs pure rolling.
  CHECK(r.speed_at_end == Approx(0.1).epsilon(1e-5));
}
