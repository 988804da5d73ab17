// The Hertz-DMT law (contact/hertz_dmt_law.hpp) against DMT's analytic pull-off force
// F_po = 4 pi gamma R* (Derjaguin, Muller & Toporov 1975; LAMMPS's dmt): the tension of a contact
// as its overlap vanishes, the equilibrium overlap with no load, and a ball hanging under a
// ceiling that holds it while its weight is 2 % below F_po and lets it go when 2 % above, the
// contact breaking as the surfaces part (zero separation). With gamma = 0 the law is
// Hertz-Mindlin's, bit for bit.
#include <catch2/catch.hpp>

#include <cmath>

#include <dem/contact/hertz_dmt_law.hpp>
#include <dem/core/law_registry.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double youngs = 7e10;  // Pa, quartz-like
constexpr double poisson = 0.25;
constexpr double gravity = 9.81;  // m/s^2

HertzDmtParams dmt(double surface_energy, HertzDamping model = HertzDamping::liggghts) {
  HertzDmtParams p;
  p.hertz = HertzMindlinParams::material(youngs, poisson, 0.5, 0.5, 0.1, model);
  p.surface_energy = surface_energy;
  return p;
}

ContactKinematics head_on(double overlap, double r_eff, double normal_speed = 0.0) {
  ContactKinematics k{};
  k.normal = Vec3::UnitX();
  k.overlap = overlap;
  k.relative_velocity = Vec3(normal_speed, 0, 0);
  k.relative_angular_velocity = Vec3::Zero();
  k.radius_1 = k.radius_2 = 2 * r_eff;
  k.effective_radius = r_eff;
  k.effective_mass = ball_mass() / 2;
  k.dt = 1e-7;
  k.kind = ContactKind::BallBall;
  return k;
}

struct Hanging {
  bool attached = false;          // still touching the ceiling at the end
  double last_overlap = 0.0;      // m, at the last step the contact carried a force
  double last_normal = 0.0;       // N, its elastic normal force then (negative: tension)
  bool force_while_apart = false;  // a force on a step the surfaces were apart
  double drop = 0.0;              // m, how far the ball's centre moved down
};

/// A ball under a facet ceiling, gravity pulling it away, started at rest at the overlap where the
/// Hertz force balances F_po - W (or at DMT's no-load overlap when W > F_po).
Hanging hang(double weight_over_pull_off) {
  const double dt = 1e-7;  // s: the contact's period at these loads is about 4e-5 s
  const double weight = ball_mass() * gravity;
  const double gamma = weight / weight_over_pull_off / (4.0 * pi * radius);
  const HertzDmtParams p = dmt(gamma);
  const double e_star = p.hertz.effective_modulus, pull_off = p.pull_off_force(radius);
  // Held: at rest where Hertz's force is F_po - W; dropped: at rest at DMT's no-load overlap.
  const double hertz_load = weight < pull_off ? pull_off - weight : pull_off;
  const double overlap = std::pow(3.0 * hertz_load / (4.0 * e_star * std::sqrt(radius)), 2.0 / 3.0);
  WorldSettings s = dynamic_settings(dt);
  s.gravity = Vec3(0, 0, -gravity);
  World world(s);
  const double ceiling = 0.0;  // m, the facet's plane
  world.add_ball(ball_at(Vec3(0, 0, ceiling - radius + overlap)));
  world.add_wall(make_facet_wall("ceiling", geometry::make_rectangle(Vec3(0, 0, ceiling), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0)),
                                 Vec3::UnitZ()));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<HertzDmtLaw>(p, "ball-facet"));
  const double z0 = world.particles().x[0].z();
  Hanging h;
  for (int step = 0; step < 20000; ++step) {  // 2 ms, some 50 periods of the contact
    // The overlap the step's forces see: the positions before it moves the ball.
    const double gap_overlap = radius - (ceiling - world.particles().x[0].z());
    world.step();
    const WallContacts& c = world.state().contacts.ball_facet;
    const bool loaded = c.size() == 1 && c.normal_force[0] != 0.0;
    h.attached = loaded;
    if (!loaded) continue;
    if (gap_overlap <= 0.0) h.force_while_apart = true;
    h.last_overlap = gap_overlap;
    h.last_normal = c.normal_force[0];
  }
  h.drop = z0 - world.particles().x[0].z();
  return h;
}

}  // namespace

TEST_CASE("hertz-dmt: the tension as the overlap vanishes is DMT's pull-off force 4 pi gamma R*",
          "[contact][physics][adhesion]") {
  const double gamma = 0.072;  // J/m^2, water's surface tension as an order of magnitude
  for (HertzDamping model : {HertzDamping::liggghts, HertzDamping::tsuji}) {
    const HertzDmtParams p = dmt(gamma, model);
    for (double r_eff : {radius / 2, radius}) {  // ball-ball of equal balls, ball-wall
      const double pull_off = 4.0 * pi * gamma * r_eff;
      HertzDmtLaw::State state{};
      const ContactForce touching = HertzDmtLaw::force(p, head_on(1e-15 * r_eff, r_eff), state);
      // Hertz's part at 1e-15 R* is 4/3 E* R*^2 1e-22.5: below 1e-9 of F_po.
      CHECK(touching.normal_force == Approx(-pull_off).epsilon(1e-9));
      CHECK(touching.force.x() == Approx(-pull_off).epsilon(1e-9));  // pulls piece 2 towards piece 1
      // No load at delta_0 = (3 F_po / (4 E* sqrt(R*)))^(2/3).
      const double e_star = p.hertz.effective_modulus;
      const double delta_0 = std::pow(3.0 * pull_off / (4.0 * e_star * std::sqrt(r_eff)), 2.0 / 3.0);
      state = {};
      CHECK(std::abs(HertzDmtLaw::force(p, head_on(delta_0, r_eff), state).normal_force) < 1e-12 * pull_off);
    }
  }
}

TEST_CASE("hertz-dmt: without surface energy it is Hertz-Mindlin, bit for bit", "[contact][physics][adhesion]") {
  for (HertzDamping model : {HertzDamping::liggghts, HertzDamping::tsuji}) {
    for (HertzRolling rolling : {HertzRolling::epsd, HertzRolling::cdt, HertzRolling::sds}) {
      INFO(to_string(model) << ", rolling " << to_string(rolling));
      HertzDmtParams p = dmt(0.0, model);
      p.hertz.rolling = rolling;
      if (rolling == HertzRolling::sds) p.hertz.rolling_stiffness = 50.0;  // N/m
      HertzDmtLaw::State dmt_state{};
      HertzMindlinLaw::State hm_state{};
      for (int step = 0; step < 50; ++step) {  // loading, sliding and rolling, the history carried over
        ContactKinematics k = head_on(1e-6 * (1 + step % 7), radius / 2, -0.01);
        k.relative_velocity += Vec3(0, 0.05 * std::sin(step), 0.02);
        k.relative_angular_velocity = Vec3(1.0, -2.0 * std::cos(step), 3.0);
        k.normal = Vec3(1.0, 0.01 * step, 0.0).normalized();
        const ContactForce a = HertzDmtLaw::force(p, k, dmt_state);
        const ContactForce b = HertzMindlinLaw::force(p.hertz, k, hm_state);
        CHECK(a.force == b.force);
        CHECK(a.moment == b.moment);
        CHECK(a.normal_force == b.normal_force);
      }
    }
  }
}

TEST_CASE("hertz-dmt: a ceiling holds a ball 2 % lighter than the pull-off force and drops one 2 % heavier, "
          "the contact breaking as the surfaces part",
          "[contact][physics][adhesion]") {
  const Hanging held = hang(0.98);
  INFO("held: drop " << held.drop << " m, last normal force " << held.last_normal << " N");
  CHECK(held.attached);
  CHECK(std::abs(held.drop) < 1e-9);  // stays within the overlap's scale (about 1e-10 m)
  CHECK_FALSE(held.force_while_apart);

  const Hanging dropped = hang(1.02);
  const double pull_off = ball_mass() * gravity / 1.02;
  INFO("dropped: drop " << dropped.drop << " m, last overlap " << dropped.last_overlap << " m, last normal force "
                        << dropped.last_normal << " N, pull-off " << pull_off << " N");
  CHECK_FALSE(dropped.attached);
  CHECK(dropped.drop > 1e-6);  // falling freely: g t^2 / 2 is 2e-5 m after 2 ms
  CHECK_FALSE(dropped.force_while_apart);
  // The last touching step: an overlap below a step's travel (dt times a speed below 1e-4 m/s),
  // where Hertz's part, 4/3 E* sqrt(R) delta^1.5 < 3.5e-8 N, is below 3e-3 of F_po: the tension is
  // F_po to that.
  CHECK(dropped.last_overlap > 0.0);
  CHECK(dropped.last_overlap < 1e-11);
  CHECK(-dropped.last_normal == Approx(pull_off).epsilon(3e-3));
}

TEST_CASE("hertz-dmt: its registry row reads the surface energy; a negative one is refused by name",
          "[contact][adhesion]") {
  const LawEntry& law = contact_law("hertz-dmt");
  LawValues values(law.parameters);
  CHECK(values.has("surface_energy"));
  values.set("surface_energy", 0.05);
  CHECK(std::string(law.bind(values, "ball_ball")->law_name()) == "hertz-dmt");
  values.set("surface_energy", -0.05);
  CHECK_THROWS_WITH(law.bind(values, "ball_ball"), Catch::Contains("ball_ball.surface_energy"));
}
