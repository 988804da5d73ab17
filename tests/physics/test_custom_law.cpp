// A user-defined contact law plugs into the engine without editing it: a plain Hertz-Mindlin,
// defined here as a user would write one (one contact at a time, no SIMD form), reproduces Hertz's
// head-on contact duration t = 2.8683 (m_eff^2 / (R_eff E^2 v0))^(1/5). The library's own
// Hertz-Mindlin, with damping and rolling resistance, is HertzMindlinLaw (test_hertz_mindlin.cpp).
#include <catch2/catch.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

/// Hertz normal force F = 4/3 E sqrt(R_eff) delta^1.5; Mindlin no-slip tangential stiffness
/// k_t = 8 G sqrt(R_eff delta) with Coulomb slip (Johnson, Contact Mechanics, 1985, ch. 4 and 7).
struct UserHertzLaw {
  struct Params {
    double modulus = 0.0;        // Pa, effective Young's modulus E*
    double shear_modulus = 0.0;  // Pa, effective shear modulus G*
    double friction = 0.0;       // -
    void validate(const std::string& where) const {
      require_positive(where + ".modulus", modulus);
      require_positive(where + ".shear_modulus", shear_modulus);
      require_non_negative(where + ".friction", friction);
    }
  };
  struct State {
    Vec3 shear_force = Vec3::Zero();  // N
  };
  static constexpr const char* name = "hertz-mindlin";

  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    // stiffness at an overlap of 1e-3 R, for the time-step estimate
    const double a = std::sqrt(k.effective_radius * 1e-3 * k.radius_1);
    return {2.0 * p.modulus * a, 8.0 * p.shear_modulus * a, 0.0};
  }
  static ContactForce force(const Params& p, const ContactKinematics& k, State& s) {
    const double a = std::sqrt(k.effective_radius * k.overlap);  // contact radius
    const double fn = 4.0 / 3.0 * p.modulus * a * k.overlap;
    const Vec3 vs = k.relative_velocity - k.relative_velocity.dot(k.normal) * k.normal;
    s.shear_force -= s.shear_force.dot(k.normal) * k.normal;
    s.shear_force -= 8.0 * p.shear_modulus * a * k.dt * vs;
    const double limit = p.friction * fn;
    if (s.shear_force.norm() > limit) s.shear_force *= limit / s.shear_force.norm();
    ContactForce out;
    out.force = fn * k.normal + s.shear_force;
    out.normal_force = fn;
    out.normal_stiffness = 2.0 * p.modulus * a;
    return out;
  }
};

}  // namespace

TEST_CASE("custom law: a Hertz-Mindlin law defined outside the library gives Hertz's contact time",
          "[physics][contact]") {
  const double v0 = 0.2, modulus = 1e8;
  World world(dynamic_settings(1e-9));
  world.add_ball(ball_at(Vec3::Zero(), Vec3(0.5 * v0, 0, 0)));
  world.add_ball(ball_at(Vec3(2 * radius + 1e-7, 0, 0), Vec3(-0.5 * v0, 0, 0)));
  world.set_contact_model(ContactKind::BallBall,
                          make_contact_model<UserHertzLaw>({modulus, modulus / 2.5, 0.5}, "ball-ball"));
  const double m_eff = ball_mass() / 2, r_eff = radius / 2;
  const double expected = 2.8683 * std::pow(m_eff * m_eff / (r_eff * modulus * modulus * v0), 0.2);
  double contact_time = 0.0;
  bool touched = false;
  for (int s = 0; s < 100000; ++s) {
    world.step();
    const bool touching = world.contact_count(ContactKind::BallBall) == 1;
    if (touching) contact_time += 1e-9, touched = true;
    if (touched && !touching) break;
  }
  // 2.8683 is the closed-form constant to 5 digits; the step (1e-9 s) is 1e-4 of the duration.
  CHECK(contact_time == Approx(expected).epsilon(2e-3));
  const auto& p = world.particles();
  CHECK((p.v[p.index_of(1)].x() - p.v[p.index_of(0)].x()) == Approx(v0).epsilon(1e-4));  // elastic
}

namespace {

/// A law whose State has LinearLaw's size, and which notes whether a contact's first State it
/// sees is fresh (value-initialised) or carries bytes another law left.
int inherited_states = 0;
struct ProbeLaw {
  struct Params {
    double stiffness = 1e4;  // N/m
    void validate(const std::string& where) const { require_positive(where + ".stiffness", stiffness); }
  };
  struct State {
    double seen = 0.0, unused_1 = 0.0, unused_2 = 0.0;
  };
  static constexpr const char* name = "probe";
  static ContactStiffness stiffness(const Params& p, const ContactKinematics&) { return {p.stiffness, 0.0, 0.0}; }
  static constexpr double marker = 12345.0;  // in `seen` once the probe has had the contact
  static ContactForce force(const Params& p, const ContactKinematics& k, State& s) {
    if (s.seen != marker && (s.seen != 0.0 || s.unused_1 != 0.0 || s.unused_2 != 0.0)) ++inherited_states;
    s.seen = marker;
    ContactForce out;
    out.normal_force = p.stiffness * k.overlap;
    out.force = out.normal_force * k.normal;
    out.normal_stiffness = p.stiffness;
    return out;
  }
};
static_assert(sizeof(ProbeLaw::State) == sizeof(LinearLaw::State), "the swap must be between same-size States");

// Two overlapping balls sliding past each other, so that LinearLaw's shear spring is loaded.
World sliding_pair() {
  World world(dynamic_settings(1e-7));
  world.add_ball(ball_at(Vec3::Zero()));
  world.add_ball(ball_at(Vec3(1.99 * radius, 0, 0), Vec3(0, 0.01, 0)));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(LinearParams::constant(1e4, 1e4, 0.5), "ball-ball"));
  world.step(20);
  return world;
}

double shear_spring(const World& world) {
  const StateBuffer& s = world.pair_contacts(ContactKind::BallBall).state;
  REQUIRE(s.count == 1);
  const auto* state = reinterpret_cast<const LinearLaw::State*>(s.at(0));
  return std::sqrt(squared_norm(state->shear_force));
}

}  // namespace

TEST_CASE("contact history: a law of another type with a same-size State starts fresh, the same law keeps it",
          "[physics][contact]") {
  {
    World world = sliding_pair();
    // After 20 steps the spring holds about k_t |v_t| t = 1e4 * 0.01 * 2e-6 N (less the spins'
    // share of the sliding), far below the Coulomb limit 0.5 * 0.1 N: bytes a probe would see.
    REQUIRE(shear_spring(world) > 0.9 * 1e4 * 0.01 * 20 * 1e-7);
    inherited_states = 0;
    world.set_contact_model(ContactKind::BallBall, make_contact_model<ProbeLaw>({}, "ball-ball"));
    world.step();
    CHECK(inherited_states == 0);
    CHECK(world.pair_contacts(ContactKind::BallBall).state.count == 1);
  }
  {
    World world = sliding_pair();
    const double before = shear_spring(world);
    world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(LinearParams::constant(1e4, 1e4, 0.8), "ball-ball"));
    world.step();
    // The spring carries on: one more step's increment (about 1/20 of it) on top of what it
    // held; a fresh one would hold that increment alone.
    CHECK(shear_spring(world) > before);
    CHECK(shear_spring(world) < 1.1 * before);
  }
}
