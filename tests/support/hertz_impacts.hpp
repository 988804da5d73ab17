// Single impacts under the Hertz-Mindlin law (docs/model.md 1.4), shared by the tests that check
// it against Chung & Ooi's (2011) benchmarks: tests/physics/test_hertz_mindlin.cpp (tests 1-3,
// the time step, the SIMD blocks) and tests/physics/test_hertz_oblique.cpp (tests 4-8).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "support/scenes.hpp"

namespace dem::testing::hertz_impacts {

inline constexpr double youngs = 7e10;  // Pa
inline constexpr double poisson = 0.25;
inline constexpr double effective_modulus = youngs / (2.0 * (1.0 - poisson * poisson));  // E* = 3.7333e10 Pa
// 2 * integral_0^1 dx / sqrt(1 - x^(5/2)): Hertz's duration in units of delta_max / v0 [Johnson
// 1985, 11.2], numerically to 10 digits; 2.8683 (m*^2 / (R* E*^2 v0))^(1/5) is the same to 4.
inline constexpr double hertz_duration_factor = 2.943275184;

struct Impact {
  double contact_time = 0.0;  // s, steps with a positive elastic normal force, times dt
  double max_overlap = 0.0;   // m
  double max_force = 0.0;     // N, elastic normal force
  Vec3 velocity{Vec3::Zero()};          // m/s, after the impact: of ball 1 relative to ball 0, or of the ball on the wall
  Vec3 angular_velocity{Vec3::Zero()};  // rad/s, of the ball on the wall
};

/// Hertz's maximum overlap of an elastic impact at speed v0 (m* v0^2 / 2 = 8/15 E* sqrt(R*) delta^2.5).
inline double hertz_max_overlap(double m_eff, double r_eff, double v0, double modulus = effective_modulus) {
  return std::pow(15.0 * m_eff * v0 * v0 / (16.0 * modulus * std::sqrt(r_eff)), 0.4);
}

/// Hertz's duration of an elastic impact at normal speed v0.
inline double hertz_duration(double m_eff, double r_eff, double v0, double modulus = effective_modulus) {
  return hertz_duration_factor * hertz_max_overlap(m_eff, r_eff, v0, modulus) / v0;
}

/// Steps `world` through one impact: until the one contact whose elastic normal force
/// `normal_force(world)` reads (N; 0 when there is none) has been on and is off again, calling
/// `on_contact(force)` after each step it is on.
template <class NormalForce, class OnContact>
void step_through_impact(World& world, NormalForce normal_force, OnContact on_contact) {
  bool touched = false;
  for (int s = 0; s < 1000000; ++s) {
    world.step();
    const double force = normal_force(world);
    if (!(force > 0.0)) {
      if (touched) return;
      continue;
    }
    touched = true;
    on_contact(force);
  }
}

/// The elastic normal force of a World's one ball-ball contact (0: none).
inline double pair_force(const World& world) {
  const PairContacts& c = world.pair_contacts(ContactKind::BallBall);
  return c.size() == 1 ? c.normal_force[0] : 0.0;
}

/// Two equal balls meeting head-on at relative speed v0, with the law `p` between them.
inline Impact two_spheres(const HertzMindlinParams& p, double v0, double dt) {
  World world(dynamic_settings(dt));
  world.add_ball(ball_at(Vec3::Zero(), Vec3(0.5 * v0, 0, 0)));
  world.add_ball(ball_at(Vec3(2 * radius + 2 * v0 * dt, 0, 0), Vec3(-0.5 * v0, 0, 0)));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<HertzMindlinLaw>(p, "ball-ball"));
  Impact r;
  step_through_impact(world, pair_force, [&](double force) {
    r.contact_time += dt;
    r.max_force = std::max(r.max_force, force);
    const ParticleStore& b = world.particles();
    r.max_overlap = std::max(r.max_overlap, 2 * radius - (b.x[1] - b.x[0]).norm());
  });
  const ParticleStore& b = world.particles();
  r.velocity = b.v[b.index_of(1)] - b.v[b.index_of(0)];
  return r;
}

/// A ball falling onto a facet floor at velocity `v` (no gravity) spinning at `w`, the law `p`
/// between them.
inline Impact sphere_on_wall(const HertzMindlinParams& p, const Vec3& v, double dt, const Vec3& w = Vec3::Zero()) {
  World world(dynamic_settings(dt));
  BallSpec ball = ball_at(Vec3(0, 0, radius - 2 * v.z() * dt), v);
  ball.angular_velocity = w;
  world.add_ball(ball);
  world.add_wall(floor_wall(0.0, 0.01));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<HertzMindlinLaw>(p, "ball-facet"));
  Impact r;
  const auto wall_force = [](const World& stepped) {
    const WallContacts& c = stepped.state().contacts.ball_facet;
    return c.size() == 1 ? c.normal_force[0] : 0.0;
  };
  step_through_impact(world, wall_force, [&](double force) {
    r.contact_time += dt;
    r.max_force = std::max(r.max_force, force);
    r.max_overlap = std::max(r.max_overlap, radius - world.particles().x[0].z());
  });
  r.velocity = world.particles().v[0];
  r.angular_velocity = world.particles().w[0];
  return r;
}

/// A ball after an impact.
struct Rebound {
  Vec3 velocity{Vec3::Zero()};          // m/s
  Vec3 angular_velocity{Vec3::Zero()};  // rad/s
};

/// Two balls, `first` at the origin and `second` on +x, about to touch (their positions are set
/// here: the gap closes in two steps), with the law `p` between them; each one after the impact.
inline std::array<Rebound, 2> spheres_meeting(const HertzMindlinParams& p, BallSpec first, BallSpec second, double dt) {
  const double closing = first.velocity.x() - second.velocity.x();  // m/s, > 0
  first.position = Vec3::Zero();
  second.position = Vec3(first.radius + second.radius + 2 * closing * dt, 0, 0);
  World world(dynamic_settings(dt));
  world.add_ball(first);
  world.add_ball(second);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<HertzMindlinLaw>(p, "ball-ball"));
  step_through_impact(world, pair_force, [](double) {});
  const ParticleStore& b = world.particles();
  std::array<Rebound, 2> r;
  for (int k = 0; k < 2; ++k) {
    const std::size_t i = b.index_of(static_cast<ParticleId>(k));
    r[static_cast<std::size_t>(k)] = {b.v[i], b.w[i]};
  }
  return r;
}

}  // namespace dem::testing::hertz_impacts
