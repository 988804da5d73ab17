// Hertz-Mindlin's rolling resistance (docs/model.md 1.4, the key `rolling`): a ball rolling without
// slip on a facet floor slows at the analytic (5/7) mu_r g and stops after v0^2 / (2 a) under
// every model, LIGGGHTS's constant directional torque (cdt), the epsd2 spring and LAMMPS's sds
// spring at their cap mu_r R |F_n| (a solid sphere, F_t the floor's friction along the motion:
// m dv/dt = F_t and (2/5) m R dv/dt = -(F_t + mu_r m g) R, so dv/dt = -(5/7) mu_r g). Below the
// cap, sds's spring is k_roll R*^2 whatever the overlap, epsd's k_t R*^2 = 8 G* sqrt(R* delta) R*^2.
// The SIMD blocks against one contact at a time with cdt are in test_hertz_mindlin.cpp.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using Catch::Matchers::Contains;
using namespace dem::testing;

namespace {

constexpr double gravity = 9.81;  // m/s^2
constexpr double v0 = 0.01;       // m/s, the rolling speed at the start
constexpr double mu_r = 0.1;

struct Rolled {
  double stop_time = 0.0;      // s, the first step at which the ball's speed is no longer forward
  double stop_distance = 0.0;  // m, travelled by then
  double deceleration = 0.0;   // m/s^2, from the speeds at a quarter and three quarters of the expected stop
};

constexpr double sds_stiffness = 1e3;  // N/m: at its cap within a step (theta = mu_r m g / (k_roll R) = 7e-7 rad)

Rolled roll(HertzRolling model) {
  // E = 1e8 Pa: the ball's contact period under its weight is about 3e-4 s, 170 steps of 2e-6 s.
  auto p = HertzMindlinParams::material(1e8, 0.25, 0.5, 0.5, mu_r);
  p.rolling = model;
  if (model == HertzRolling::sds) p.rolling_stiffness = sds_stiffness;
  const double dt = 2e-6;
  WorldSettings s = dynamic_settings(dt);
  s.gravity = Vec3(0, 0, -gravity);
  World world(s);
  // At rest on the floor at Hertz's overlap under its weight, rolling without slip along x.
  const double weight = ball_mass() * gravity;
  const double overlap = std::pow(3.0 * weight / (4.0 * p.effective_modulus * std::sqrt(radius)), 2.0 / 3.0);
  BallSpec ball = ball_at(Vec3(0, 0, radius - overlap), Vec3(v0, 0, 0));
  ball.angular_velocity = Vec3(0, v0 / radius, 0);
  world.add_ball(ball);
  world.add_wall(floor_wall(0.0, 0.05));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<HertzMindlinLaw>(p, "ball-facet"));
  const double expected_stop = v0 / (5.0 / 7.0 * mu_r * gravity);
  const long quarter = std::lround(0.25 * expected_stop / dt), three_quarters = std::lround(0.75 * expected_stop / dt);
  Rolled r;
  double v_quarter = 0.0, v_three_quarters = 0.0;
  for (long step = 1; step <= 8 * quarter; ++step) {  // twice the expected stop
    world.step();
    const double v = world.particles().v[0].x();
    if (step == quarter) v_quarter = v;
    if (step == three_quarters) v_three_quarters = v;
    if (v <= 0.0) {
      r.stop_time = static_cast<double>(step) * dt;
      r.stop_distance = world.particles().x[0].x();
      break;
    }
  }
  r.deceleration = (v_quarter - v_three_quarters) / (static_cast<double>(three_quarters - quarter) * dt);
  return r;
}

}  // namespace

TEST_CASE("hertz-mindlin rolling: a ball rolling on a plane slows at (5/7) mu_r g and stops where that says, "
          "for cdt, epsd and sds",
          "[physics][contact][hertz][rolling]") {
  const double a = 5.0 / 7.0 * mu_r * gravity;  // 0.7007 m/s^2
  const double stop_time = v0 / a, stop_distance = v0 * v0 / (2.0 * a);  // 0.0143 s, 71 um
  for (HertzRolling model : {HertzRolling::cdt, HertzRolling::epsd, HertzRolling::sds}) {
    const Rolled r = roll(model);
    INFO(to_string(model) << ": deceleration " << r.deceleration << " / " << a << ", stop time " << r.stop_time
                          << " / " << stop_time << ", distance " << r.stop_distance << " / " << stop_distance);
    // The torque is mu_r R |F_n| with |F_n| = m g, the ball started at rest at its static overlap
    // (measured: the deceleration within 2e-5, the stop within one step of 2e-6 s, 1.4e-4 of the
    // stop time, the distance within 2e-4; epsd's spring reaches its cap within a step, its
    // k_r theta = mu_r R m g at theta = 7e-6 rad).
    CHECK(r.deceleration == Approx(a).epsilon(1e-4));
    CHECK(r.stop_time == Approx(stop_time).epsilon(3e-4));
    CHECK(r.stop_distance == Approx(stop_distance).epsilon(5e-4));
  }
}

namespace {

/// The rolling moment on the floor after `steps` steps of a ball held at `overlap` on it, spinning
/// at `spin` (rad/s) about y, nothing else moving: a bend rotation of spin x steps x dt.
double held_moment(HertzRolling model, double overlap, double spin, int steps, double dt) {
  auto p = HertzMindlinParams::material(1e8, 0.25, 0.5, 0.5, 0.5);  // mu_r 0.5: far from the cap
  p.rolling = model;
  if (model == HertzRolling::sds) p.rolling_stiffness = sds_stiffness;
  World world(dynamic_settings(dt));
  BallSpec ball = ball_at(Vec3(0, 0, radius - overlap));
  ball.angular_velocity = Vec3(0, spin, 0);
  ball.fixed = dof_all;  // velocity and spin held
  world.add_ball(ball);
  world.add_wall(floor_wall(0.0, 0.05));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<HertzMindlinLaw>(p, "ball-facet"));
  world.step(steps);
  return world.state().contacts.ball_facet.moment.at(0).norm();
}

}  // namespace

TEST_CASE("hertz-mindlin rolling: below its cap the sds spring is k_roll R*^2 at any overlap, epsd's k_t R*^2",
          "[physics][contact][hertz][rolling]") {
  const double dt = 1e-7, spin = 1e-3;  // rad/s: 100 steps turn the ball 1e-8 rad
  const int steps = 100;
  const double theta = spin * steps * dt;
  const auto p = HertzMindlinParams::material(1e8, 0.25, 0.5, 0.5, 0.5);
  for (const double overlap : {1e-6, 4e-6}) {  // m: the moment's cap mu_r R F_n is 1e4 times above it
    // R* = R against a wall; each step adds k R^2 spin dt: the sum of 100 equal increments, 1e-12.
    CHECK(held_moment(HertzRolling::sds, overlap, spin, steps, dt) ==
          Approx(sds_stiffness * radius * radius * theta).epsilon(1e-12));
    const double k_t = 8.0 * p.effective_shear_modulus * std::sqrt(radius * overlap);
    CHECK(held_moment(HertzRolling::epsd, overlap, spin, steps, dt) == Approx(k_t * radius * radius * theta).epsilon(1e-12));
  }
}

TEST_CASE("hertz-mindlin rolling: a rolling stiffness is refused but with sds, and needed with it", "[contact][hertz][rolling]") {
  auto p = HertzMindlinParams::material(1e8, 0.25, 0.5, 0.5, 0.1);
  p.rolling_stiffness = 1e3;
  CHECK_THROWS_WITH(p.validate("ball_ball"), Contains("ball_ball.rolling_stiffness") && Contains("rolling = sds"));
  p.rolling = HertzRolling::sds;
  CHECK_NOTHROW(p.validate("ball_ball"));
  p.rolling_stiffness = 0.0;
  CHECK_THROWS_WITH(p.validate("ball_ball"), Contains("ball_ball.rolling_stiffness") && Contains("> 0"));
}
