// The NGI-type simple-shear cell as a part of a protocol: two facet plates (discs reaching under
// the rings) and a stack of clump rings around a cylindrical specimen, added to a World the
// caller owns. The cell does not step the world; a protocol's controller calls move_rings() every
// step so that the rings move as the ring mode says (docs/model.md 4).
#pragma once

#include <cstddef>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/history_log.hpp>

namespace dem::lab {

/// How the rings move vertically once the specimen is made (docs/model.md 4).
enum class RingVertical {
  Fixed,       ///< held at their generation heights
  Follow,      ///< each ring moves with the specimen: its height interpolated between the plates
  Prescribed,  ///< follow, and the horizontal displacement is prescribed linear in height (diagnostic)
  Free,        ///< free in z too: each ring rides on the sand next to it, no vertical side friction on balance
  Sand,        ///< each ring moves vertically with the mean vertical velocity of the balls touching it
};

/// The cell's geometry, in SI units; z up, the bottom plate at z = 0.
struct ShearCellSpec {
  double diameter = 0.070;        // m, of the specimen
  double height = 0.022;          // m, plate gap as built
  double pebble_diameter = 7e-4;  // m, of the ring pebbles; also the height of one ring
  double ring_gap = 3.5e-5;       // m, vertical gap between rings
  double ring_density = 2700.0;   // kg/m^3, of the solid ring the pebbles stand for
  double stack_height = 0.0;      // m, height the ring stack covers; 0: `height`
  double max_opening = 0.0;       // m; > 0: every opening of the stack must be smaller
  RingVertical rings = RingVertical::Follow;
};

/// A cell in a world: its plates and rings, and the plate gap as built.
struct ShearCell {
  WallId bottom = -1, top = -1;
  std::size_t first_ring = 0, ring_count = 0;  // the rings are world.clumps()[first_ring, +ring_count)
  double radius = 0.0;         // m, of the specimen
  double built_height = 0.0;   // m, plate gap as built
  double area = 0.0;           // m^2, specimen cross-section: the plates' loaded area
  double pebble_radius = 0.0;  // m
  RingVertical rings = RingVertical::Follow;

  /// Top minus bottom plate height now (m).
  double plate_gap(const World& world) const;
};

/// Adds the plates and the ring stack (rings held in every degree of freedom: release_rings()
/// frees them once the specimen is made). InputError for a spec the ring stack refuses.
ShearCell build_shear_cell(World& world, const ShearCellSpec& spec);

/// Radial push of the sand on the rings (Pa): the outward radial components of the ball-pebble
/// contact forces over the specimen's lateral surface at the current plate gap.
double ring_lateral_stress(const World& world, const ShearCell& cell);

/// Sets the rings' velocities for this step from the plates' (call it after the plates' velocities
/// are set). While the specimen is made (`specimen_made` false) every mode but Fixed interpolates
/// the vertical velocity between the plates; afterwards Follow and Prescribed interpolate (and
/// Prescribed also horizontally), Sand takes the mean vertical velocity of the balls touching each
/// ring, and Free and Fixed leave the rings to the engine.
/// A simulation spread over processes (World::spread_over) runs every mode but Sand, which reads
/// the balls touching each ring during the step: InputError for Sand on more than one process.
void move_rings(World& world, const ShearCell& cell, bool specimen_made);
/// The same check before any work: InputError if `rings` is Sand and `processes` > 1.
void require_rings_spreadable(RingVertical rings, int processes);

/// The plates' affine field: each plate's velocity at its height (the bottom plate's surface, built
/// at z = 0, moved by its displacement), interpolated linearly between them (uniform simple shear,
/// and the servo's vertical motion). Set as the world's damping frame (World::set_damping_frame)
/// while the plates shear the specimen, local damping brakes only the motion about uniform shear,
/// not the layers that move with a plate (docs/model.md 3.1, 8). The plates move: compute it again
/// every step.
DampingFrame plate_damping_frame(const World& world, const ShearCell& cell);

/// Frees the rings for the test, never in rotation: Follow, Sand and Fixed rings move freely in x
/// and y (their vertical velocity is set by move_rings, or zero for Fixed), Free rings in x, y and
/// z; Prescribed rings stay held, moved only by move_rings.
void release_rings(World& world, const ShearCell& cell);

/// Keeps the top plate from moving down this step to a plate gap below `min_gap` (m), by raising
/// its vertical velocity where needed: a servo may lift it, never lower it past that gap. While
/// radii grow, a plate that chased its stress into the loose half-size balls would pack them at
/// the bottom of the cavity. Call it after the servo has set the velocity.
void keep_plate_gap(World& world, const ShearCell& cell, double min_gap);

/// 1 - ball volume / (area x plate gap): the specimen's porosity, overlaps ignored.
double specimen_porosity(const World& world, const ShearCell& cell);

/// Adds each ring's horizontal displacement since it was built (m) to `log`: ring_1_dx, ring_1_dy,
/// ring_2_dx, ... from the bottom ring up.
void add_ring_columns(HistoryLog& log, const World& world, const ShearCell& cell);

}  // namespace dem::lab
