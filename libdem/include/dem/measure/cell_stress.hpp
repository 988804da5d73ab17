// The stress of a periodic cell (boundary/periodic_cell.hpp): the whole cell is the averaging
// volume, so the Love-Weber sum runs over every contact, each with its branch vector to the image
// it touches, plus the kinetic (Reynolds) term of the particles' velocities about the cell's mean
// flow (docs/model.md 13):
//
//   sigma = -(1 / V) [ sum_c F_c (outer) d_c  +  sum_p m_p u_p (outer) u_p ],   V = det h,
//
// with F_c the force on piece 2, d_c = x2 + h n - x1 the branch vector (core/pair_geometry.hpp),
// and u_p = v_p - L (x_p - origin) a particle's velocity relative to the affine field of the
// velocity gradient L. Tension positive, as the measurement sphere's stress (docs/model.md 6.1):
// an output quotes -sigma (compression positive). The contact part is symmetrised as the
// measurement sphere's; the kinetic part is symmetric already.
//
// Contacts are those of the last step (World::for_each_contact: positive normal force), with the
// positions and cell as they are when it is read.
#pragma once

#include <dem/core/math.hpp>

namespace dem {

class World;

namespace measure {

struct CellStress {
  Mat3 stress = Mat3::Zero();    // Pa, tension positive: contact_part + kinetic_part
  Mat3 contact_part = Mat3::Zero();  // Pa, the Love-Weber sum over the contacts (symmetric part)
  Mat3 kinetic_part = Mat3::Zero();  // Pa, the particles' velocity fluctuations
  double volume = 0.0;           // m^3, det h
};

/// The stress of the World's periodic cell. InputError without a periodic cell.
CellStress cell_stress(const World& world);

}  // namespace measure
}  // namespace dem
