// Two equal balls, head-on, linear law (docs/model.md T1, T2): contact duration, restitution, force
// direction, against the closed-form solution of a linear spring-dashpot oscillator.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

struct ImpactResult {
  double contact_time;   // s
  double restitution;    // -
  double max_overlap;    // m
  bool force_along_normal = true;
};

ImpactResult head_on(double damping_ratio, double dt) {
  World world(dynamic_settings(dt));
  const double v0 = 0.1;  // m/s relative
  world.add_ball(ball_at(Vec3(0, 0, 0), Vec3(0.5 * v0, 0, 0)));
  world.add_ball(ball_at(Vec3(2 * radius + 1e-6, 0, 0), Vec3(-0.5 * v0, 0, 0)));
  LinearParams p = LinearParams::deformable(modulus_ball, 1.0, 0.0);
  p.normal_damping_ratio = damping_ratio;
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(p, "ball-ball"));

  ImpactResult r{0.0, 0.0, 0.0};
  bool touched = false;
  for (int s = 0; s < 200000; ++s) {
    world.step();
    const auto& c = world.pair_contacts(ContactKind::BallBall);
    const bool touching = c.size() == 1 && c.normal_force[0] > 0.0;
    if (touching) {
      touched = true;
      r.contact_time += dt;
      // force on piece 2 (the ball on the right) must push it along +x
      if (c.force[0].x() <= 0.0 && c.normal_force[0] > 1e-9) r.force_along_normal = false;
      const auto& pa = world.particles();
      r.max_overlap = std::max(r.max_overlap, 2 * radius - (pa.x[1] - pa.x[0]).norm());
    } else if (touched) {
      break;
    }
  }
  const auto& pa = world.particles();
  const std::size_t left = pa.index_of(0), right = pa.index_of(1);
  r.restitution = (pa.v[right].x() - pa.v[left].x()) / v0;
  return r;
}

}  // namespace

TEST_CASE("linear law: undamped head-on impact lasts pi sqrt(m_eff/kn) and restitutes fully", "[physics][contact]") {
  const double kn = pi * radius * modulus_ball / 2.0;  // deformability, equal balls: 41626 N/m
  const double m_eff = ball_mass() / 2.0;
  const double t_c = pi * std::sqrt(m_eff / kn);  // 1.28255e-5 s
  const double dt = t_c / 2000.0;
  const ImpactResult r = head_on(0.0, dt);
  CHECK(kn == Approx(41626.1).epsilon(1e-5));
  // The measured duration is a whole number of steps: error below 2 dt = 0.1 % of t_c; 1 % asked.
  CHECK(r.contact_time == Approx(t_c).epsilon(0.01));
  CHECK(r.contact_time == Approx(t_c).margin(2 * dt));
  // Leapfrog is symplectic: the energy error is O((omega dt)^2) ~ 1e-6 here.
  CHECK(r.restitution == Approx(1.0).epsilon(1e-4));
  CHECK(r.max_overlap == Approx(0.1 * std::sqrt(m_eff / kn)).epsilon(1e-3));  // 4.0825e-7 m
  CHECK(r.force_along_normal);
}

TEST_CASE("linear law: damped head-on impact gives the analytic restitution and duration", "[physics][contact]") {
  const double kn = pi * radius * modulus_ball / 2.0;
  const double m_eff = ball_mass() / 2.0;
  for (double beta : {0.1, 0.3}) {
    const double expected_e = std::exp(-pi * beta / std::sqrt(1 - beta * beta));     // 0.72925, 0.37233
    const double expected_t = pi / std::sqrt(kn / m_eff * (1 - beta * beta));         // 1.28901e-5, 1.34448e-5
    const double dt = expected_t / 2000.0;
    const ImpactResult r = head_on(beta, dt);
    // The dashpot acts on half-step velocities: an O(dt/t_c) = 5e-4 relative error; 0.5 % allowed.
    CHECK(r.restitution == Approx(expected_e).epsilon(5e-3));
    CHECK(r.contact_time == Approx(expected_t).epsilon(0.01));
  }
}
