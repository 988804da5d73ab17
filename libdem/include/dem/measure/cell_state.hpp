// The homogeneous state of a periodic cell besides its stress (measure/cell_stress.hpp): its strain
// and rotation from the cell matrix, and the packing it holds (porosity, void ratio, coordination).
//
// Strain from a reference cell h0 to the cell h now (docs/model.md 13): the deformation gradient
// F = h h0^-1 = V R (left stretch V, rotation R, by the polar decomposition), the small strain
// sym(F) - I, and the logarithmic (Hencky) strain ln V, whose trace is ln(det F) = ln(V/V0) for
// any path. Extension positive, as continuum mechanics writes them; an output quotes -e for
// compression positive as the simple-shear app does.
#pragma once

#include <cstddef>

#include <dem/core/math.hpp>

namespace dem {

class World;

namespace measure {

struct CellStrain {
  Mat3 deformation_gradient = Mat3::Identity();  // -, F = h h0^-1
  Mat3 small_strain = Mat3::Zero();              // -, (F + F^T)/2 - I
  Mat3 logarithmic_strain = Mat3::Zero();        // -, ln V with F = V R
  Mat3 rotation = Mat3::Identity();              // -, R
  double volumetric_strain = 0.0;                // -, ln(det F) = trace of the logarithmic strain
};

/// The strain of the cell `now` from the cell `reference` (both m, edge vectors as columns; the
/// edges in the same order: a cell re-mapped since (PeriodicCell::remap_tilt) gives the strain of
/// its re-mapped edges, the same up to a lattice symmetry of the tiling). InputError for a
/// reference that is not invertible.
CellStrain cell_strain(const Mat3& reference, const Mat3& now);

struct CellPacking {
  std::size_t balls = 0;
  double volume = 0.0;       // m^3, det h
  double porosity = 0.0;     // -, 1 - sum of ball volumes / V
  double void_ratio = 0.0;   // -, porosity / (1 - porosity)
  std::size_t contacts = 0;  // ball-ball contacts with a positive normal force in the last step
  double coordination_number = 0.0;  // -, 2 contacts / balls
  /// -, over the balls with two contacts or more only (the others, rattlers, carry no load), as
  /// the measurement sphere's (docs/model.md 6.2)
  double mechanical_coordination_number = 0.0;
};

/// The packing of the World's periodic cell. InputError without a cell.
CellPacking cell_packing(const World& world);

}  // namespace measure
}  // namespace dem
