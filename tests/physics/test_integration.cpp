// Time integration: local damping (docs/model.md T7), free flight, the SIMD leapfrog against the
// scalar one, and the instability stop.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/isa_scope.hpp"
#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

TEST_CASE("integration: local damping 0.7 leaves (1 - 0.7) of a constant force", "[physics][integration]") {
  WorldSettings s;
  s.time_step = 1e-5;
  s.local_damping = 0.7;
  s.gravity = Vec3(0, 0, -9.81);
  World world(s);
  world.add_ball(ball_at(Vec3::Zero()));
  world.step(1);  // from rest the force does no work yet: undamped first kick
  const double v1 = world.particles().v[0].z();
  world.step(1000);
  // a = (1 - alpha) g exactly once the ball moves along the force.
  CHECK((world.particles().v[0].z() - v1) / (1000 * s.time_step) == Approx(-0.3 * 9.81).epsilon(1e-12));
}

TEST_CASE("integration: free flight under gravity is exact for leapfrog", "[physics][integration]") {
  WorldSettings s = dynamic_settings(1e-5);
  s.gravity = Vec3(0, 0, -9.81);
  World world(s);
  world.add_ball(ball_at(Vec3::Zero(), Vec3(1.0, 0, 0.2)));
  world.step(1000);
  const double t = world.time();
  CHECK(world.particles().x[0].x() == Approx(1.0 * t).epsilon(1e-12));
  // leapfrog with v(-dt/2) = v0: z = v0 t - g t^2/2 - g t dt/2
  CHECK(world.particles().x[0].z() == Approx(0.2 * t - 0.5 * 9.81 * t * t - 0.5 * 9.81 * t * 1e-5).epsilon(1e-10));
}

TEST_CASE("instability: a time step far above the stable one stops the run with a diagnosis", "[physics][integration]") {
  World world(dynamic_settings(1e-3));  // ~100x the critical step of these contacts
  world.add_ball(ball_at(Vec3::Zero(), Vec3(0.5, 0, 0)));
  world.add_ball(ball_at(Vec3(2.1 * radius, 0, 0), Vec3(-0.5, 0, 0)));
  world.set_contact_model(ContactKind::BallBall,
                          make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1, 0.5), "ball-ball"));
  try {
    world.step(20);
    FAIL("the run should have stopped");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK_THAT(msg, Contains("ball id") && Contains("step") && Contains("time step") && Contains("stable estimate"));
    CHECK(world.step_count() < 5);
  }
}

TEST_CASE("instability: below the stable step, a soft contact type beside stiff balls is named, not the step",
          "[physics][integration]") {
  // One ball pressed onto the floor by 1000 g through a ball-facet contact 10^4 times softer than
  // the ball-ball one: the ball-ball stiffness sets the stable step, the step is a quarter of it,
  // and the overlap with the floor grows past the limit (m g / k_n is about 6 radii).
  WorldSettings s = dynamic_settings(1e-6);
  s.gravity = Vec3(0, 0, -9.81e3);
  s.max_overlap_ratio = 0.5;  // a facet contact ends when the centre crosses the facet
  World world(s);
  world.add_ball(ball_at(Vec3(0, 0, radius)));
  world.add_wall(floor_wall(0.0, 10 * radius));
  world.set_contact_model(ContactKind::BallBall,
                          make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1, 0.5), "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet,
                          make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball * 1e-4, 1, 0.5), "ball-facet"));
  REQUIRE(world.critical_time_step() > 3e-6);
  try {
    world.step(200000);
    FAIL("the run should have stopped");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK_THAT(msg, Contains("overlaps wall 'floor'") && Contains("below the stable estimate") &&
                        Contains("not the cause") && Contains("set by the stiffest contact type, ball-ball") &&
                        Contains("ball-facet contacts are too soft"));
    // The law and the key that stiffens it, as the configuration names them.
    CHECK_THAT(msg, Contains("N/m (linear)") && Contains("raise the ball-facet effective_modulus (law linear)"));
    CHECK_THAT(msg, !Contains("Reduce time_step"));
  }
}

TEST_CASE("instability: the overlap limit is a setting that a loaded world can raise", "[physics][integration]") {
  // Two balls at rest, overlapping by 0.4 of their radius, with the contact law switched off
  // (zero stiffness is not allowed, so a tiny one): nothing moves, only the limit decides.
  WorldSettings s = dynamic_settings(1e-6);
  s.max_overlap_ratio = 0.3;
  World world(s);
  world.add_ball(ball_at(Vec3::Zero()));
  world.add_ball(ball_at(Vec3(1.6 * radius, 0, 0)));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(LinearParams::constant(1e-12, 1e-12, 0.5), "ball-ball"));
  CHECK_THROWS_AS(world.step(1), InstabilityError);
  world.set_max_overlap_ratio(0.5);
  CHECK_NOTHROW(world.step(10));
  CHECK_THROWS_WITH(world.set_max_overlap_ratio(0.0), Contains("max_overlap_ratio"));
  CHECK_THROWS_WITH(world.set_max_overlap_ratio(std::nan("")), Contains("max_overlap_ratio"));
}

namespace {

/// LinearLaw without its lane form: the pair loops take one contact at a time on every
/// instruction set, so that only the leapfrog kernel changes between the runs below.
struct LinearOneAtATime {
  using Params = LinearLaw::Params;
  using State = LinearLaw::State;
  static constexpr const char* name = "linear, one contact at a time";
  static ContactForce force(const Params& p, const ContactKinematics& k, State& s) { return LinearLaw::force(p, k, s); }
  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) { return LinearLaw::stiffness(p, k); }
};

/// Balls, spinning and falling into a pile with locally damped motion, among small rigid clumps,
/// one ball partly fixed (x and its spin about z) and one held entirely. Re-sorted at every
/// rebuild, so that pebbles share groups of eight with balls in storage. Damped against `frame`.
World damped_pile_with_clumps(const DampingFrame& frame = {}) {
  WorldSettings s;
  s.gravity = Vec3(300.0, 0.0, -2000.0);
  s.local_damping = 0.7;
  s.sort_every = 1;
  World world(s);
  std::vector<BallSpec> balls = separated_balls(200, 5e-3, 0.25e-3, 0.4e-3, 11);
  for (std::size_t k = 0; k < balls.size(); ++k) {
    BallSpec& b = balls[k];
    b.position.z() += 0.5e-3;
    b.angular_velocity = Vec3(std::sin(k), std::cos(3.0 * k), 0.5) * 200.0;
    if (k == 17) b.fixed = dof_x | dof_rz;
    if (k == 90) b.fixed = dof_all;
    world.add_ball(b);
  }
  for (int c = 0; c < 4; ++c) {
    ClumpSpec clump;
    const Vec3 centre(1e-3 + c * 1e-3, 2.5e-3, 6.5e-3);
    clump.pebbles = {{centre, 0.3e-3}, {centre + Vec3(0.4e-3, 0, 0), 0.3e-3}};
    clump.with_pebble_mass(density);
    world.add_clump(clump);
  }
  const auto model = make_contact_model<LinearOneAtATime>(LinearParams::deformable(modulus_ball, 1.0, 0.4), "all");
  for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble})
    world.set_contact_model(kind, model);
  world.add_wall(floor_wall(0.0, 0.01));
  world.set_damping_frame(frame);
  world.step(4000);
  return world;
}

}  // namespace

TEST_CASE("integration: eight particles at a time in SIMD lanes give the one-at-a-time bits", "[physics][integration]") {
  World reference = [] {
    const BlockIsaScope scope(detail::BlockIsa::scalar);
    return damped_pile_with_clumps();
  }();
  if (detail::detected_block_isa() != detail::BlockIsa::avx512)
    WARN("this processor has no AVX-512: both runs integrate one particle at a time");
  const World lanes = damped_pile_with_clumps();

  // The scene has what the lanes must handle: groups of eight mixing pebbles and free balls
  // (pebbles are left to their clump), and groups with a partly fixed ball (one at a time).
  const ParticleStore& p = lanes.particles();
  std::size_t mixed_groups = 0, fixed_groups = 0;
  for (std::size_t g = 0; g + 8 <= p.size(); g += 8) {
    std::size_t pebbles = 0, fixed = 0;
    for (std::size_t i = g; i < g + 8; ++i) pebbles += p.is_pebble(i), fixed += !p.is_pebble(i) && p.fixed[i] != 0;
    mixed_groups += pebbles > 0 && pebbles < 8;
    fixed_groups += fixed > 0;
  }
  CHECK(mixed_groups >= 2);
  CHECK(fixed_groups >= 1);
  CHECK(lanes.pair_contacts(ContactKind::BallBall).size() > 100);

  require_same_bits(lanes, reference);
  for (std::size_t c = 0; c < lanes.clumps().size(); ++c) CHECK(lanes.clumps()[c].x == reference.clumps()[c].x);
  // and the fixed components kept their velocity (the spin they started with, no drift along x)
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed[i] == dof_all && !p.is_pebble(i)) CHECK(p.v[i] == Vec3::Zero());
    if (p.fixed[i] == (dof_x | dof_rz)) CHECK((p.v[i].x() == 0.0 && p.w[i].z() == 100.0));
  }
}

TEST_CASE("integration: with a sheared damping frame the SIMD lanes give the one-at-a-time bits", "[physics][integration]") {
  DampingFrame frame;  // a field like a shear cell's: sheared along x and y, stretched in z
  frame.velocity = Vec3(0.01, -0.004, 0.0);
  frame.height = 1e-3;
  frame.velocity_gradient = Vec3(-3.0, 1.5, 0.2);
  World reference = [&] {
    const BlockIsaScope scope(detail::BlockIsa::scalar);
    return damped_pile_with_clumps(frame);
  }();
  if (detail::detected_block_isa() != detail::BlockIsa::avx512)
    WARN("this processor has no AVX-512: both runs integrate one particle at a time");
  const World lanes = damped_pile_with_clumps(frame);
  require_same_bits(lanes, reference);
  for (std::size_t c = 0; c < lanes.clumps().size(); ++c) CHECK(lanes.clumps()[c].x == reference.clumps()[c].x);
  // and the frame changed the trajectories: the same pile in the fixed frame ends elsewhere
  const World fixed = damped_pile_with_clumps();
  CHECK(fixed.particles().x != lanes.particles().x);
}

TEST_CASE("instability: the first runaway ball is named whichever path integrates it", "[physics][integration]") {
  // 40 balls apart (five groups of eight): ids 13 and 29 move 8 radii per step.
  auto run = [] {
    World world(dynamic_settings(1e-5));
    for (int k = 0; k < 40; ++k) {
      const Vec3 velocity = (k == 13 || k == 29) ? Vec3(0, 0, 400.0) : Vec3(0, 0, 1.0);
      world.add_ball(ball_at(Vec3(3.0 * radius * k, 0, 0), velocity));
    }
    try {
      world.step(1);
    } catch (const InstabilityError& e) {
      return std::string(e.what());
    }
    return std::string("no stop");
  };
  std::string one_at_a_time;
  {
    const BlockIsaScope scope(detail::BlockIsa::scalar);
    one_at_a_time = run();
  }
  for (const std::string& msg : {one_at_a_time, run()}) {
    CHECK_THAT(msg, Contains("ball id 13 ") && Contains("radii in one step"));
  }
}
