// The stress of a periodic cell (measure/cell_stress.hpp): a face-centred cubic lattice of equal
// balls, every neighbour pair a linear spring already compressed, under a small affine strain
// (the cell and the balls deformed together, the cell skewed): the Love-Weber sum over contacts
// across the faces gives the springs' analytic stress; and a rigid rotation of the cell, images
// moving with it (Lees-Edwards velocity shift), leaves it unchanged.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>

#include <dem/measure/cell_stress.hpp>

#include "support/periodic_lattice.hpp"

using namespace dem;
using namespace dem::testing;

namespace {

/// The springs' stress (Pa, tension positive): each ball's six neighbour pairs d = F d0, each
/// pushing with kn (2R - |d|) along d, summed over the balls and divided by the volume.
Mat3 spring_stress(const Mat3& deformation) {
  const double a = lattice_constant();
  const std::array<Vec3, 6> half_shell{Vec3(1, 1, 0), Vec3(1, -1, 0), Vec3(1, 0, 1),
                                       Vec3(1, 0, -1), Vec3(0, 1, 1), Vec3(0, 1, -1)};
  Mat3 moment = Mat3::Zero();
  for (const Vec3& d0 : half_shell) {
    const Vec3 d = deformation * (0.5 * a * d0);
    const double length = d.norm();
    moment += lattice_stiffness * (2.0 * radius - length) * (d / length) * d.transpose();
  }
  const double balls = 4.0 * std::pow(lattice_cells, 3);
  const double volume = deformation.determinant() * std::pow(lattice_cells * a, 3);
  return -balls / volume * moment;
}

double largest(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("cell stress: a face-centred cubic lattice under a small strain gives its springs' stress",
          "[physics][periodic][cell-stress]") {
  Mat3 strain;
  strain << 1.0, 0.5, 0.2,
            0.5, -0.7, 0.3,
            0.2, 0.3, 0.4;
  const Mat3 deformation = Mat3::Identity() + 1e-3 * strain;  // skews the cell
  World world = fcc_lattice(deformation);
  world.step(1);
  const measure::CellStress measured = measure::cell_stress(world);
  const Mat3 expected = spring_stress(deformation);
  INFO("measured\n" << measured.stress << "\nexpected\n" << expected);
  CHECK(world.contact_count(ContactKind::BallBall) == 6u * 4u * 27u);  // every neighbour, across the faces too
  CHECK(largest(measured.stress - expected) <= 1e-9 * largest(expected));
  CHECK(largest(measured.kinetic_part) <= 1e-12 * largest(expected));
  CHECK(measured.volume == Approx(deformation.determinant() * std::pow(lattice_cells * lattice_constant(), 3)));
}

TEST_CASE("cell stress: a rigid rotation of a compressed lattice leaves its stress as it was",
          "[physics][periodic][cell-stress]") {
  const Mat3 deformation = (1.0 - 1e-3) * Mat3::Identity();  // isotropic: the stress is too
  World world = fcc_lattice(deformation);
  const Vec3 spin(0.3, -0.5, 0.8);  // rad/s
  Mat3 rotation_rate;             // W x = spin x x
  rotation_rate << 0, -spin.z(), spin.y(),
                   spin.z(), 0, -spin.x(),
                   -spin.y(), spin.x(), 0;
  world.set_velocity_gradient(rotation_rate);
  world.set_time_step(1e-7);
  ParticleStore& p = world.particles();
  for (std::size_t i = 0; i < p.size(); ++i) p.v[i] = rotation_rate * p.x[i], p.w[i] = spin;
  world.step(1);
  const Mat3 before = measure::cell_stress(world).stress;
  world.step(20);
  const Mat3 after = measure::cell_stress(world).stress;
  INFO("before\n" << before << "\nafter\n" << after);
  CHECK(world.periodic_cell()->matrix()(1, 0) != 0.0);  // the cell turned
  CHECK(largest(after - before) <= 1e-9 * largest(before));
}
