// A face-centred cubic lattice of equal balls in a periodic cell, every neighbour pair overlapping,
// for the cell's stress and control tests.
#pragma once

#include <array>
#include <cmath>

#include "scenes.hpp"

namespace dem::testing {

inline constexpr double lattice_stiffness = 4e4;      // N/m, kn = ks of the linear law
inline constexpr int lattice_cells = 3;               // unit cells along each edge of the periodic cell
inline constexpr double lattice_overlap = 0.01 * 2.0 * radius;  // m, of every neighbour pair before a strain

inline double lattice_constant() { return std::sqrt(2.0) * (2.0 * radius - lattice_overlap); }  // m

/// The lattice of `cells`^3 unit cells, deformed by x -> F x, in its periodic cell, with the linear
/// law (kn = ks = lattice_stiffness, friction 0.5).
inline World fcc_lattice(const Mat3& deformation, WorldSettings settings = dynamic_settings(1e-9),
                         int cells = lattice_cells) {
  World world(settings);
  const double a = lattice_constant();
  const std::array<Vec3, 4> basis{Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (const Vec3& b : basis)
          world.add_ball(ball_at(deformation * ((Vec3(i, j, k) + b + Vec3::Constant(0.25)) * a)));
  world.set_periodic_cell(PeriodicCell(deformation * (cells * a * Mat3::Identity())));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(
                                                     LinearParams::constant(lattice_stiffness, lattice_stiffness, 0.5)));
  return world;
}

}  // namespace dem::testing
