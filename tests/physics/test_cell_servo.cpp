// The periodic cell's servo (control/cell_servo.hpp): a face-centred cubic lattice compressed to
// a target isotropic stress by the servo on the cell's rate, then compressed along z at a
// prescribed rate while x and y keep their stress (a drained triaxial path in miniature).
#include <catch2/catch.hpp>

#include <cmath>

#include <dem/control/cell_servo.hpp>
#include <dem/measure/cell_stress.hpp>

#include "support/periodic_lattice.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

/// The compressive normal stresses (Pa) of the cell's last step.
Vec3 normal_stresses(const World& world) { return -measure::cell_stress(world).stress.diagonal(); }

}  // namespace

TEST_CASE("cell servo: a lattice is brought to an isotropic stress, then held laterally under axial compression",
          "[physics][periodic][cell-servo]") {
  WorldSettings settings;  // local damping 0.7, automatic time step
  World world = fcc_lattice(Mat3::Identity(), settings);
  world.step(1);
  world.update_time_step();  // with the contacts found: a dozen a ball
  const double initial = normal_stresses(world).mean();
  REQUIRE(initial > 0.0);
  const double target = 1.5 * initial;
  auto servo = add_cell_servo(world, CellServoSettings::isotropic(target, 2.0));
  REQUIRE(world.run_until([&](const World&) { return servo->settled(); }, 100, 50'000));
  const Vec3 held = normal_stresses(world);
  INFO("normal stresses " << held.transpose() << " Pa, target " << target);
  for (int a = 0; a < 3; ++a) CHECK(std::abs(held[a] - target) <= 0.01 * target);
  const Mat3 h = world.periodic_cell()->matrix();
  CHECK(h(0, 1) == 0.0);  // prescribed shear rates 0: the cell stays a box
  CHECK(h(0, 0) < 3.0 * lattice_constant());  // it was compressed

  // Axial compression at a prescribed rate; x and y keep their stress.
  const double rate = -0.5;  // 1/s
  servo->set_rate(CellComponent::zz, rate);
  const double height = world.periodic_cell()->matrix()(2, 2);
  const int steps = 3000;
  world.step(steps);
  const Vec3 after = normal_stresses(world);
  INFO("after axial compression " << after.transpose() << " Pa");
  CHECK(std::abs(after.x() - target) <= 0.02 * target);
  CHECK(std::abs(after.y() - target) <= 0.02 * target);
  CHECK(after.z() > 1.05 * target);  // about 0.14 % axial strain on a 1 % overlap
  CHECK(world.periodic_cell()->matrix()(2, 2) == Approx(height * std::exp(rate * world.time_step() * steps)).epsilon(1e-12));
}

TEST_CASE("cell servo: constant volume under axial compression, the lateral stress following a path",
          "[physics][periodic][cell-servo]") {
  WorldSettings settings;  // local damping 0.7, automatic time step
  World world = fcc_lattice(Mat3::Identity(), settings);
  world.step(1);
  world.update_time_step();
  const double target = 1.5 * normal_stresses(world).mean();
  auto servo = add_cell_servo(world, CellServoSettings::isotropic(target, 2.0));
  REQUIRE(world.run_until([&](const World&) { return servo->settled(); }, 100, 50'000));
  // z shortens at 1/s, y keeps the volume, x follows a ramp of stress to 1.1 x target.
  const double start = world.time(), duration = 3000 * world.time_step();
  servo->set_rate(CellComponent::zz, -1.0);
  servo->hold_volume(CellComponent::yy);
  servo->set_stress_path(CellComponent::xx, [=](double t) { return target * (1.0 + 0.1 * std::min(1.0, (t - start) / duration)); });
  const double volume = world.periodic_cell()->volume();
  const double width = world.periodic_cell()->matrix()(1, 1);
  world.step(3500);
  const Vec3 after = normal_stresses(world);
  INFO("after: " << after.transpose() << " Pa, target " << target);
  CHECK(std::abs(world.periodic_cell()->volume() - volume) <= 1e-9 * volume);
  CHECK(world.periodic_cell()->matrix()(1, 1) > width);  // y widened as z shortened
  CHECK(std::abs(after.x() - 1.1 * target) <= 0.02 * target);
  REQUIRE_THROWS_WITH(servo->hold_volume(CellComponent::xy), Catch::Contains("xx, yy or zz"));
}

TEST_CASE("cell servo: bad settings are refused, naming the key", "[physics][periodic][cell-servo]") {
  CellServoSettings s = CellServoSettings::isotropic(1e5, 0.0);
  REQUIRE_THROWS_WITH(CellServo{s}, Catch::Contains("cell servo.max_rate"));
  s.max_rate = 1.0;
  s.relaxation = 2.0;
  REQUIRE_THROWS_WITH(CellServo{s}, Catch::Contains("cell servo.relaxation"));
  World open;
  REQUIRE_THROWS_WITH(add_cell_servo(open, CellServoSettings::isotropic(1e5, 1.0)), Catch::Contains("periodic cell"));
}
