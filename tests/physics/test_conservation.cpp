// Conservation laws (docs/model.md 2): without damping and friction a granular gas in a closed box
// keeps its total energy (kinetic + elastic); pair forces are equal and opposite, so linear
// momentum of a colliding cluster is conserved to round-off, with friction and rolling resistance.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

double elastic_energy(const World& world, double kn_ball, double kn_wall) {
  double energy = 0.0;
  world.for_each_contact([&](const ContactView& c) {
    const double kn = c.kind == ContactKind::BallBall ? kn_ball : kn_wall;
    energy += 0.5 * c.normal_force * c.normal_force / kn;
  });
  return energy;
}

}  // namespace

TEST_CASE("energy: a frictionless undamped granular gas keeps its total energy", "[physics][conservation]") {
  const double box = 8e-3;
  World world(dynamic_settings(0.0));
  // A gas, not a packing: balls apart from each other and from the walls.
  add_gas(world, 150, box, 0.1, 0.3e-3, 0.5e-3, 0.6, 11, 7);
  add_facet_box(world, box);
  const auto law = make_contact_model<LinearLaw>(LinearParams::constant(2e4, 2e4, 0.0), "contact");
  world.set_contact_model(ContactKind::BallBall, law);
  world.set_contact_model(ContactKind::BallFacet, law);
  world.update_time_step();
  world.set_time_step(0.1 * world.critical_time_step());  // energy error ~ (omega dt)^2 ~ 1e-3 of a contact's
  world.step(1);
  const double e0 = world.kinetic_energy() + elastic_energy(world, 2e4, 2e4);
  std::size_t contact_steps = 0;
  world.add_callback(1, [&](World& w) { contact_steps += w.contact_count(ContactKind::BallBall); });
  for (int block = 0; block < 40; ++block) {
    world.step(2000);
    const double e = world.kinetic_energy() + elastic_energy(world, 2e4, 2e4);
    // Leapfrog keeps energy bounded with an O((omega dt)^2) oscillation during contacts; the
    // half-step velocities add O(dt) within a contact. 0.5 % is the bound we hold ourselves to.
    REQUIRE(e == Approx(e0).epsilon(5e-3));
  }
  // The gas really collides: a ball-ball collision lasts ~30 steps here, so this is > 100 collisions.
  CHECK(contact_steps > 3000);
}

TEST_CASE("momentum: a colliding cluster with friction and rolling resistance conserves momentum",
          "[physics][conservation]") {
  World world(dynamic_settings(0.0));
  world.set_local_damping(0.0);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> speed(0.0, 1.0);
  for (auto b : separated_balls(300, 9e-3, 0.3e-3, 0.6e-3, 5)) {
    b.velocity = Vec3(speed(rng), speed(rng), speed(rng));
    b.angular_velocity = Vec3(speed(rng), speed(rng), speed(rng)) * 100.0;
    world.add_ball(b);
  }
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  p.normal_damping_ratio = 0.2;
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
  auto momentum = [&] {
    Vec3 m = Vec3::Zero();
    const auto& pa = world.particles();
    for (std::size_t i = 0; i < pa.size(); ++i) m += pa.mass[i] * pa.v[i];
    return m;
  };
  auto scale = [&] {
    double s = 0.0;
    const auto& pa = world.particles();
    for (std::size_t i = 0; i < pa.size(); ++i) s += pa.mass[i] * pa.v[i].norm();
    return s;
  };
  world.update_time_step();
  const Vec3 m0 = momentum();
  std::size_t contact_steps = 0;
  world.add_callback(1, [&](World& w) { contact_steps += w.contact_count(ContactKind::BallBall); });
  world.step(6000);
  CHECK(contact_steps > 1000);  // many collisions, with friction and rolling moments
  // Round-off only: 300 balls x 3000 steps of sums of O(10) terms, relative 1e-16 each.
  CHECK((momentum() - m0).norm() < 1e-11 * scale());
}
