// The periodic cell (boundary/periodic_cell.hpp): a contact across a face, an edge or a corner is
// the same pair inside the cell, images moving with the cell's flow (Lees-Edwards); a ball that
// leaves re-enters on the opposite face with its contacts' history; momentum is conserved; the
// results do not depend on the thread count; a restart resumes byte for byte; what is not
// supported yet is refused.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <sstream>

#include <dem/core/block_isa.hpp>
#include <dem/io/world_state.hpp>

#include "support/isa_scope.hpp"
#include "support/periodic_lattice.hpp"
#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

constexpr double cell_edge = 10e-3;  // m

std::shared_ptr<const ContactModel> sand_law() {
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  p.normal_damping_ratio = 0.2;
  return make_contact_model<RollingLinearLaw>(p, "ball-ball");
}

/// The one ball-ball contact of `world`'s last step (force on piece 2), or zero without one.
ContactView only_contact(const World& world) {
  ContactView found{ContactKind::BallBall, 0, 0, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 0.0};
  int count = 0;
  world.for_each_contact([&](const ContactView& c) { found = c, ++count; });
  REQUIRE(count <= 1);
  return found;
}

/// Piece 2's force in world `a` and `b` agree to rounding (both seen from the same ball: `flip`
/// when the pieces are the other way round in b).
void require_same_force(const Vec3& a, const Vec3& b, double scale) {
  INFO("force " << a.transpose() << " against " << b.transpose());
  REQUIRE((a - b).norm() <= 1e-9 * scale);
}

/// A pair in open space and the same pair in a periodic cell, ball 2 placed across the faces
/// `across` (its image x2 + h n touches ball 1): both stepped, the contact force compared every
/// step. The cell shears (L = rate e_x e_z^T), so an image across a z face moves faster in x.
void compare_across(const std::array<int, 3>& across, const Vec3& first_position) {
  const double shear_rate = 50.0;  // 1/s
  Mat3 gradient = Mat3::Zero();
  gradient(0, 2) = shear_rate;
  const Vec3 n(across[0], across[1], across[2]);
  const Vec3 direction = Vec3(n.x() != 0 ? n.x() : 0.3, n.y() != 0 ? n.y() : -0.4, n.z() != 0 ? n.z() : 0.5).normalized();
  const Vec3 branch_vector = (2.0 * radius - 0.02e-3) * direction;
  const Vec3 v1(0.01, -0.02, 0.005), v2(-0.01, 0.01, 0.02), w1(30, -10, 5), w2(-5, 20, 10);
  PeriodicCell cell = PeriodicCell::box(Vec3::Zero(), Vec3::Constant(cell_edge));
  cell.set_velocity_gradient(gradient);
  const Vec3 image_shift = cell.image_shift({across[0], across[1], across[2]});

  World open(dynamic_settings(1e-7)), periodic(dynamic_settings(1e-7));
  BallSpec a = ball_at(first_position, v1), b = ball_at(first_position + branch_vector, v2 + gradient * image_shift);
  a.angular_velocity = w1, b.angular_velocity = w2;
  open.add_ball(a), open.add_ball(b);
  b.position -= image_shift, b.velocity = v2;  // the same ball, in the cell: its image touches a
  for (int axis = 0; axis < 3; ++axis) REQUIRE((b.position[axis] > 0 && b.position[axis] < cell_edge));
  periodic.add_ball(a), periodic.add_ball(b);
  periodic.set_periodic_cell(cell);
  for (World* w : {&open, &periodic}) w->set_contact_model(ContactKind::BallBall, sand_law());
  Vec3 largest = Vec3::Zero();
  for (int s = 0; s < 40; ++s) {
    open.step(1), periodic.step(1);
    INFO("across " << n.transpose() << ", step " << s);
    const ContactView inside = only_contact(open), across_faces = only_contact(periodic);
    REQUIRE(inside.normal_force > 0.0);
    REQUIRE(across_faces.normal_force > 0.0);
    REQUIRE(across_faces.image_shift.norm() > 0.5 * cell_edge);  // the contact is across the faces
    require_same_force(across_faces.force, inside.force, inside.force.norm());
    const ParticleStore& p = periodic.particles();
    const ParticleStore& q = open.particles();
    const std::size_t pa = p.index_of(0), pb = p.index_of(1), qa = q.index_of(0), qb = q.index_of(1);
    REQUIRE((p.w[pa] - q.w[qa]).norm() <= 1e-9 * w1.norm());
    REQUIRE((p.w[pb] - q.w[qb]).norm() <= 1e-9 * w1.norm());
    largest = inside.force;
  }
  // The shear force is part of the force compared: the tangential history and the velocity shift.
  CHECK((largest - largest.dot(branch_vector.normalized()) * branch_vector.normalized()).norm() > 1e-3 * largest.norm());
}

}  // namespace

TEST_CASE("periodic cell: a pair across a face, an edge and a corner feels the force it feels inside the cell",
          "[physics][periodic]") {
  for (const auto isa : {detail::BlockIsa::scalar, detail::detected_block_isa()}) {
    const BlockIsaScope scope(isa);  // both loop paths: one contact at a time, and the SIMD blocks
    INFO("instruction set " << static_cast<int>(detail::block_isa()));
    compare_across({-1, 0, 0}, Vec3(0.3e-3, 5e-3, 5e-3));               // a face
    compare_across({0, 0, 1}, Vec3(5e-3, 5e-3, cell_edge - 0.3e-3));    // the face across the shear
    compare_across({-1, 0, 1}, Vec3(0.3e-3, 5e-3, cell_edge - 0.3e-3));  // an edge
    compare_across({1, -1, -1}, Vec3(cell_edge - 0.3e-3, 0.3e-3, 0.3e-3));  // a corner
  }
}

TEST_CASE("periodic cell: a ball that leaves through a face re-enters with its contact's history",
          "[physics][periodic]") {
  // Two touching balls drift through the face x = edge; ball 2 a little behind ball 1, so that for
  // a while the contact is across the face. The same pair in open space is the reference.
  const Vec3 drift(2.0, 0.0, 0.0);  // m/s
  BallSpec a = ball_at(Vec3(cell_edge - 1e-6, 5e-3, 5e-3), drift + Vec3(0, 0.02, 0.01));
  BallSpec b = ball_at(a.position + Vec3(-3e-6, 2.0 * radius - 0.02e-3, 0.0), drift + Vec3(0, -0.02, -0.01));
  World open(dynamic_settings(1e-8)), periodic(dynamic_settings(1e-8));
  open.add_ball(a), open.add_ball(b);
  periodic.add_ball(a), periodic.add_ball(b);
  periodic.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(cell_edge)));
  for (World* w : {&open, &periodic}) w->set_contact_model(ContactKind::BallBall, sand_law());
  bool seen_across = false;
  for (int s = 0; s < 300; ++s) {
    open.step(1), periodic.step(1);
    INFO("step " << s);
    const ContactView inside = only_contact(open), in_cell = only_contact(periodic);
    REQUIRE(inside.normal_force > 0.0);
    require_same_force(in_cell.force, inside.force, inside.force.norm());
    seen_across = seen_across || in_cell.image_shift.norm() > 0.0;
    if (s % 5 == 4) periodic.rebuild_now(s % 10 == 9);  // wraps now, re-sorting every other time
  }
  const ParticleStore& p = periodic.particles();
  CHECK(seen_across);
  for (ParticleId id : {0, 1}) CHECK(p.x[p.index_of(id)].x() < 0.1e-3);  // both came back at x = 0
  const ContactView last = only_contact(open);
  const Vec3 normal = last.normal;
  CHECK((last.force - last.force.dot(normal) * normal).norm() > 1e-3 * last.force.norm());  // history
}

namespace {

/// A gravity-free periodic gas of `count` balls, colliding, with a drift (m/s, along x and -z)
/// that carries them through the faces.
World periodic_gas(int threads, std::size_t count, double drift = 3.0, double edge = cell_edge) {
  WorldSettings settings = dynamic_settings(0.0);
  settings.threads = threads;
  World world(settings);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> speed(0.0, 0.5);
  const double largest = 0.45e-3;  // m
  const auto balls = separated_balls(count, edge - 2.0 * largest, 0.3e-3, largest, 9);
  for (BallSpec b : balls) {
    b.position += Vec3::Constant(largest);  // none overlaps another's image either
    b.velocity = Vec3(speed(rng) + drift, speed(rng), speed(rng) - 2.0 / 3.0 * drift);
    b.angular_velocity = Vec3(speed(rng), speed(rng), speed(rng)) * 100.0;
    world.add_ball(b);
  }
  world.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(edge)));
  world.set_contact_model(ContactKind::BallBall, sand_law());
  world.update_time_step();
  return world;
}

Vec3 momentum(const World& world) {
  Vec3 m = Vec3::Zero();
  const ParticleStore& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) m += p.mass[i] * p.v[i];
  return m;
}

}  // namespace

TEST_CASE("periodic cell: a colliding gas conserves momentum", "[physics][periodic][conservation]") {
  World one = periodic_gas(1, 400);
  const Vec3 m0 = momentum(one);
  double scale = 0.0;
  for (std::size_t i = 0; i < one.particles().size(); ++i) scale += one.particles().mass[i] * one.particles().v[i].norm();
  std::size_t across = 0;
  one.add_callback(1, [&](World& w) {
    w.for_each_contact([&](const ContactView& c) { across += c.image_shift.norm() > 0.0; });
  });
  one.step(4000);
  INFO("momentum " << momentum(one).transpose() << " against " << m0.transpose());
  CHECK((momentum(one) - m0).norm() <= 1e-12 * scale);
  CHECK(across > 100);            // contacts across the faces took part
  CHECK(one.rebuild_count() > 20);  // and the balls were wrapped many times
  const ParticleStore& p = one.particles();
  for (std::size_t i = 0; i < p.size(); ++i)  // every ball in the cell, to a skin
    for (int a = 0; a < 3; ++a) REQUIRE((p.x[i][a] > -p.radius[i] && p.x[i][a] < cell_edge + p.radius[i]));
}

namespace {

/// A dense, sheared periodic packing: a face-centred cubic lattice of 1,372 balls, every neighbour
/// pair overlapping, positions jittered and velocities random, so that most balls sum a dozen
/// contacts (whose order sets the bits).
World sheared_lattice(int threads) {
  WorldSettings settings = dynamic_settings(0.0);
  settings.threads = threads;
  settings.adapt_threads = false;  // a busy machine must not leave the two-thread path untried
  World world(settings);
  const int cells = 7;
  const double a = std::sqrt(2.0) * (2.0 * radius - 0.01e-3);  // m, lattice constant
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.005 * radius, 0.005 * radius);
  std::normal_distribution<double> speed(0.0, 0.05);
  const std::array<Vec3, 4> basis{Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (const Vec3& b : basis) {
          BallSpec ball = ball_at((Vec3(i, j, k) + b + Vec3::Constant(0.25)) * a + Vec3(jitter(rng), jitter(rng), jitter(rng)),
                                  Vec3(speed(rng), speed(rng), speed(rng)));
          ball.angular_velocity = Vec3(speed(rng), speed(rng), speed(rng)) * 1e3;
          world.add_ball(ball);
        }
  world.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(cells * a)));
  Mat3 gradient = Mat3::Zero();
  gradient(0, 2) = 100.0;  // 1/s: the images' travel remakes the lists every few tens of steps
  world.set_velocity_gradient(gradient);
  world.set_contact_model(ContactKind::BallBall, sand_law());
  world.update_time_step();
  return world;
}

}  // namespace

TEST_CASE("periodic cell: one and two threads give the same bits", "[physics][periodic][threads]") {
  World one = sheared_lattice(1), two = sheared_lattice(2);
  one.step(600), two.step(600);
  REQUIRE(two.pair_plan(ContactKind::BallBall).shares.size() == 3);  // the pair loop ran on two threads
  CHECK(one.rebuild_count() > 4);  // lists remade, the balls wrapped, with the cell skewing
  const ParticleStore& p = one.particles();
  const ParticleStore& q = two.particles();
  REQUIRE(p.size() == q.size());
  REQUIRE(std::memcmp(p.x.data(), q.x.data(), p.size() * sizeof(Vec3)) == 0);
  REQUIRE(std::memcmp(p.v.data(), q.v.data(), p.size() * sizeof(Vec3)) == 0);
  REQUIRE(std::memcmp(p.w.data(), q.w.data(), p.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("periodic cell: a restart of a shearing cell resumes byte for byte", "[physics][periodic][restart]") {
  // The cell shears fast enough that its images' travel, not the balls', sets when the lists are
  // remade: a restart must carry the cell at the last rebuild too.
  Mat3 gradient = Mat3::Zero();
  gradient(0, 1) = 500.0, gradient(2, 2) = -20.0;  // 1/s: shear and compression
  World first = periodic_gas(1, 300, 0.0);
  first.set_velocity_gradient(gradient);
  first.step(300);
  std::stringstream saved;
  io::write_world_state(saved, first);
  World resumed = periodic_gas(1, 300, 0.0);
  io::read_world_state(saved, resumed);
  REQUIRE(resumed.periodic_cell() != nullptr);
  const std::int64_t rebuilds = first.rebuild_count();
  first.step(300), resumed.step(300);
  CHECK(first.rebuild_count() > rebuilds + 20);
  std::stringstream a, b;
  io::write_world_state(a, first), io::write_world_state(b, resumed);
  REQUIRE(a.str() == b.str());
  REQUIRE(first.periodic_cell()->matrix()(0, 1) > 0.0);  // the cell sheared
}

TEST_CASE("periodic cell: what is not supported yet is refused, naming it", "[physics][periodic]") {
  const PeriodicCell cell = PeriodicCell::box(Vec3::Zero(), Vec3::Constant(cell_edge));
  World with_wall;
  with_wall.add_wall(floor_wall(0.0, cell_edge));
  REQUIRE_THROWS_WITH(with_wall.set_periodic_cell(cell), Catch::Contains("no walls"));
  World world;
  world.set_periodic_cell(cell);
  REQUIRE_THROWS_WITH(world.add_wall(floor_wall(0.0, cell_edge)), Catch::Contains("periodic on every axis"));
  PeriodicCell partly = cell;
  partly.set_periodic_axes({true, true, false});
  REQUIRE_THROWS_WITH(World().set_periodic_cell(partly), Catch::Contains("x y z"));
  REQUIRE_THROWS_WITH(World().set_velocity_gradient(Mat3::Zero()), Catch::Contains("periodic cell"));
  REQUIRE_THROWS_AS(PeriodicCell(Mat3::Zero()), InputError);
  WorldState with_cell_and_wall = world.state();  // a state cannot bring in what the API refuses
  with_cell_and_wall.walls.push_back(floor_wall(0.0, cell_edge));
  REQUIRE_THROWS_WITH(world.restore(with_cell_and_wall), Catch::Contains("walls or clumps"));
  // A cell thinner than three search cells: refused at the first step.
  World thin;
  thin.add_ball(ball_at(Vec3::Constant(1e-3)));
  thin.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(3e-3)));
  thin.set_contact_model(ContactKind::BallBall, sand_law());
  thin.set_time_step(1e-7);
  REQUIRE_THROWS_WITH(thin.step(1), Catch::Contains("make the cell larger"));
}

TEST_CASE("periodic cell: a restart file of format 2 (no cell) still loads", "[physics][periodic][restart]") {
  World open(dynamic_settings(1e-7));
  open.add_ball(ball_at(Vec3(1e-3, 1e-3, 1e-3), Vec3(0.1, 0, 0)));
  open.add_ball(ball_at(Vec3(1e-3, 1.99e-3, 1e-3)));
  open.set_contact_model(ContactKind::BallBall, sand_law());
  open.step(10);
  std::stringstream written;
  io::write_world_state(written, open);
  std::string format_4 = written.str();
  // format 4 ends with the cell's flag (none) and the bonds (none: thirteen zero array counts)
  constexpr std::size_t bond_bytes = 13 * 8;
  REQUIRE(format_4.substr(format_4.size() - bond_bytes - 1) == std::string(bond_bytes + 1, '\0'));
  std::stringstream format_2(format_4.substr(0, format_4.size() - bond_bytes - 1));
  World loaded(dynamic_settings(1e-7));
  loaded.set_contact_model(ContactKind::BallBall, sand_law());
  io::read_world_state(format_2, loaded, 2);
  REQUIRE(loaded.periodic_cell() == nullptr);
  std::stringstream again;
  io::write_world_state(again, loaded);
  REQUIRE(again.str() == format_4);
}

namespace {

/// Every touching ball-ball contact's force on its piece 2 (N), by the two balls' ids.
std::map<std::pair<ParticleId, ParticleId>, Vec3> contact_forces(const World& world) {
  std::map<std::pair<ParticleId, ParticleId>, Vec3> forces;
  const ParticleStore& p = world.particles();
  world.for_each_contact([&](const ContactView& c) {
    forces[{p.id[c.first], p.id[static_cast<std::size_t>(c.second)]}] = c.force;
  });
  return forces;
}

}  // namespace

TEST_CASE("periodic cell: re-mapping a sheared cell changes no force", "[physics][periodic][remap]") {
  // A lattice of 256 balls flowing with a cell sheared just short of the tilt limit (0.6), stepped
  // with and without the re-map: where the cell is re-mapped to tilt -0.4, every ball's force is
  // the one of the cell that was not, to rounding, and stays so.
  const double rate = 400.0;  // 1/s, dv_x/dy
  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 0.59;
  Mat3 gradient = Mat3::Zero();
  gradient(0, 1) = rate;
  WorldSettings settings = dynamic_settings(5e-7);
  World remapped = fcc_lattice(shear, settings, 4), skewed = fcc_lattice(shear, settings, 4);
  for (World* w : {&remapped, &skewed}) {
    w->set_velocity_gradient(gradient);
    ParticleStore& p = w->particles();
    for (std::size_t i = 0; i < p.size(); ++i) p.v[i] = gradient * p.x[i], p.w[i] = Vec3(0, 0, -0.5 * rate);
  }
  PeriodicCell no_remap = *skewed.periodic_cell();
  no_remap.set_tilt_remap(false);
  skewed.set_periodic_cell(no_remap);
  const double tilt_to_edge = 1.0 / (4 * lattice_constant());
  for (int s = 0; s < 200; ++s) {
    remapped.step(1), skewed.step(1);
    const auto remapped_forces = contact_forces(remapped), skewed_forces = contact_forces(skewed);
    REQUIRE(remapped_forces.size() == skewed_forces.size());
    double largest = 0.0, differs = 0.0;
    for (const auto& [pair, f] : skewed_forces) {
      REQUIRE(remapped_forces.count(pair) == 1);
      largest = std::max(largest, f.norm());
      differs = std::max(differs, (remapped_forces.at(pair) - f).norm());
    }
    INFO("step " << s << ": tilt " << remapped.periodic_cell()->matrix()(0, 1) * tilt_to_edge << " against "
                 << skewed.periodic_cell()->matrix()(0, 1) * tilt_to_edge);
    REQUIRE(largest > 0.0);
    REQUIRE(differs <= 1e-9 * largest);
    if (s == 60)  // tilt 0.602: this rebuild re-maps
      remapped.rebuild_now(false), skewed.rebuild_now(false);
  }
  CHECK(remapped.periodic_cell()->matrix()(0, 1) * tilt_to_edge == Approx(-0.37).margin(0.005));
  CHECK(skewed.periodic_cell()->matrix()(0, 1) * tilt_to_edge == Approx(0.63).margin(0.005));
}
