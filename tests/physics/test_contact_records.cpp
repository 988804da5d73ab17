// World::ContactRecords: skipping the pair contacts' force records on the steps nobody can read
// them must not change the motion, the history or the records where they are read. The reference
// is the same scene recording every step (what every step did before the setting existed): a
// dense gas of frictional balls with rolling resistance in a box, so that contacts open, close and
// slide, and the lists are rebuilt on steps that do not record.
#include <catch2/catch.hpp>

#include <cstring>
#include <stdexcept>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

World colliding_gas(World::ContactRecords records) {
  const double box = 5e-3;
  World world(dynamic_settings(0.0));
  add_gas(world, 300, box, 0.05, 0.3e-3, 0.45e-3, 0.5, 13, 5);
  add_facet_box(world, box);
  auto params = RollingLinearLaw::Params::deformable(modulus_ball, 1.5, 0.5, 0.1);
  params.normal_damping_ratio = 0.1;
  const auto law = make_contact_model<RollingLinearLaw>(params, "contact");
  world.set_contact_model(ContactKind::BallBall, law);
  world.set_contact_model(ContactKind::BallFacet, law);
  // The automatic time step, re-estimated at every rebuild from the contacts that touch: a
  // rebuild on a step that skipped the records must find the same ones.
  world.update_time_step();
  world.set_contact_records(records);
  return world;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace

TEST_CASE("contact records: recording only where they are read changes no bit of the run", "[physics][contacts]") {
  World every = colliding_gas(World::ContactRecords::EveryStep);
  World when_read = colliding_gas(World::ContactRecords::WhenRead);
  every.step(800);
  when_read.step(800);  // one call: only its last step records
  // The lists were rebuilt on steps that skipped the records (the history is carried by `touching`):
  // about 65 times in this run.
  REQUIRE(when_read.rebuild_count() >= 20);
  const ParticleStore& a = every.particles();
  const ParticleStore& b = when_read.particles();
  CHECK(same_bits(a.x, b.x));
  CHECK(same_bits(a.v, b.v));
  CHECK(same_bits(a.w, b.w));
  const PairContacts& ca = every.pair_contacts(ContactKind::BallBall);
  const PairContacts& cb = when_read.pair_contacts(ContactKind::BallBall);
  CHECK(same_bits(ca.touching, cb.touching));
  CHECK(same_bits(ca.state.bytes, cb.state.bytes));
  CHECK(same_bits(ca.normal_force, cb.normal_force));
  CHECK(same_bits(ca.force, cb.force));
  CHECK(every.contact_count(ContactKind::BallBall) == when_read.contact_count(ContactKind::BallBall));
  CHECK(every.contact_count(ContactKind::BallBall) > 0);
}

TEST_CASE("contact records: callbacks read current records; a controller needs EveryStep", "[physics][contacts]") {
  SECTION("a callback every 7 steps sees the same contacts in both modes") {
    std::vector<std::size_t> counts[2];
    int m = 0;
    for (auto records : {World::ContactRecords::EveryStep, World::ContactRecords::WhenRead}) {
      World world = colliding_gas(records);
      std::vector<std::size_t>& seen = counts[m++];
      world.add_callback(7, [&seen](World& w) { seen.push_back(w.contact_count(ContactKind::BallBall)); });
      world.step(200);
    }
    CHECK(counts[0].size() == 200 / 7);
    CHECK(counts[0] == counts[1]);
  }
  SECTION("a controller reading contacts throws on a step that skips the records, and works with EveryStep") {
    World world = colliding_gas(World::ContactRecords::WhenRead);
    std::size_t visits = 0;
    world.add_controller([&visits](World& w) { w.for_each_contact([&visits](const ContactView&) { ++visits; }); });
    CHECK_THROWS_AS(world.step(5), std::logic_error);
    world.set_contact_records(World::ContactRecords::EveryStep);
    visits = 0;
    world.step(5);
    CHECK(visits > 0);
  }
}
