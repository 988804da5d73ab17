// Temporary + fsync + rename. The fsync goes through a POSIX descriptor because std::ofstream
// cannot reach the kernel's page cache; without it a power cut after rename can leave an empty
// file under the new name on some file systems (ext4 delayed allocation).
#include "dem/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "dem/core/errors.hpp"

namespace dem::io {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int error) {
  return error == 0 ? std::string("unknown error") : std::string(std::strerror(error));
}

[[noreturn]] void fail(const fs::path& path, const std::string& what, const std::string& why) {
  throw std::runtime_error("cannot write " + path.string() + ": " + what + ": " + why);
}

void check_target(const fs::path& path) {
  require(!path.empty() && path.has_filename(), "output path", path.string(),
          "a file name (not empty, not ending in '/')");
  std::error_code ec;
  require(!fs::is_directory(path, ec), "output path", path.string(),
          "a file, but it is an existing directory");
  const fs::path parent = path.parent_path();
  if (!parent.empty() && !fs::exists(parent, ec)) {
    fs::create_directories(parent, ec);
    if (ec) fail(path, "creating directory " + parent.string(), ec.message());
  }
}

void fsync_file(const fs::path& file, const fs::path& target) {
  const int fd = ::open(file.c_str(), O_WRONLY);
  if (fd < 0) fail(target, "reopening " + file.string() + " for fsync", errno_text(errno));
  const int sync_result = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  if (sync_result != 0) fail(target, "fsync of " + file.string(), errno_text(sync_errno));
}

// Makes the rename itself durable. Best effort: some file systems refuse fsync on directories,
// and the new file's content is already safe at this point.
void fsync_directory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  static_cast<void>(::fsync(fd));
  ::close(fd);
}

void write_via_temporary(const fs::path& path, const std::function<void(std::ostream&)>& write,
                         std::ios::openmode mode) {
  check_target(path);
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());

  auto remove_temporary = [&temporary] {
    std::error_code ignored;
    fs::remove(temporary, ignored);
  };
  try {
    {
      errno = 0;
      std::ofstream out(temporary, mode | std::ios::out | std::ios::trunc);
      if (!out) fail(path, "opening temporary " + temporary.string(), errno_text(errno));
      write(out);
      out.flush();
      if (!out) fail(path, "writing temporary " + temporary.string(), errno_text(errno));
      out.close();
      if (!out) fail(path, "closing temporary " + temporary.string(), errno_text(errno));
    }
    fsync_file(temporary, path);
    std::error_code ec;
    fs::rename(temporary, path, ec);
    if (ec) fail(path, "renaming " + temporary.string() + " onto it", ec.message());
  } catch (...) {
    remove_temporary();
    throw;
  }
  fsync_directory(path.parent_path());
}

}  // namespace

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  write_via_temporary(path, write, std::ios::openmode{});
}

void write_atomically_binary(const fs::path& path,
                             const std::function<void(std::ostream&)>& write) {
  write_via_temporary(path, write, std::ios::binary);
}

}  // namespace dem::io
