// The one check every reader makes before it opens an input file: the path must be a regular file
// of a plausible size. A FIFO would block the read forever, a device such as /dev/zero would be
// read until memory runs out, and a folder reads as nothing; each is refused by name before it is
// opened, in the words of the option or key that named it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace dem {

/// Throws InputError "<what> = <path>: <what it is>; must be <allowed>" unless `path` is a regular
/// file (symbolic links followed) of at most `max_bytes` bytes. `what` names the option or key,
/// e.g. "--from" or "cyclic.series_file"; `allowed` says what it should be, e.g. "a restart file".
void require_input_file(const std::filesystem::path& path, const std::string& what, const std::string& allowed,
                        std::uintmax_t max_bytes);

/// Sizes above which an input of each kind cannot be valid, in bytes: a configuration is a few
/// KB, a CSV curve or series a few MB, a restart file some 250 B per particle.
inline constexpr std::uintmax_t max_text_input_bytes = std::uintmax_t{1} << 30;        // 1 GiB
inline constexpr std::uintmax_t max_restart_file_bytes = std::uintmax_t{1} << 40;     // 1 TiB

}  // namespace dem
