// The lateral confinement of an NGI-type simple-shear specimen: a stack of rings around the
// cylindrical specimen, each ring a rigid clump of pebbles (docs/model.md 4). The sand pushes the rings
// passively; each ring is free to translate horizontally and is fixed in rotation, so the stack keeps
// the cross-section constant and follows the shear profile layer by layer. Vertically the rings are
// fixed here; a protocol may move them (lab::SimpleShearTest moves each with the specimen height).
//
// Why clumps and not a cylindrical facet wall: a facet wall only moves with a prescribed velocity,
// and a prescribed velocity concentrates load at the boundary (the study's reason, docs/model.md 4).
//
// Geometry of the stack built here (z up, all rings coaxial with the specimen):
//   - pebble centres lie on the circle of radius a + r_peb, so the pebbles' inner surfaces are
//     tangent to the specimen radius a;
//   - each ring layer has the fewest pebbles n for which neighbouring centres are at most r_peb
//     apart (chord 2 (a + r_peb) sin(pi/n) <= r_peb): neighbours overlap by at least a radius, so
//     the inner surface is nearly smooth (the bumps are at most (1 - sqrt(3)/2) r_peb = 0.13 r_peb
//     deep) and a ball cannot nest between two pebbles;
//   - a ring taller than one pebble diameter has several layers, equally spaced with centres at
//     most r_peb apart vertically, the lowest and highest layers tangent to the ring's faces;
//   - every layer of every ring has a pebble at azimuth 0 (+x): pebbles line up vertically, which
//     gives the largest openings, so the openings reported are upper bounds for any azimuthal
//     offset. Shearing the stack (neighbouring rings shifted by delta) widens the holes between
//     rings to about sqrt(chord^2 + (2 r_peb + gap)^2 + delta^2) - 2 r_peb: check large strains.
//   - ring k (from 0 at the bottom) spans z0 + k (h_ring + gap) to z0 + k (h_ring + gap) + h_ring.
// Mass and inertia are those of the solid ring the pebbles stand for (thick cylinder shell, inner
// radius a, outer a + 2 r_peb, height h_ring), not of the overlapping pebbles.
#pragma once

#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>
#include <dem/boundary/clump.hpp>
#include <dem/core/particles.hpp>

namespace dem {

/// Input for a stack of pebble rings around a cylindrical specimen with a vertical (+z) axis.
struct RingStackSpec {
  Vec3 base_centre = Vec3::Zero();  // m, centre of the specimen's bottom face
  double inner_radius = 0.0;   // m, specimen radius a: the pebbles' inner surfaces are tangent to it
  double height = 0.0;         // m, specimen height the stack must cover
  int ring_count = 0;          // rings in the stack; 0: the fewest that cover `height`
  double ring_height = 0.0;    // m, height of one ring, >= 2 pebble_radius (layers stacked if larger)
  double pebble_radius = 0.0;  // m
  double gap = 0.0;            // m, vertical gap between neighbouring rings
  double ring_density = 2700.0;  // kg/m^3, of the solid ring the pebbles stand for (aluminium-like)
  double max_opening = 0.0;    // m; if > 0, every opening must be smaller (give the smallest ball diameter)
  std::uint8_t fixed = dof_z | dof_rotation;  // Dof bits of every ring (NGI rings: free in x and y only)
};

/// Mass properties of a solid thick cylinder shell about its centre, axis z (docs/model.md 4).
struct RingMass {
  double mass = 0.0;            // kg, rho pi (b^2 - a^2) h
  double axial_inertia = 0.0;   // kg m^2, I_zz = m (a^2 + b^2)/2
  double radial_inertia = 0.0;  // kg m^2, I_xx = I_yy = m (3 (a^2 + b^2) + h^2)/12
};

/// Mass and inertia of a thick cylinder shell of inner radius `inner` (m), outer radius `outer`
/// (m), height `height` (m) and density `density` (kg/m^3). Throws InputError unless
/// 0 <= inner < outer, height > 0 and density > 0.
RingMass thick_ring_mass(double inner, double outer, double height, double density);

/// Pebbles in one layer of a ring of the stack (each ring has ring_layer_count layers of them).
/// Validates the spec like make_ring_stack, except for the height coverage and max_opening.
int ring_pebble_count(const RingStackSpec& spec);

/// Pebble layers in one ring. Validates the spec like ring_pebble_count.
int ring_layer_count(const RingStackSpec& spec);

/// Rings the stack has: spec.ring_count, or the fewest that cover spec.height if it is 0.
/// Validates the spec like ring_pebble_count.
int ring_stack_count(const RingStackSpec& spec);

/// Diameter (m) of the largest ball that can pass between the pebbles of the stack as built,
/// through a ring wall or between two rings; 0 if none can. Validates the spec like
/// ring_pebble_count.
double ring_stack_opening(const RingStackSpec& spec);

/// The rings, bottom first, ready for World::add_clump: pebbles in the world frame, centre of mass
/// on the axis at each ring's mid-height, thick-cylinder mass and inertia, `fixed` from the spec,
/// zero velocity. Throws InputError naming the key and value for a non-positive size, a ring lower
/// than a pebble diameter, a stack lower than `height`, an opening of max_opening or more, or more
/// than 1e7 pebbles in all.
std::vector<ClumpSpec> make_ring_stack(const RingStackSpec& spec);

}  // namespace dem
