// The one pair geometry: where piece 2 of a contact is seen from piece 1, and the branch vector
// x2 - x1 between them (m), for two particles by storage index. The contact loops (one contact at
// a time and in SIMD blocks), the near lists of the broad phase, the World's contact views and the
// measurements all take it from here; none subtracts two particles' positions itself.
//
// In a periodic cell (boundary/periodic_cell.hpp) piece 2 of a contact may be an image of a
// particle: x2 + s, with s = h n for the contact's image vector n (PairContacts::image), moving at
// v2 + L h n (the Lees-Edwards velocity shift). The World looks each image code's shifts up once a
// step (ImageShifts) and the loops add the contact's `shift` here, so the kinematics of a contact
// across a face are those of the same pair inside the cell. A later three-dimensional
// decomposition over processes will hold partners on other processes as ghosts named the same way
// (the owner's particle plus h n), as LAMMPS treats images and ghosts alike.
//
// Without a periodic cell the loops call the forms without a shift: x[j] - x[i], component by
// component, the operations every caller did before (the same bits, at no cost). With one, a
// contact inside the cell has shift 0 and x[j] + 0 is x[j]: the same bits again.
#pragma once

#include <cstddef>

#include <dem/base/math.hpp>
#include <dem/boundary/periodic_cell.hpp>
#include <dem/contact/contact_sets.hpp>
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

/// The same with piece 2's image shifted by `shift` (m): x2 + shift, and x2 + shift - x1.
DEM_HOT_INLINE Vec3 partner_position(const Vec3* x, std::size_t /*first*/, std::size_t second, const Vec3& shift) {
  return x[second] + shift;
}
DEM_HOT_INLINE Vec3 branch(const Vec3* x, std::size_t first, std::size_t second, const Vec3& shift) {
  return partner_position(x, first, second, shift) - x[first];
}
DEM_HOT_INLINE Lane3 branch_lanes(const Vec3* x, std::size_t first, std::size_t second, const Vec3& shift) {
  return lane(partner_position(x, first, second, shift)) - lane(x[first]);
}

/// Candidate k of a pair set: the shift of its piece 2's image (m), zero without a cell (`images`
/// null, as the World passes when it has none) or for a contact inside the cell.
inline Vec3 image_shift_of(const PairContacts& c, std::size_t k, const ImageShifts* images) {
  return images != nullptr && k < c.image.size() ? images->position[c.image[k]] : Vec3::Zero();
}
/// The branch vector of candidate k of a pair set, its image included, in positions `x` (m): for
/// the code outside the hot loops (near lists, contact views, measurements).
inline Vec3 contact_branch(const PairContacts& c, std::size_t k, const Vec3* x, const ImageShifts* images) {
  const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
  if (images == nullptr) return branch(x, i, j);
  return branch(x, i, j, image_shift_of(c, k, images));
}

}  // namespace dem
