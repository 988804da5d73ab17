// A World's state (WorldState) as a binary stream: the body of a restart file (checkpoint.hpp adds
// the framing). Doubles are written as their bytes, so a run resumed from it continues bit for
// bit. Contact models, controllers and callbacks are code, not state: the caller sets them up
// again before reading.
#pragma once

#include <cstdint>
#include <iosfwd>

#include <dem/core/world.hpp>

namespace dem::io {

/// The layout write_world_state writes. 2 added the walls' analytic surfaces and their contacts
/// at the end; 3 the periodic cell after them (a flag, then its origin, matrix, velocity gradient,
/// periodic axes and tilt re-map flag, its matrix at the last rebuild, and the pair contacts'
/// image codes); 4 the bonds after it (their ids, parameters, state and status, one array each).
/// Layouts 1 and 2 (no cell) and 3 (no bonds) are still read.
inline constexpr std::uint32_t world_state_format = 4;

/// Writes the complete dynamic state of `world` (the law name of each contact kind, then its
/// WorldState: clock, settings that shape the trajectory, particles, clumps, walls, contact lists
/// with their law history, and the record of the last rebuild).
void write_world_state(std::ostream& out, const World& world);

/// Replaces the state of `world` with one written by write_world_state. The contact models must
/// already be set, with the same laws as when it was written (checked by name). Every count, index
/// and value a later step trusts is checked first: InputError naming the field on a mismatch, a
/// value out of range or a truncated stream, and then `world` is unchanged (World::restore).
/// `format`: the layout the stream was written in (a restart file's header says it).
void read_world_state(std::istream& in, World& world, std::uint32_t format = world_state_format);

}  // namespace dem::io
