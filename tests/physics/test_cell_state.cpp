// The periodic cell's strain and packing (measure/cell_state.hpp): a stretch along rotated axes
// followed by a rotation gives back its logarithmic strain, rotation and volume change; a small
// simple shear gives half the shear as the small strain; a face-centred cubic lattice has its
// porosity and twelve contacts a ball.
#include <catch2/catch.hpp>

#include <cmath>

#include <dem/measure/cell_state.hpp>

#include "support/periodic_lattice.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

Mat3 rotation_about(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

}  // namespace

TEST_CASE("cell state: a rotated stretch gives back its logarithmic strain, rotation and volume change",
          "[physics][periodic][cell-state]") {
  const Mat3 turn = rotation_about(Vec3(0.3, -0.5, 0.8), 0.4);
  const Mat3 axes = rotation_about(Vec3(1.0, 0.2, -0.4), 0.9);
  const Vec3 stretches(1.1, 0.95, 1.02);
  const Mat3 stretch = axes * stretches.asDiagonal() * axes.transpose();  // U
  Mat3 reference;
  reference << 4e-3, 1e-3, 0.5e-3,
               0.0, 5e-3, -0.7e-3,
               0.0, 0.0, 6e-3;
  const measure::CellStrain strain = measure::cell_strain(reference, turn * stretch * reference);
  const Vec3 log_stretches = stretches.array().log().matrix();
  const Mat3 expected = turn * axes * log_stretches.asDiagonal() * axes.transpose() * turn.transpose();  // ln V, V = R U R^T
  CHECK((strain.logarithmic_strain - expected).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK((strain.rotation - turn).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK(strain.volumetric_strain == Approx(std::log(1.1 * 0.95 * 1.02)).epsilon(1e-12));
  CHECK((strain.deformation_gradient - turn * stretch).cwiseAbs().maxCoeff() <= 1e-12);

  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 1e-4;
  const measure::CellStrain small = measure::cell_strain(reference, shear * reference);
  CHECK(small.small_strain(0, 1) == Approx(0.5e-4).epsilon(1e-9));
  CHECK(small.small_strain(1, 0) == Approx(0.5e-4).epsilon(1e-9));
  CHECK(small.small_strain.diagonal().cwiseAbs().maxCoeff() <= 1e-15);
  REQUIRE_THROWS_AS(measure::cell_strain(Mat3::Zero(), reference), InputError);
}

TEST_CASE("cell state: a face-centred cubic lattice has its porosity and twelve contacts a ball",
          "[physics][periodic][cell-state]") {
  World world = fcc_lattice(Mat3::Identity());
  world.step(1);
  const measure::CellPacking packing = measure::cell_packing(world);
  const double a = lattice_constant();
  const double porosity = 1.0 - 4.0 * (4.0 / 3.0 * pi * radius * radius * radius) / (a * a * a);
  CHECK(packing.balls == 4u * 27u);
  CHECK(packing.porosity == Approx(porosity).epsilon(1e-12));
  CHECK(packing.void_ratio == Approx(porosity / (1.0 - porosity)).epsilon(1e-12));
  CHECK(packing.contacts == 6u * 4u * 27u);
  CHECK(packing.coordination_number == 12.0);
  CHECK(packing.mechanical_coordination_number == 12.0);
  REQUIRE_THROWS_WITH(measure::cell_packing(World()), Catch::Contains("periodic cell"));
}
