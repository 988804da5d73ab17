#include <dem/lab/toolkit/shear_cell.hpp>

#include <dem/core/errors.hpp>

#include <algorithm>
#include <vector>

#include <dem/boundary/clump_ring.hpp>
#include <dem/geometry/mesh.hpp>

namespace dem::lab {

double ShearCell::plate_gap(const World& world) const {
  return (built_height + world.wall(top).displacement.z()) - world.wall(bottom).displacement.z();
}

ShearCell build_shear_cell(World& world, const ShearCellSpec& spec) {
  ShearCell cell;
  const double radius = spec.diameter / 2;
  cell.radius = radius;
  cell.built_height = spec.height;
  cell.area = pi * radius * radius;
  cell.rings = spec.rings;
  // Plates: discs reaching under the rings, loaded over the specimen's cross-section.
  const double plate_radius = radius + 2.0 * spec.pebble_diameter;
  cell.bottom = world.add_wall(
      make_facet_wall("bottom", geometry::make_disc(Vec3::Zero(), plate_radius, -Vec3::UnitZ(), 24), -Vec3::UnitZ(), cell.area));
  cell.top = world.add_wall(make_facet_wall(
      "top", geometry::make_disc(Vec3(0, 0, spec.height), plate_radius, Vec3::UnitZ(), 24), Vec3::UnitZ(), cell.area));
  RingStackSpec rings;
  rings.inner_radius = radius;
  rings.height = spec.stack_height > 0 ? spec.stack_height : spec.height;
  rings.ring_height = spec.pebble_diameter;
  rings.pebble_radius = spec.pebble_diameter / 2;
  rings.gap = spec.ring_gap;
  rings.ring_density = spec.ring_density;
  rings.max_opening = spec.max_opening;
  rings.fixed = dof_all;  // held while the specimen is made; release_rings() frees them
  cell.pebble_radius = rings.pebble_radius;
  cell.first_ring = world.clumps().size();
  for (const ClumpSpec& ring : make_ring_stack(rings)) world.add_clump(ring);
  cell.ring_count = world.clumps().size() - cell.first_ring;
  return cell;
}

double ring_lateral_stress(const World& world, const ShearCell& cell) {
  double radial = 0.0;  // N
  const ParticleStore& p = world.particles();
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallPebble) return;
    const auto j = static_cast<std::size_t>(c.second);
    const Vec3& centre = world.clumps()[static_cast<std::size_t>(p.clump[j])].x;
    Vec3 outward = c.point - centre;
    outward.z() = 0.0;
    if (outward.norm() > 0) radial += c.force.dot(outward.normalized());
  });
  return radial / (2 * pi * cell.radius * cell.plate_gap(world));
}

DampingFrame plate_damping_frame(const World& world, const ShearCell& cell) {
  const Wall& bottom = world.wall(cell.bottom);
  DampingFrame frame;
  frame.velocity = bottom.velocity;
  frame.height = bottom.displacement.z();
  frame.velocity_gradient = (world.wall(cell.top).velocity - bottom.velocity) / cell.plate_gap(world);
  return frame;
}

// docs/model.md 4: with Follow, ring k keeps its fraction s_k = (z_k - z_b) / H of the height
// between the plates: v_k,z = v_b,z + s_k (v_t,z - v_b,z), so z_k - z_b - s_k H is invariant under
// the step (both move by v dt). Prescribed rings also interpolate horizontally.
void require_rings_spreadable(RingVertical rings, int processes) {
  // Sand reads inside the step, where a World spread over processes holds only its own subdomain.
  if (rings == RingVertical::Sand && processes > 1)
    throw InputError("rings.vertical = sand: the rings follow the balls touching them, read during each step, which a "
                     "simulation spread over " + std::to_string(processes) +
                     " processes does not gather; use fixed, follow, prescribed or free, or run it in one process");
}

void move_rings(World& world, const ShearCell& cell, bool specimen_made) {
  if (cell.rings == RingVertical::Fixed) return;
  // Free rings follow the plates only while the specimen is made; then the sand carries them.
  if (cell.rings == RingVertical::Free && specimen_made) return;
  const Wall& top = world.wall(cell.top);
  const Wall& bottom = world.wall(cell.bottom);
  const double z_bottom = bottom.displacement.z(), gap = cell.plate_gap(world);
  const bool prescribed = cell.rings == RingVertical::Prescribed && specimen_made;
  // Sand rings: the mean vertical velocity of the balls touching each ring (the interpolation
  // while the specimen is made, or for a ring that touches none).
  std::vector<double> sand_vz, touching;
  if (cell.rings == RingVertical::Sand && specimen_made) {
    require_rings_spreadable(cell.rings, world.ranks());
    sand_vz.assign(world.clumps().size(), 0.0);
    touching.assign(world.clumps().size(), 0.0);
    const PairContacts& pebbles = world.pair_contacts(ContactKind::BallPebble);
    const ParticleStore& p = world.particles();
    for (std::size_t k = 0; k < pebbles.size(); ++k) {
      if (!pebbles.touching[k]) continue;
      const auto ring = static_cast<std::size_t>(p.clump[static_cast<std::size_t>(pebbles.second[k])]);
      sand_vz[ring] += p.v[static_cast<std::size_t>(pebbles.first[k])].z();
      touching[ring] += 1.0;
    }
  }
  for (std::size_t k = cell.first_ring; k < cell.first_ring + cell.ring_count; ++k) {
    Clump& ring = world.clumps()[k];
    const double s = (ring.x.z() - z_bottom) / gap;
    const Vec3 v = bottom.velocity + s * (top.velocity - bottom.velocity);
    ring.v.z() = !touching.empty() && touching[k] > 0 ? sand_vz[k] / touching[k] : v.z();
    if (prescribed) ring.v.x() = v.x(), ring.v.y() = v.y();
  }
}

void release_rings(World& world, const ShearCell& cell) {
  const std::uint8_t fixed = cell.rings == RingVertical::Prescribed ? dof_all
                             : cell.rings == RingVertical::Free     ? dof_rotation
                                                                    : dof_z | dof_rotation;
  for (std::size_t k = cell.first_ring; k < cell.first_ring + cell.ring_count; ++k) {
    Clump& ring = world.clumps()[k];
    ring.fixed = fixed;
    if (cell.rings == RingVertical::Fixed) ring.v.z() = 0.0;
  }
}

void keep_plate_gap(World& world, const ShearCell& cell, double min_gap) {
  Wall& top = world.wall(cell.top);
  const double room = cell.plate_gap(world) - min_gap;  // m, >= 0
  top.velocity.z() = std::max(top.velocity.z(), -room / world.time_step());
}

double specimen_porosity(const World& world, const ShearCell& cell) {
  const ParticleStore& p = world.particles();
  double solid = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) solid += 4.0 / 3.0 * pi * p.radius[i] * p.radius[i] * p.radius[i];
  return 1.0 - solid / (cell.area * cell.plate_gap(world));
}

void add_ring_columns(HistoryLog& log, const World& world, const ShearCell& cell) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < cell.ring_count; ++k)
    for (const char* axis : {"dx", "dy"}) names.push_back("ring_" + std::to_string(k + 1) + "_" + axis);
  if (names.empty()) return;
  log.add(names, [&world, &cell](std::vector<double>& row) {
    for (std::size_t k = 0; k < cell.ring_count; ++k) {
      const Vec3& d = world.clumps()[cell.first_ring + k].displacement;
      row.insert(row.end(), {d.x(), d.y()});
    }
  });
}

}  // namespace dem::lab
