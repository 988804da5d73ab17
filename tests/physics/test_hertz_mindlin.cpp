// The Hertz-Mindlin law (docs/model.md 1.4) against the analytic single-impact tests of Chung &
// Ooi (2011, Granular Matter 13:643): head-on elastic impact of two equal spheres (their test 1)
// and of a sphere on a flat wall (test 2) against Hertz's maximum overlap, maximum force and
// duration; the restitution set against the one measured across its range, for both damping
// models (test 3); an oblique impact in gross sliding against the rigid-body Coulomb result (a
// tangential speed without spin: test 5's setting, its sliding regime; tests 4, 5, 7 and 8 in full
// are in test_hertz_oblique.cpp). Then the SIMD blocks against one contact at a time, to the bit
// (either rolling model), and the time-step estimate. The materials are the study's balls (0.5 mm, 2650 kg/m^3) with a
// quartz-like Young's modulus, not Chung & Ooi's own; their tests compare with theory, which holds
// for any material.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/hertz_impacts.hpp"
#include "support/isa_scope.hpp"

using namespace dem;
using namespace dem::testing;
using namespace dem::testing::hertz_impacts;

namespace {

void check_against_hertz(const Impact& r, double m_eff, double r_eff, double v0, double dt) {
  const double overlap = hertz_max_overlap(m_eff, r_eff, v0);
  const double force = 4.0 / 3.0 * effective_modulus * std::sqrt(r_eff) * std::pow(overlap, 1.5);
  const double duration = hertz_duration_factor * overlap / v0;
  INFO("overlap " << r.max_overlap << " / " << overlap << ", force " << r.max_force << " / " << force << ", duration "
                  << r.contact_time << " / " << duration);
  // dt is 1/2000 of the impact: the overlap and force are sampled within (pi dt / t_c)^2 of their
  // peaks and the leapfrog's energy error is of that order too (2.5e-6); 1e-4 leaves room for
  // the rounding of the sums. The duration is a whole number of steps: within 2 dt = 1e-3.
  CHECK(r.max_overlap == Approx(overlap).epsilon(1e-4));
  CHECK(r.max_force == Approx(force).epsilon(1e-4));
  CHECK(r.contact_time == Approx(duration).margin(2 * dt));
}

/// The measured restitution of a head-on impact of two balls (the relative speed's ratio).
double restitution(double e, HertzDamping model) {
  const auto p = HertzMindlinParams::material(youngs, poisson, e, 0.0, 0.0, model);
  const double v0 = 0.2, m_eff = ball_mass() / 2, r_eff = radius / 2;
  const double dt = hertz_duration_factor * hertz_max_overlap(m_eff, r_eff, v0) / v0 / 2000.0;
  const Impact r = two_spheres(p, v0, dt);
  return r.velocity.x() / v0;
}

}  // namespace

TEST_CASE("hertz-mindlin: elastic head-on impact of two equal spheres as Hertz (Chung & Ooi test 1)",
          "[physics][contact][hertz]") {
  const auto p = HertzMindlinParams::material(youngs, poisson, 1.0, 0.3);
  const double v0 = 0.2, m_eff = ball_mass() / 2, r_eff = radius / 2;  // 0.1 m/s each
  const double dt = hertz_duration_factor * hertz_max_overlap(m_eff, r_eff, v0) / v0 / 2000.0;
  const Impact r = two_spheres(p, v0, dt);
  check_against_hertz(r, m_eff, r_eff, v0, dt);
  CHECK(r.velocity.x() == Approx(v0).epsilon(1e-5));  // e = 1: no dashpots; the leapfrog returns the energy
}

TEST_CASE("hertz-mindlin: elastic impact of a sphere on a flat wall as Hertz (Chung & Ooi test 2)",
          "[physics][contact][hertz]") {
  const auto p = HertzMindlinParams::material(youngs, poisson, 1.0, 0.3);
  const double v0 = 0.2, m_eff = ball_mass(), r_eff = radius;  // the wall: rigid, flat
  const double dt = hertz_duration_factor * hertz_max_overlap(m_eff, r_eff, v0) / v0 / 2000.0;
  const Impact r = sphere_on_wall(p, Vec3(0, 0, -v0), dt);
  check_against_hertz(r, m_eff, r_eff, v0, dt);
  CHECK(r.velocity.z() == Approx(v0).epsilon(1e-5));
}

TEST_CASE("hertz-mindlin: the restitution set is the one measured, across its range, for both damping models "
          "(Chung & Ooi test 3)",
          "[physics][contact][hertz]") {
  for (const double e : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    INFO("e = " << e);
    // LIGGGHTS's dashpot c = 2 sqrt(5/6) |beta| sqrt(2 E* a m*) makes the Hertz oscillator's
    // restitution e exactly (an integration of the contact's equation of motion to 1e-6 agrees);
    // the dashpots act on half-step velocities, an O(dt / t_c) = 5e-4 error (1.1e-3 seen at e =
    // 0.1, below 3e-4 from 0.3 up): 2e-3 allowed.
    CHECK(restitution(e, HertzDamping::liggghts) == Approx(e).epsilon(2e-3));
    // Tsuji's alpha(e) is Marshall's polynomial fit: the exact equation of motion with it gives
    // e within 0.52 % (0.09948 for 0.1), 0.03 % from 0.3 up; plus the half-step error (0.62 % and
    // below 0.06 % seen).
    CHECK(restitution(e, HertzDamping::tsuji) == Approx(e).epsilon(e < 0.2 ? 8e-3 : 2e-3));
  }
}

TEST_CASE("hertz-mindlin: an oblique impact in gross sliding rebounds as the rigid-body Coulomb result",
          "[physics][contact][hertz]") {
  // Tangential speed 5 times the normal one, above 7/2 mu (1 + e) = 2.1: the contact slides for the
  // whole impact, so the tangential impulse is mu times the normal one, (1 + e) m v_n:
  //   v_t' = v_t - mu (1 + e) v_n,   omega' = 5/2 mu (1 + e) v_n / R   (about the axis n x t).
  const double mu = 0.3, v_n = 0.2, v_t = 1.0, e = 1.0;
  const auto p = HertzMindlinParams::material(youngs, poisson, e, mu);
  const double dt = hertz_duration_factor * hertz_max_overlap(ball_mass(), radius, v_n) / v_n / 2000.0;
  const Impact r = sphere_on_wall(p, Vec3(v_t, 0, -v_n), dt);
  const double v_t_after = v_t - mu * (1 + e) * v_n;       // 0.88 m/s
  const double spin_after = 2.5 * mu * (1 + e) * v_n / radius;  // 600 rad/s
  // The first and last steps of the impact (1/2000 of it each) are where the sum of the impulses
  // differs from the integral: 1e-3.
  CHECK(r.velocity.x() == Approx(v_t_after).epsilon(1e-3));
  CHECK(r.angular_velocity.y() == Approx(spin_after).epsilon(1e-3));
  CHECK(r.velocity.z() == Approx(e * v_n).epsilon(1e-4));
  // and the rebound angle from the normal, atan(v_t' / (e v_n)), follows
  CHECK(std::atan2(r.velocity.x(), r.velocity.z()) == Approx(std::atan2(v_t_after, e * v_n)).epsilon(1e-3));
}

namespace {

/// HertzMindlinLaw without force_lanes: the engine takes it one contact at a time.
struct HertzOneAtATime {
  using Params = HertzMindlinLaw::Params;
  using State = HertzMindlinLaw::State;
  static constexpr const char* name = "hertz-mindlin, one contact at a time";
  static ContactForce force(const Params& p, const ContactKinematics& k, State& s) { return HertzMindlinLaw::force(p, k, s); }
  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) { return HertzMindlinLaw::stiffness(p, k); }
};
static_assert(detail::LaneContactLaw<HertzMindlinLaw>);
static_assert(!detail::LaneContactLaw<HertzOneAtATime>);

/// Balls poured onto a floor under strong gravity that then tilts: contacts load, slide and roll.
template <class Law>
World pile(const HertzMindlinParams& params) {
  WorldSettings s;
  s.gravity = Vec3(2000.0, 0.0, -5000.0);
  World world(s);
  for (auto b : separated_balls(300, 5e-3, 0.25e-3, 0.4e-3, 5)) {
    b.position.z() += 0.5e-3;
    world.add_ball(b);
  }
  world.add_wall(floor_wall(0.0, 0.01));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<Law>(params, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<Law>(params, "ball-facet"));
  world.step(2000);  // about 12 ms: settled, and sliding down the tilt (tan 0.4 > mu 0.3), not yet off the floor
  return world;
}

}  // namespace

TEST_CASE("hertz-mindlin: blocks in SIMD lanes and one contact at a time give the same bits",
          "[physics][contact][hertz]") {
  struct Case {
    HertzDamping damping;
    HertzRolling rolling;
  };
  for (const Case c : {Case{HertzDamping::liggghts, HertzRolling::epsd}, Case{HertzDamping::tsuji, HertzRolling::epsd},
                       Case{HertzDamping::liggghts, HertzRolling::cdt}, Case{HertzDamping::tsuji, HertzRolling::sds}}) {
    INFO("damping model " << to_string(c.damping) << ", rolling " << to_string(c.rolling));
    auto params = HertzMindlinParams::material(1e8, 0.3, 0.4, 0.3, 0.1, c.damping);
    params.rolling = c.rolling;
    if (c.rolling == HertzRolling::sds) params.rolling_stiffness = 20.0;  // N/m, softer than the pile's k_t (a few hundred N/m)
    REQUIRE(HertzMindlinLaw::lane_variant(params) == (c.rolling == HertzRolling::epsd ? 0 : 1));
    const World single = pile<HertzOneAtATime>(params);
    // the scene exercises every branch of the law (the lanes compute them as selects): contacts
    // sliding (|F_t| = mu |F_n|) and rolling at their cap (|M| = mu_r R* |F_n|; cdt's torque is
    // always there, its history always zero)
    const PairContacts& pairs = single.pair_contacts(ContactKind::BallBall);
    const ParticleStore& b = single.particles();
    std::size_t touching = 0, sliding = 0, rolling_capped = 0, rolling_history = 0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (pairs.normal_force[k] <= 0.0) continue;
      ++touching;
      const auto i = static_cast<std::size_t>(pairs.first[k]), j = static_cast<std::size_t>(pairs.second[k]);
      const Vec3 n = (b.x[j] - b.x[i]).normalized();
      const double normal = std::abs(pairs.force[k].dot(n));
      const double tangential = (pairs.force[k] - pairs.force[k].dot(n) * n).norm();
      const auto* state = reinterpret_cast<const HertzMindlinLaw::State*>(pairs.state.at(k));
      const double r_eff = b.radius[i] * b.radius[j] / (b.radius[i] + b.radius[j]);
      const double moment = to_vec3(state->rolling_moment).norm();
      if (tangential >= 0.999 * params.friction * normal) ++sliding;
      if (moment >= 0.999 * params.rolling_friction * r_eff * normal) ++rolling_capped;
      if (moment != 0.0) ++rolling_history;
    }
    INFO("touching " << touching << ", sliding " << sliding << ", rolling capped " << rolling_capped
                     << ", with a rolling history " << rolling_history);
    REQUIRE(touching > 200);
    REQUIRE(sliding > 0);
    if (c.rolling == HertzRolling::cdt) REQUIRE(rolling_history == 0);
    else REQUIRE(rolling_capped > 0);
    const detail::BlockIsa best = detail::detected_block_isa();
    if (best == detail::BlockIsa::scalar) WARN("this processor takes one contact at a time for every law");
    for (const detail::BlockIsa isa : {detail::BlockIsa::avx2, detail::BlockIsa::avx512}) {
      if (isa > best) continue;
      const BlockIsaScope scope(isa);
      INFO("blocks on instruction set " << static_cast<int>(isa) << " (1: AVX2, 2: AVX-512)");
      require_same_bits(pile<HertzMindlinLaw>(params), single);
    }
    if (c.rolling != HertzRolling::epsd) {  // and cdt's or sds's run is not epsd's (the scene sees the model)
      params.rolling = HertzRolling::epsd;
      params.rolling_stiffness = 0.0;
      CHECK(pile<HertzMindlinLaw>(params).particles().w != single.particles().w);
    }
  }
}

TEST_CASE("hertz-mindlin: the time-step estimate takes the tangent stiffness at an overlap of 1 % of R*",
          "[physics][contact][hertz]") {
  const auto p = HertzMindlinParams::material(youngs, poisson, 0.5, 0.3);
  World world(dynamic_settings(0.0));
  world.add_ball(ball_at(Vec3::Zero()));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<HertzMindlinLaw>(p, "ball-ball"));
  // one ball alone: the estimate of a single ball-ball contact of two of its size
  const double r_eff = radius / 2, a = std::sqrt(r_eff * 0.01 * r_eff);
  const double k_n = 2.0 * effective_modulus * a;
  const double k_t = 8.0 * youngs / (4.0 * (2.0 - poisson) * (1.0 + poisson)) * a;
  CHECK(world.critical_time_step() == Approx(std::sqrt(ball_mass() / (k_n + k_t))).epsilon(1e-12));
  // An impact at 2 m/s (overlap 0.7 % of R*) at 0.8 of the estimate, about 5 steps: stable, and
  // the leapfrog gives back the energy to 0.07 %.
  const auto elastic = HertzMindlinParams::material(youngs, poisson, 1.0, 0.3);
  const double dt = 0.8 * world.critical_time_step();
  const Impact r = two_spheres(elastic, 2.0, dt);
  CHECK(r.velocity.x() == Approx(2.0).epsilon(5e-3));
}

TEST_CASE("hertz-mindlin: parameters out of range are refused by name, stale derived constants too",
          "[physics][contact][hertz]") {
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(make_contact_model<HertzMindlinLaw>(HertzMindlinParams::material(youngs, 0.6, 0.5, 0.3), "ball_ball"),
                    Contains("ball_ball.poissons_ratio") && Contains("0.6"));
  CHECK_THROWS_WITH(make_contact_model<HertzMindlinLaw>(HertzMindlinParams::material(youngs, 0.3, 0.0, 0.3), "ball_ball"),
                    Contains("ball_ball.restitution"));
  auto stale = HertzMindlinParams::material(youngs, 0.3, 0.5, 0.3);
  stale.restitution = 0.8;
  CHECK_THROWS_WITH(make_contact_model<HertzMindlinLaw>(stale, "ball_ball"), Contains("derive()"));
  stale.derive();
  CHECK_NOTHROW(make_contact_model<HertzMindlinLaw>(stale, "ball_ball"));
}
