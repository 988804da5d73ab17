// Restart files: the World's state plus a text block for the protocol that drives it (stage,
// targets, output counters), framed with a format version and a checksum and written
// atomically, so that a crash never leaves a half file and a damaged file is refused.
#pragma once

#include <filesystem>
#include <string>

#include <dem/core/world.hpp>
#include <dem/io/world_state.hpp>

namespace dem::io {

/// The version a restart file is written with: the layout of its world state (world_state_format).
/// Files of every earlier version are read.
inline constexpr std::uint32_t checkpoint_format_version = world_state_format;

/// Writes `world` and `protocol_state` to `path` (temporary file, fsync, rename).
void save_checkpoint(const std::filesystem::path& path, const World& world, const std::string& protocol_state);

/// Restores `world` (its contact models must already be set, with the same laws) and returns
/// the protocol text. Throws InputError naming the file for a missing, truncated (shorter than
/// its header says), too long (bytes past its end) or corrupted file, another format version,
/// mismatched laws, or a field of the world state outside its allowed range.
std::string load_checkpoint(const std::filesystem::path& path, World& world);

/// The protocol text of a restart file alone (what a protocol asks before it builds a world for
/// the file, e.g. the stage a specimen is in), after the same checks of the file as a whole.
std::string read_checkpoint_protocol(const std::filesystem::path& path);

}  // namespace dem::io
