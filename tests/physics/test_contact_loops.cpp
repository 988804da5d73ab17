// The engine has two pair loops: blocks of contacts in SIMD lanes for a law with a plain-double
// form (contact/lanes.hpp), one contact at a time for any other law. They must be the same
// physics to the bit: same arithmetic in the same order, sums in contact order. Here a loaded,
// sliding, rolling pile runs once with RollingLinearLaw (blocks, where the processor has AVX2) and
// once with the same law hidden behind a per-contact-only wrapper, and every particle must end
// bit for bit where the other run left it. The blocks run the law's variant for the parameters'
// dashpots (none, rate, any); the wrapper always takes the general formula: one section each.
// The blocks run on every instruction set the processor has (AVX2, AVX-512), each compared. The
// pile rests on a floor, a facet wall or an analytic plane: its ball-wall contacts run in blocks
// too, and their records and the floor's force must match as well.
#include <algorithm>

#include <catch2/catch.hpp>

#include "support/isa_scope.hpp"
#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

/// RollingLinearLaw without force_lanes: the engine can only take it one contact at a time.
struct RollingOneAtATime {
  using Params = RollingLinearLaw::Params;
  using State = RollingLinearLaw::State;
  static constexpr const char* name = "rolling-linear, one contact at a time";
  static ContactForce force(const Params& p, const ContactKinematics& k, State& s) {
    return RollingLinearLaw::force(p, k, s);
  }
  static ContactStiffness stiffness(const Params& p, const ContactKinematics& k) {
    return RollingLinearLaw::stiffness(p, k);
  }
};

static_assert(detail::LaneContactLaw<RollingLinearLaw>);
static_assert(!detail::LaneContactLaw<RollingOneAtATime>);

enum class Floor { facets, plane };

/// Balls poured onto a floor under strong gravity, then the floor tilts by moving sideways:
/// contacts load, slide (Coulomb cap) and roll (rolling cap).
template <class Law>
World pile(const typename Law::Params& params, double near_skin = 0.0, Floor floor = Floor::facets) {
  WorldSettings s;
  s.gravity = Vec3(2000.0, 0.0, -5000.0);
  s.near_skin = near_skin;
  World world(s);
  for (auto b : separated_balls(300, 5e-3, 0.25e-3, 0.4e-3, 5)) {
    b.position.z() += 0.5e-3;
    world.add_ball(b);
  }
  world.add_wall(floor == Floor::facets ? floor_wall(0.0, 0.01)
                                        : make_plane_wall("floor", Vec3::Zero(), -Vec3::UnitZ(), 4e-4));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<Law>(params, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<Law>(params, "ball-facet"));
  world.step(6000);
  return world;
}

/// Touching ball-ball contacts, and those at their Coulomb and rolling caps.
struct ContactCensus {
  std::size_t touching = 0, sliding = 0, rolling_capped = 0;
};
ContactCensus census(const World& world, const RollingLinearLaw::Params& params) {
  ContactCensus out;
  const PairContacts& c = world.pair_contacts(ContactKind::BallBall);
  const ParticleStore& p = world.particles();
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    ++out.touching;
    const auto* state = reinterpret_cast<const RollingLinearLaw::State*>(c.state.at(k));
    const double r1 = p.radius[static_cast<std::size_t>(c.first[k])];
    const double r2 = p.radius[static_cast<std::size_t>(c.second[k])];
    const double shear = to_vec3(state->shear_force).norm();
    const double moment = to_vec3(state->rolling_moment).norm();
    if (shear >= 0.999 * params.friction * c.normal_force[k]) ++out.sliding;
    if (moment >= 0.999 * params.rolling_friction * (r1 * r2 / (r1 + r2)) * c.normal_force[k]) ++out.rolling_capped;
  }
  return out;
}

/// The pile with blocks on each SIMD instruction set this processor has, against one contact at
/// a time. Returns the run on the best one.
World require_same_bits_on_every_isa(const RollingLinearLaw::Params& params, Floor floor = Floor::facets) {
  const World single = pile<RollingOneAtATime>(params, 0.0, floor);
  const detail::BlockIsa best = detail::detected_block_isa();
  if (best == detail::BlockIsa::scalar)
    WARN("this processor takes one contact at a time for every law: both runs use the same loop");
  for (const detail::BlockIsa isa : {detail::BlockIsa::avx2, detail::BlockIsa::avx512}) {
    if (isa > best) continue;
    const BlockIsaScope scope(isa);
    INFO("blocks on instruction set " << static_cast<int>(isa) << " (1: AVX2, 2: AVX-512)");
    REQUIRE(detail::block_isa() == isa);
    require_same_bits(pile<RollingLinearLaw>(params, 0.0, floor), single);
  }
  return pile<RollingLinearLaw>(params, 0.0, floor);
}

}  // namespace

TEST_CASE("contact loops: blocks in SIMD lanes and one contact at a time give the same bits",
          "[physics][contact]") {
  SECTION("stiffness from E*, critical-damping ratios") {
    auto params = RollingLinearLaw::Params::deformable(modulus_ball, 1.5, 0.3, 0.1);
    params.normal_damping_ratio = 0.2;
    params.shear_damping_ratio = 0.1;
    const World blocks = require_same_bits_on_every_isa(params);
    // the scene exercises every branch of the law (the lanes compute them as selects)
    const ContactCensus seen = census(blocks, params);
    INFO("touching " << seen.touching << ", sliding " << seen.sliding << ", rolling capped " << seen.rolling_capped);
    REQUIRE(seen.touching > 200);
    REQUIRE(seen.sliding > 0);
    REQUIRE(seen.rolling_capped > 0);
  }
  SECTION("stiffness from E*, no dashpots (the study's models)") {
    const auto params = RollingLinearLaw::Params::deformable(modulus_ball, 1.5, 0.3, 0.1);
    REQUIRE(RollingLinearLaw::lane_variant(params) == static_cast<int>(Dashpots::none));
    require_same_bits_on_every_isa(params);
  }
  SECTION("constant stiffness, mass-proportional dashpots (the peers' benchmark law)") {
    auto params = RollingLinearLaw::Params::constant(2e4, 2e4, 0.5, 0.17);
    params.normal_damping_rate = 1e4;
    params.shear_damping_rate = 5e3;
    require_same_bits_on_every_isa(params);
  }
  SECTION("on an analytic plane (the peers' walls)") {
    auto params = RollingLinearLaw::Params::deformable(modulus_ball, 1.5, 0.3, 0.1);
    params.normal_damping_ratio = 0.2;
    const World blocks = require_same_bits_on_every_isa(params, Floor::plane);
    // the floor carries the pile: a third or more of its balls touch it, sliding as it moves
    const WallContacts& floor = blocks.state().contacts.ball_surface;
    const auto touching = std::count_if(floor.normal_force.begin(), floor.normal_force.end(), [](double f) { return f > 0; });
    INFO("balls on the plane " << touching);
    REQUIRE(touching > 30);
    REQUIRE(blocks.walls().front().force.z() < 0.0);
  }
}

TEST_CASE("contact loops: the near list changes no result, however small or large its skin",
          "[physics][contact]") {
  const auto params = RollingLinearLaw::Params::deformable(modulus_ball, 1.5, 0.3, 0.1);
  // 1 nm: remade nearly every step, holding little beyond the touching contacts; 1 m: every
  // candidate; default: a fifth of the Verlet skin. A wrong refresh criterion would miss contacts
  // as they close, and the piles would part.
  const World tight = pile<RollingLinearLaw>(params, 1e-9);
  const World loose = pile<RollingLinearLaw>(params, 1.0);
  const World usual = pile<RollingLinearLaw>(params);
  const PairContacts& c = tight.pair_contacts(ContactKind::BallBall);
  const PairPlan& plan = tight.pair_plan(ContactKind::BallBall);
  INFO("candidates " << c.size() << ", near with 1 nm " << plan.near.size() << ", near refreshes " << tight.near_refresh_count());
  REQUIRE(plan.near.size() < c.size());
  REQUIRE(loose.pair_plan(ContactKind::BallBall).near.size() == loose.pair_contacts(ContactKind::BallBall).size());
  REQUIRE(tight.near_refresh_count() > usual.near_refresh_count());
  require_same_bits(tight, usual);
  require_same_bits(loose, usual);
  SECTION("and one contact at a time") { require_same_bits(pile<RollingOneAtATime>(params, 1e-9), usual); }
}
