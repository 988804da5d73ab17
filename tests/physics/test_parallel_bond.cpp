// The linear parallel bond (contact/parallel_bond.hpp): two bonded balls moved by prescribed small
// relative motions (no gravity, no damping, every degree of freedom held at its velocity) carry
// the force and moments of a beam of the bond's disc; each mode breaks at its strength on the
// first step past it; bonds follow their balls through rebuilds and re-sorts, resume bit for bit
// from a restart file, give the same bits on one and two threads, and act across a periodic face
// as inside the cell.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

#include <dem/contact/bond_material.hpp>
#include <dem/io/world_state.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double dt = 1e-7;          // s
constexpr double gap = 0.01 * radius;  // m, between the two balls' surfaces
constexpr double kn = 4e11, ks = 1.5e11;  // Pa/m
constexpr std::int64_t steps = 100;
// Ball 2 sits along a slanted axis, so that no component is trivially zero.
const Vec3 axis = Vec3(1.0, 2.0, -0.5).normalized();
const Vec3 across = axis.cross(Vec3::UnitZ()).normalized();  // a direction in the bond plane

ParallelBondLaw::Params bond_params(double tensile = 1e12, double cohesion = 1e12, double friction_deg = 0.0) {
  ParallelBondLaw::Params p;
  p.radius = 0.8 * radius;
  p.normal_stiffness = kn;
  p.shear_stiffness = ks;
  p.tensile_strength = tensile;
  p.cohesion = cohesion;
  p.friction_angle = friction_deg * pi / 180.0;
  return p;
}

std::shared_ptr<const ContactModel> contact_law() {
  return make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1.0, 0.5), "ball-ball");
}

/// Two balls a gap apart along `axis`, bonded, each held at its own velocity and angular
/// velocity (m/s, rad/s).
World bonded_pair(const ParallelBondLaw::Params& p, const Vec3& v2, const Vec3& w2, const Vec3& w1 = Vec3::Zero()) {
  World world(dynamic_settings(dt));
  BallSpec a = ball_at(Vec3(1e-3, 1e-3, 1e-3));
  BallSpec b = ball_at(a.position + (2.0 * radius + gap) * axis, v2);
  a.angular_velocity = w1, b.angular_velocity = w2;
  a.fixed = b.fixed = dof_all;
  world.add_ball(a), world.add_ball(b);
  world.set_contact_model(ContactKind::BallBall, contact_law());
  world.add_bond(0, 1, p);
  return world;
}

/// Relative difference |a - b| / |b|.
double relative(const Vec3& a, const Vec3& b) { return (a - b).norm() / b.norm(); }
double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

constexpr double speed = 1e-5;  // m/s: 1e-10 m in 100 steps, 2e-7 of a radius
constexpr double spin = 1e-2;   // rad/s: 1e-7 rad in 100 steps

}  // namespace

TEST_CASE("parallel bond: axial tension and compression as a bar of the disc", "[physics][bond]") {
  const ParallelBondLaw::Params p = bond_params();
  for (const double sign : {1.0, -1.0}) {
    World world = bonded_pair(p, sign * speed * axis, Vec3::Zero());
    world.step(steps);
    const double stretch = sign * speed * dt * steps;  // m, > 0 pulled apart
    const double expected = kn * p.area() * stretch;   // N, P&C 2004 eq. 11 summed: kn A delta
    INFO("sign " << sign);
    CHECK(relative(world.bonds().normal_force[0], expected) < 1e-9);
    // the force on ball 2 pulls it back (tension) or pushes it away (compression); ball 1 the opposite
    const std::size_t j = world.particles().index_of(1), i = world.particles().index_of(0);
    CHECK(relative(world.particles().f[j], -expected * axis) < 1e-9);
    CHECK(relative(world.particles().f[i], expected * axis) < 1e-9);
    CHECK(world.particles().t[j].norm() < 1e-12 * std::abs(expected) * radius);
  }
}

TEST_CASE("parallel bond: shear as a shear spring of the disc", "[physics][bond]") {
  const ParallelBondLaw::Params p = bond_params();
  World world = bonded_pair(p, speed * across, Vec3::Zero());
  world.step(steps);
  const double expected = ks * p.area() * speed * dt * steps;  // N, ks A delta_s
  CHECK(relative(world.bonds().shear_force[0].norm(), expected) < 1e-9);
  CHECK(relative(world.bonds().shear_force[0], -expected * across) < 1e-6);  // the plane turned by 2e-7 rad
  const ParticleStore& q = world.particles();
  const Vec3 f2 = q.f[q.index_of(1)];
  // the force acts at the bond point, mid-gap: the torques are its moments about each centre
  const Vec3 arm_first = (radius + 0.5 * gap) * axis;
  CHECK(relative(q.t[q.index_of(0)], -arm_first.cross(f2)) < 1e-6);
  CHECK(relative(q.t[q.index_of(1)], -arm_first.cross(f2)) < 1e-6);  // arm_second = -arm_first
}

TEST_CASE("parallel bond: twisting and bending as a shaft and a beam of the disc", "[physics][bond]") {
  const ParallelBondLaw::Params p = bond_params();
  SECTION("twisting: Mt = -ks J theta") {
    World world = bonded_pair(p, Vec3::Zero(), spin * axis);
    world.step(steps);
    const double expected = -ks * p.polar_inertia() * spin * dt * steps;
    CHECK(relative(world.bonds().twist_moment[0], expected) < 1e-9);
    const ParticleStore& q = world.particles();
    CHECK(relative(q.t[q.index_of(1)], expected * axis) < 1e-9);
    CHECK(relative(q.t[q.index_of(0)], -expected * axis) < 1e-9);
    CHECK(q.f[q.index_of(1)].norm() < 1e-9 * std::abs(expected) / radius);
  }
  SECTION("bending: Mb = -kn I theta, the balls turned opposite ways") {
    World world = bonded_pair(p, Vec3::Zero(), spin * across, -spin * across);
    world.step(steps);
    const Vec3 expected = -kn * p.bending_inertia() * 2.0 * spin * dt * steps * across;
    CHECK(relative(world.bonds().bend_moment[0], expected) < 1e-9);
    const ParticleStore& q = world.particles();
    CHECK(relative(q.t[q.index_of(1)], expected) < 1e-9);
    CHECK(q.f[q.index_of(1)].norm() < 1e-9 * expected.norm() / radius);
  }
}

namespace {

/// Steps `world` one step at a time and returns the step on which its bond broke (0: never in
/// `most` steps), checking that the step that breaks it leaves no bond force on ball 2.
std::int64_t breaking_step(World& world, std::int64_t most) {
  for (std::int64_t s = 1; s <= most; ++s) {
    world.step(1);
    if (!world.bonds().intact(0)) {
      CHECK(world.particles().f[world.particles().index_of(1)].norm() == 0.0);  // not touching: the bond only
      return s;
    }
  }
  return 0;
}

constexpr std::int64_t strong_steps = 60;  // a strength reached between steps 60 and 61

}  // namespace

TEST_CASE("parallel bond: each mode breaks on the first step past its strength", "[physics][bond]") {
  const double half = strong_steps + 0.5;
  SECTION("tension: sigma = Fn / A") {
    World world = bonded_pair(bond_params(kn * speed * dt * half), speed * axis, Vec3::Zero());
    CHECK(breaking_step(world, 2 * strong_steps) == strong_steps + 1);
    CHECK(world.bonds().status_of(0) == BondStatus::broken_tension);
  }
  SECTION("shear: tau = |Fs| / A against the cohesion") {
    World world = bonded_pair(bond_params(1e12, ks * speed * dt * half), speed * across, Vec3::Zero());
    CHECK(breaking_step(world, 2 * strong_steps) == strong_steps + 1);
    CHECK(world.bonds().status_of(0) == BondStatus::broken_shear);
  }
  SECTION("shear under compression: the strength c - (Fn / A) tan(phi) rises with it") {
    const double phi = 30.0, closing = 0.5 * speed, sliding = speed;
    // per step: tau grows by ks sliding dt, the strength by kn closing dt tan(phi)
    const double net = ks * sliding * dt - kn * closing * dt * std::tan(phi * pi / 180.0);
    REQUIRE(net > 0.0);
    World world = bonded_pair(bond_params(1e12, net * half, phi), sliding * across - closing * axis, Vec3::Zero());
    CHECK(breaking_step(world, 2 * strong_steps) == strong_steps + 1);
    CHECK(world.bonds().status_of(0) == BondStatus::broken_shear);
  }
  SECTION("bending: sigma = |Mb| R / I, in tension") {
    const ParallelBondLaw::Params p0 = bond_params();
    const double per_step = kn * 2.0 * spin * dt * p0.radius;  // Pa, |Mb| R / I grows by this
    World world = bonded_pair(bond_params(per_step * half), Vec3::Zero(), spin * across, -spin * across);
    CHECK(breaking_step(world, 2 * strong_steps) == strong_steps + 1);
    CHECK(world.bonds().status_of(0) == BondStatus::broken_tension);
  }
  SECTION("twisting: tau = |Mt| R / J, in shear") {
    const ParallelBondLaw::Params p0 = bond_params();
    const double per_step = ks * spin * dt * p0.radius;  // Pa, |Mt| R / J grows by this
    World world = bonded_pair(bond_params(1e12, per_step * half), Vec3::Zero(), spin * axis);
    CHECK(breaking_step(world, 2 * strong_steps) == strong_steps + 1);
    CHECK(world.bonds().status_of(0) == BondStatus::broken_shear);
  }
}

TEST_CASE("parallel bond: a broken bond leaves the pair to its contact law", "[physics][bond]") {
  World world = bonded_pair(bond_params(kn * speed * dt * 10.5), speed * axis, Vec3::Zero());
  world.step(20);
  REQUIRE(world.bonds().status_of(0) == BondStatus::broken_tension);
  const ParallelBondLaw::State kept = world.bonds().state(0);  // the loads that broke it, kept
  world.step(20);
  CHECK(world.bonds().normal_force[0] == kept.normal_force);  // a broken bond's loads are not stepped
  CHECK(world.particles().f[0].norm() == 0.0);                // apart: nothing acts
}

TEST_CASE("parallel bond: a bond broken in tension releases kn A delta^2 / 2", "[physics][bond]") {
  // Pulled apart at a constant speed, the bond's force is kn A delta (a linear spring), so the
  // energy it holds when it breaks at stretch delta is kn A delta^2 / 2; the shear, twisting and
  // bending parts are zero but for rounding (the motion is along the line of centres).
  const ParallelBondLaw::Params p = bond_params(kn * speed * dt * 10.5);  // breaks on step 11
  World world = bonded_pair(p, speed * axis, Vec3::Zero());
  CHECK(world.bonds().released_energy() == 0.0);
  const std::int64_t broke = breaking_step(world, 20);
  REQUIRE(broke == 11);
  const double delta = speed * dt * static_cast<double>(broke);  // m, stretch at the breaking step
  const double expected = 0.5 * kn * p.area() * delta * delta;    // J
  CHECK(relative(world.bonds().released_energy(), expected) < 1e-9);
  CHECK(relative(ParallelBondLaw::strain_energy(p, world.bonds().state(0)), expected) < 1e-9);
  world.step(10);  // released once: stepping on adds nothing
  CHECK(relative(world.bonds().released_energy(), expected) < 1e-9);
  // and kept through a restart file (format 4 keeps a broken bond's loads)
  std::stringstream file;
  io::write_world_state(file, world);
  World loaded = bonded_pair(bond_params(), Vec3::Zero(), Vec3::Zero());
  io::read_world_state(file, loaded);
  CHECK(loaded.bonds().released_energy() == world.bonds().released_energy());
}

TEST_CASE("parallel bond: the bond's stiffness counts in the critical time step", "[physics][bond]") {
  World world = bonded_pair(bond_params(), Vec3::Zero(), Vec3::Zero());
  World plain(dynamic_settings(dt));
  plain.add_ball(ball_at(Vec3(1e-3, 1e-3, 1e-3))), plain.add_ball(ball_at(Vec3(1e-3, 1e-3, 1e-3) + (2.0 * radius + gap) * axis));
  plain.set_contact_model(ContactKind::BallBall, contact_law());
  const ParallelBondLaw::Params p = bond_params();
  const double bond_dt = std::sqrt(ball_mass() / ((kn + ks) * p.area()));  // sqrt(m / k) on translation
  CHECK(plain.critical_time_step() > bond_dt);
  CHECK(world.critical_time_step() <= bond_dt);
}

TEST_CASE("parallel bond: the material draws each bond's strengths from its key", "[bond]") {
  ParallelBondMaterial m;
  m.normal_stiffness = kn, m.shear_stiffness = ks;
  m.tensile_strength = 1e6, m.tensile_strength_std = 2e5, m.cohesion = 2e6, m.cohesion_std = 4e5;
  m.seed = 7;
  const ParallelBondLaw::Params a = m.draw(3, 9, radius, 2 * radius);
  const ParallelBondLaw::Params b = m.draw(9, 3, 2 * radius, radius);
  CHECK(a.tensile_strength == b.tensile_strength);  // either order, the same bond
  CHECK(a.radius == radius);
  double sum = 0.0, sum_sq = 0.0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const double s = m.draw(k, k + 1, radius, radius).tensile_strength;
    sum += s, sum_sq += s * s;
  }
  const double mean = sum / n, std = std::sqrt(sum_sq / n - mean * mean);
  CHECK(std::abs(mean - 1e6) < 4.0 * 2e5 / std::sqrt(n));  // within four standard errors
  CHECK(std::abs(std - 2e5) < 0.05 * 2e5);
  m.seed = 8;
  CHECK(m.draw(3, 9, radius, radius).tensile_strength != a.tensile_strength);
  m.radius_multiplier = 1.5;
  CHECK_THROWS_WITH(m.validate("cementation"), Catch::Contains("cementation.radius_multiplier = 1.5: must be in (0, 1]"));
}

namespace {

/// A jittered cubic block of 1,331 balls with random velocities and spins, neighbours bonded when
/// closer than 1.05 x their radii, strengths drawn so that some bonds break within a few hundred
/// steps; contacts come and go beside the bonds.
World bonded_block(int threads, int sort_every) {
  WorldSettings s = dynamic_settings(2e-8);
  s.threads = threads;
  s.adapt_threads = false;  // a busy machine must not leave the two-thread path untried
  s.sort_every = sort_every;
  s.skin = 2e-6;  // m: the lists are remade every few hundred steps
  World world(s);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> jitter(-0.01 * radius, 0.01 * radius);
  std::normal_distribution<double> velocity(0.0, 0.2);
  const int side = 11;
  const double a = 2.0 * radius;  // m: neighbours touch, give or take the jitter
  std::vector<BallSpec> balls;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k) {
        BallSpec b = ball_at(Vec3(i, j, k) * a + Vec3(jitter(rng), jitter(rng), jitter(rng)),
                             Vec3(velocity(rng), velocity(rng), velocity(rng)));
        b.angular_velocity = Vec3(velocity(rng), velocity(rng), velocity(rng)) * 1e3;
        balls.push_back(b);
      }
  std::shuffle(balls.begin(), balls.end(), rng);  // ids in no spatial order: a cell-order sort moves them
  for (const BallSpec& b : balls) world.add_ball(b);
  world.set_contact_model(ContactKind::BallBall, contact_law());
  ParallelBondMaterial m;
  m.radius_multiplier = 0.7, m.normal_stiffness = 2e11, m.shear_stiffness = 1e11;
  m.tensile_strength = 6e5, m.tensile_strength_std = 2e5, m.cohesion = 8e5, m.cohesion_std = 2e5;
  m.friction_angle = 0.5, m.seed = 3;
  const ParticleStore& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if ((p.x[j] - p.x[i]).norm() < (p.radius[i] + p.radius[j]) * 1.05)
        world.add_bond(p.id[i], p.id[j], m.draw(p.id[i], p.id[j], p.radius[i], p.radius[j]));
  return world;
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

}  // namespace

TEST_CASE("parallel bond: bonds follow their balls through rebuilds and re-sorts", "[physics][bond]") {
  // Re-sorting every rebuild against never: the balls move in storage, the bonds keep their ids.
  World sorted = bonded_block(1, 1), unsorted = bonded_block(1, 0);
  sorted.step(300), unsorted.step(300);
  sorted.rebuild_now(true);
  sorted.step(100), unsorted.step(100);
  REQUIRE(sorted.rebuild_count() > 3);
  const ParticleStore& p = sorted.particles();
  bool moved = false;
  for (std::size_t i = 0; i < p.size(); ++i) moved = moved || p.id[i] != static_cast<ParticleId>(i);
  REQUIRE(moved);
  const BondStore& a = sorted.bonds();
  const BondStore& b = unsorted.bonds();
  REQUIRE(a.size() > 1000);
  std::size_t broken = a.size() - a.count(BondStatus::intact);
  INFO(broken << " of " << a.size() << " bonds broke");
  CHECK(broken > 0);                 // some broke ...
  CHECK(broken < a.size() / 2);      // ... most hold
  CHECK(a.status == b.status);
  // Contact sums follow storage order, so the two runs differ in the last bits: the bonds' loads
  // must agree to rounding, bond by bond.
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double scale = std::abs(b.normal_force[k]) + b.shear_force[k].norm() + 1e-3;
    REQUIRE(std::abs(a.normal_force[k] - b.normal_force[k]) < 1e-6 * scale);
  }
}

TEST_CASE("parallel bond: a bonded block resumes from a restart file bit for bit", "[physics][bond][restart]") {
  World first = bonded_block(1, 1);
  first.step(250);
  std::stringstream saved;
  io::write_world_state(saved, first);
  World resumed = bonded_block(1, 1);
  io::read_world_state(saved, resumed);
  REQUIRE(resumed.bonds().size() == first.bonds().size());
  first.step(250), resumed.step(250);
  REQUIRE(first.rebuild_count() > 2);
  std::stringstream a, b;
  io::write_world_state(a, first), io::write_world_state(b, resumed);
  REQUIRE(a.str() == b.str());
  CHECK(first.bonds().count(BondStatus::intact) < first.bonds().size());
}

TEST_CASE("parallel bond: one and two threads give the same bits", "[physics][bond][threads]") {
  World one = bonded_block(1, 1), two = bonded_block(2, 1);
  one.step(400), two.step(400);
  REQUIRE(two.pair_plan(ContactKind::BallBall).shares.size() == 3);  // the pair loop ran on two threads
  REQUIRE(static_cast<std::int64_t>(two.bonds().size()) >= min_parallel_items);  // and the bonds' blocks
  REQUIRE(two.bonds().count(BondStatus::intact) < two.bonds().size());           // some of them broke
  const ParticleStore& p = one.particles();
  const ParticleStore& q = two.particles();
  REQUIRE(same_bits(p.x, q.x));
  REQUIRE(same_bits(p.v, q.v));
  REQUIRE(same_bits(p.w, q.w));
  REQUIRE(same_bits(one.bonds().shear_force, two.bonds().shear_force));
  REQUIRE(one.bonds().normal_force == two.bonds().normal_force);
  REQUIRE(one.bonds().status == two.bonds().status);
}

TEST_CASE("parallel bond: across a periodic face as inside the cell", "[physics][bond][periodic]") {
  // The same bonded pair, sheared and twisted, in open space and with ball 2 across the cell's
  // x face (ball 1 is bonded to its image x2 + h e_x): the bond's force is the same to rounding.
  const ParallelBondLaw::Params p = bond_params();
  const Vec3 v2 = speed * (axis + across), w2 = spin * (axis - across);
  World open = bonded_pair(p, v2, w2);
  const double edge = 8e-3;  // m
  World cell(dynamic_settings(dt));
  BallSpec a = ball_at(Vec3(edge - 0.6 * radius, 4e-3, 4e-3));
  BallSpec b = ball_at(a.position + (2.0 * radius + gap) * axis - Vec3(edge, 0.0, 0.0), v2);  // across x = edge
  b.angular_velocity = w2;
  a.fixed = b.fixed = dof_all;
  cell.add_ball(a), cell.add_ball(b);
  cell.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(edge)));
  cell.set_contact_model(ContactKind::BallBall, contact_law());
  cell.add_bond(0, 1, p);
  open.step(steps), cell.step(steps);
  const double scale = open.bonds().shear_force[0].norm();
  REQUIRE(scale > 0.0);
  CHECK(std::abs(cell.bonds().normal_force[0] - open.bonds().normal_force[0]) < 1e-6 * scale);
  CHECK((cell.bonds().shear_force[0] - open.bonds().shear_force[0]).norm() < 1e-6 * scale);
  CHECK(std::abs(cell.bonds().twist_moment[0] - open.bonds().twist_moment[0]) <
        1e-6 * std::abs(open.bonds().twist_moment[0]));
  // The bond's branch (what the broken-bond files place the bond point by) goes to the image too:
  // the open pair's, where the stored positions are almost a cell apart.
  const double branch_scale = open.bond_branch(0).norm();
  CHECK((cell.bond_branch(0) - open.bond_branch(0)).norm() < 1e-9 * branch_scale);
  CHECK((cell.particles().x[1] - cell.particles().x[0]).norm() > 0.5 * edge);
}

TEST_CASE("parallel bond: a restart file of format 3 (no bonds) still loads", "[physics][bond][restart]") {
  World plain(dynamic_settings(dt));
  plain.add_ball(ball_at(Vec3(1e-3, 1e-3, 1e-3), Vec3(0.1, 0, 0)));
  plain.add_ball(ball_at(Vec3(1e-3, 1.99e-3, 1e-3)));
  plain.set_contact_model(ContactKind::BallBall, contact_law());
  plain.step(10);
  std::stringstream written;
  io::write_world_state(written, plain);
  const std::string format_4 = written.str();
  constexpr std::size_t bond_bytes = 13 * 8;  // thirteen empty arrays' counts
  std::stringstream format_3(format_4.substr(0, format_4.size() - bond_bytes));
  World loaded(dynamic_settings(dt));
  loaded.set_contact_model(ContactKind::BallBall, contact_law());
  io::read_world_state(format_3, loaded, 3);
  CHECK(loaded.bonds().empty());
  std::stringstream again;
  io::write_world_state(again, loaded);
  CHECK(again.str() == format_4);
  // and a file with a bond naming a ball that is not there is refused, by field
  World bonded = bonded_pair(bond_params(), Vec3::Zero(), Vec3::Zero());
  bonded.step(1);
  std::stringstream with_bond;
  io::write_world_state(with_bond, bonded);
  std::string bytes = with_bond.str();
  // the bonds are the file's last 225 bytes: thirteen counts, two ids, eight doubles, two vectors
  // and a status byte; the second id comes after the first ids (count, id) and its own count
  const std::size_t section = 13 * 8 + 2 * 4 + 8 * 8 + 2 * 24 + 1;
  const std::size_t at = bytes.size() - section + 8 + 4 + 8;
  const std::int32_t missing = 7;
  std::memcpy(&bytes[at], &missing, sizeof missing);
  std::stringstream damaged(bytes);
  World refused = bonded_pair(bond_params(), Vec3::Zero(), Vec3::Zero());
  CHECK_THROWS_WITH(io::read_world_state(damaged, refused), Catch::Contains("bond 0 ball id = 7: must be in [0, 2)"));
}
