// Coulomb slip of the linear law (docs/model.md T3), at the law level and through the engine: a block
// (a ball with rotation locked) on an incline sticks while tan(theta) < mu and otherwise slides
// with a = g (sin theta - mu cos theta).
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

ContactKinematics facet_contact(double overlap, const Vec3& sliding_velocity, double dt) {
  ContactKinematics k{};
  k.normal = -Vec3::UnitZ();  // the facet is below the ball
  k.overlap = overlap;
  k.relative_velocity = sliding_velocity;  // facet relative to ball
  k.relative_angular_velocity = Vec3::Zero();
  k.radius_1 = radius;
  k.radius_2 = 0.0;
  k.effective_radius = radius;
  k.effective_mass = ball_mass();
  k.dt = dt;
  k.kind = ContactKind::BallFacet;
  return k;
}

}  // namespace

TEST_CASE("linear law: shear force is elastic below mu Fn, capped at mu Fn, unloads with ks", "[physics][contact]") {
  const LinearParams p = LinearParams::deformable(modulus_wall, 1.0, 0.9);
  const double kn = pi * radius * modulus_wall;  // ball-facet: rbar = L = R, 31415.9 N/m
  const double overlap = 1.0 / kn;               // Fn = 1 N
  const double du = 1e-7, dt = 1e-6;             // facet moved 0.1 um per step along +x
  LinearLaw::State state;
  const double u_star = 0.9 / kn;  // 2.8648e-5 m, ks = kn
  double u = 0.0;
  double max_shear = 0.0;
  for (int s = 0; s < 600; ++s) {
    const ContactForce f = LinearLaw::force(p, facet_contact(overlap, Vec3(du / dt, 0, 0), dt), state);
    u += du;
    const double shear = -f.force.x();  // the facet (piece 2) is held back against +x motion
    max_shear = std::max(max_shear, shear);
    CHECK(f.normal_force == Approx(1.0).epsilon(1e-12));
    if (u < u_star - du) CHECK(shear == Approx(kn * u).epsilon(1e-9));       // sticking: ks u
    if (u > u_star + du) CHECK(shear == Approx(0.9).epsilon(1e-12));         // sliding at mu Fn
  }
  CHECK(max_shear <= 0.9 * (1 + 1e-12));  // never above the limit
  // Reversal: elastic unloading with slope ks from the sliding value.
  const ContactForce back = LinearLaw::force(p, facet_contact(overlap, Vec3(-du / dt, 0, 0), dt), state);
  CHECK(-back.force.x() == Approx(0.9 - kn * du).epsilon(1e-9));
}

namespace {

/// Block on a plane tilted by `angle` about y; returns its speed after `duration` seconds.
double block_speed_on_incline(double angle, double mu, double duration) {
  const double dt = 2e-7;
  WorldSettings s = dynamic_settings(dt);
  const double g = 9.81;
  s.gravity = Vec3(g * std::sin(angle), 0, -g * std::cos(angle));  // tilt gravity instead of the plane
  World world(s);
  BallSpec b = ball_at(Vec3(0, 0, radius));
  b.fixed = dof_rotation;  // a block: no rolling
  world.add_ball(b);
  world.add_wall(floor_wall(0.0, 0.05));
  LinearParams p = LinearParams::deformable(modulus_wall, 1.0, mu);
  p.normal_damping_ratio = 0.7;  // settle the normal bounce quickly
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<LinearLaw>(p, "ball-facet"));
  world.step(static_cast<std::int64_t>(duration / dt));
  return world.particles().v[0].x();
}

}  // namespace

TEST_CASE("linear law: a block sticks on an incline below the friction angle and slides above it",
          "[physics][contact]") {
  const double mu = 0.5, g = 9.81, duration = 0.02;
  // Sticking at 20 deg (tan = 0.364 < 0.5): only the elastic creep of the shear spring, whose
  // speed is bounded by that of a free oscillation of amplitude mu Fn/ks: < 1e-3 m/s.
  CHECK(std::abs(block_speed_on_incline(20.0 * pi / 180, mu, duration)) < 1e-3);
  // Sliding at 35 deg: v = g (sin - mu cos) t after the start-up transient (< 1e-4 s).
  const double angle = 35.0 * pi / 180;
  const double expected = g * (std::sin(angle) - mu * std::cos(angle)) * duration;
  CHECK(block_speed_on_incline(angle, mu, duration) == Approx(expected).epsilon(0.01));
}
