// The one pair geometry: where piece 2 of a contact is seen from piece 1, and the branch vector
// x2 - x1 between them (m), for two particles by storage index. The contact loops (one contact at
// a time and in SIMD blocks), the near lists of the broad phase, the World's contact views and the
// measurements all take it from here; none subtracts two particles' positions itself.
//
// This is the place where a periodic cell will apply its image shift. A contact across a periodic
// face sees piece 2's image, x2 + s with s a sum of the cell's vectors (and in a deforming cell a
// velocity shifted by the cell's rate of deformation times s); a later three-dimensional
// decomposition over processes will hold those images as ghosts, as LAMMPS does. The candidate's
// image then becomes an argument here, and every caller already goes through these functions.
//
// Today there is no shift: the branch is x[j] - x[i], component by component, the operations every
// caller did before (the same bits).
#pragma once

#include <cstddef>

#include <dem/base/math.hpp>
#include <dem/contact/lanes.hpp>

namespace dem {

/// Where piece 2 (storage index `second`) is as seen from piece 1 (`first`), in the positions `x`
/// (m): its own position; its image, once a periodic cell puts the pieces on opposite faces.
DEM_HOT_INLINE const Vec3& partner_position(const Vec3* x, std::size_t /*first*/, std::size_t second) {
  return x[second];
}

/// The branch vector from piece 1 (storage index `first`) to piece 2 (`second`): x2 - x1 (m).
DEM_HOT_INLINE Vec3 branch(const Vec3* x, std::size_t first, std::size_t second) {
  return partner_position(x, first, second) - x[first];
}

/// branch() for the SIMD blocks (Lane3, lanes.hpp): the same operations, the same bits.
DEM_HOT_INLINE Lane3 branch_lanes(const Vec3* x, std::size_t first, std::size_t second) {
  return lane(partner_position(x, first, second)) - lane(x[first]);
}

}  // namespace dem
