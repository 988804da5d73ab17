// Guards of a specimen in a shear cell (lab/toolkit/shear_cell.hpp): balls that have left it, and the
// checks a restart file of it passes before a protocol goes on from it with a configuration.
#pragma once

#include <cstddef>
#include <filesystem>
#include <iosfwd>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

/// Balls whose centre has left the specimen: beyond the inner radius of the ring at its height
/// plus a pebble radius, or beyond a plate.
std::size_t balls_outside(const World& world, const ShearCell& cell);

/// Throws InstabilityError naming the first ball that left the specimen, where it is, the step, the
/// time and `shear_strain` (-, for the message) and the likely cause; nothing when none has.
void require_no_escape(const World& world, const ShearCell& cell, double shear_strain);

/// InputError naming `file` when the balls of the world loaded from it are not within the
/// grading of `config` (a specimen resumed under another preset or size scale).
void require_configured_grading(const World& world, const SimpleShearConfig& config, const std::filesystem::path& file);

/// After a restart file is loaded into `world`, which was built as `as_configured` from `config`:
/// applies this configuration's engine.local_damping, engine.max_overlap_ratio, rings.density and
/// a fixed engine.time_step again (each change logged to `log`). Refused with an InputError naming
/// `file`, the key and the file's value: engine.time_step = 0 (automatic) where the file ran a
/// fixed step of another length, another engine.time_step_safety, and the keys of the specimen
/// itself (specimen.density, specimen.height, the ring stack), which the file's specimen was made
/// with (docs/restart.md).
void apply_restart_keys(World& world, const World& as_configured, const ShearCell& cell, const SimpleShearConfig& config,
                        const std::filesystem::path& file, std::ostream& log);

}  // namespace dem::lab
