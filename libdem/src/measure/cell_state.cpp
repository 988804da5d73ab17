#include <dem/measure/cell_state.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include <dem/base/errors.hpp>
#include <dem/core/world.hpp>

namespace dem::measure {

CellStrain cell_strain(const Mat3& reference, const Mat3& now) {
  require(reference.allFinite() && reference.determinant() > 0.0, "reference cell determinant", reference.determinant(),
          "> 0 m^3 (a cell matrix: three right-handed, independent edges)");
  CellStrain out;
  const Mat3 f = now * reference.inverse();
  out.deformation_gradient = f;
  out.small_strain = 0.5 * (f + f.transpose()) - Mat3::Identity();
  // V^2 = F F^T: its eigenvectors are V's, its eigenvalues V's squared.
  const Eigen::SelfAdjointEigenSolver<Mat3> left(f * f.transpose());
  const Vec3 stretch_sq = left.eigenvalues();
  const Mat3& axes = left.eigenvectors();
  const Vec3 log_stretch = 0.5 * stretch_sq.array().log().matrix();
  const Vec3 inverse_stretch = stretch_sq.array().rsqrt().matrix();
  out.logarithmic_strain = axes * log_stretch.asDiagonal() * axes.transpose();
  out.rotation = axes * inverse_stretch.asDiagonal() * axes.transpose() * f;  // R = V^-1 F
  out.volumetric_strain = log_stretch.sum();
  return out;
}

CellPacking cell_packing(const World& world) {
  const PeriodicCell* cell = world.periodic_cell();
  require(cell != nullptr, "cell packing", "asked of a World without a periodic cell",
          "asked of a World with one (World::set_periodic_cell)");
  CellPacking out;
  const ParticleStore& p = world.particles();
  out.volume = cell->volume();
  out.balls = p.size();
  double solid = 0.0;  // m^3
  for (const double r : p.radius) solid += 4.0 / 3.0 * pi * r * r * r;
  out.porosity = 1.0 - solid / out.volume;
  out.void_ratio = out.porosity / (1.0 - out.porosity);
  std::vector<int> contacts_of(p.size(), 0);
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallBall) return;
    ++out.contacts;
    ++contacts_of[c.first];
    ++contacts_of[static_cast<std::size_t>(c.second)];
  });
  long active_contacts = 0, active_balls = 0;
  for (const int n : contacts_of)
    if (n >= 2) active_contacts += n, ++active_balls;
  out.coordination_number = out.balls == 0 ? 0.0 : 2.0 * static_cast<double>(out.contacts) / static_cast<double>(out.balls);
  out.mechanical_coordination_number =
      active_balls == 0 ? 0.0 : static_cast<double>(active_contacts) / static_cast<double>(active_balls);
  return out;
}

}  // namespace dem::measure
