// Crash-safe file output. Long runs are killed (wall-clock limits, Ctrl-C, full disks) while they
// write logs and snapshots; a reader must then see either the previous complete file or the new
// complete file, never a truncated one. So every writer in dem::io goes through here: write a
// temporary beside the target, fsync it, then rename it over the target (rename is atomic within
// one file system, which is why the temporary lives in the same directory, not in /tmp).
//
// The temporary is named "<path>.tmp.<pid>": two processes never collide, but two threads of one
// process must not write the same path at the same time.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

namespace dem::io {

/// Calls write(stream) on a temporary file next to `path`, flushes and fsyncs it, then renames it
/// onto `path`. Missing parent directories are created. On any failure (the callback throws, the
/// stream goes bad, fsync or rename fails) the temporary is removed and an existing file at `path`
/// is left untouched. Throws dem::InputError for an unusable path (empty, or a directory) and
/// std::runtime_error naming the path and the system's reason for I/O failures; exceptions thrown
/// by `write` propagate unchanged. Text mode.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(std::ostream&)>& write);

/// As write_atomically, with the stream opened in std::ios::binary mode.
void write_atomically_binary(const std::filesystem::path& path,
                             const std::function<void(std::ostream&)>& write);

}  // namespace dem::io
