// An exclusive lock on a folder for as long as a run writes into it: flock on a lock file in the
// folder, released by the kernel when the process ends, even when it is killed. The lock file
// holds who took it (pid, program, start time), which a refused run names.
#pragma once

#include <filesystem>
#include <string>

namespace dem::io {

class FolderLock {
 public:
  /// Creates `folder / lock_name` if needed and locks it. InputError naming the folder: in use by
  /// another process (named from the lock file), or not writable. `program` goes into the file.
  FolderLock(const std::filesystem::path& folder, const std::string& lock_name, const std::string& program);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace dem::io
