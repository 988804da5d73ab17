#include <dem/measure/cell_stress.hpp>

#include <dem/base/errors.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/core/world.hpp>

namespace dem::measure {

CellStress cell_stress(const World& world) {
  const PeriodicCell* cell = world.periodic_cell();
  require(cell != nullptr, "cell stress", "asked of a World without a periodic cell",
          "asked of a World with one (World::set_periodic_cell); a measurement sphere measures open specimens");
  CellStress out;
  out.volume = cell->volume();
  const ParticleStore& p = world.particles();
  Mat3 contact_moment = Mat3::Zero();  // N m, sum_c F_c (outer) d_c
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind == ContactKind::BallFacet) return;  // none in a fully periodic cell
    const auto i = c.first, j = static_cast<std::size_t>(c.second);
    contact_moment += c.force * branch(p.x.data(), i, j, c.image_shift).transpose();
  });
  Mat3 momentum_flux = Mat3::Zero();  // kg m^2/s^2, sum_p m u u
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 u = p.v[i] - cell->affine_velocity(p.x[i]);
    momentum_flux += p.mass[i] * u * u.transpose();
  }
  out.contact_part = 0.5 * (contact_moment + contact_moment.transpose()) * (-1.0 / out.volume);
  out.kinetic_part = momentum_flux * (-1.0 / out.volume);
  out.stress = out.contact_part + out.kinetic_part;
  return out;
}

}  // namespace dem::measure
