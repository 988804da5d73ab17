#include <dem/io/output_folder.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <dem/core/errors.hpp>

namespace fs = std::filesystem;

namespace dem::io {

namespace {

// "<name>.tmp.<pid>" of a process that no longer runs: what write_atomically leaves when killed.
// Only the temporaries of files a run writes are ones: <name> one of the run's files, or a restart
// file; a user's own "notes.tmp.12" is not.
bool is_leftover_temporary(const fs::path& file, const std::vector<std::string>& run_files, bool in_run_folder) {
  const std::string name = file.filename().string();
  const auto at = name.rfind(".tmp.");
  if (at == std::string::npos || at + 5 >= name.size()) return false;
  const std::string target = name.substr(0, at);
  const bool written_by_a_run = in_run_folder || target.ends_with(".restart") ||
                                std::find(run_files.begin(), run_files.end(), target) != run_files.end();
  if (!written_by_a_run) return false;
  const std::string digits = name.substr(at + 5);
  if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  const auto pid = static_cast<pid_t>(std::stol(digits));
  if (pid == ::getpid()) return false;
  return ::kill(pid, 0) != 0 && errno == ESRCH;
}

// The leftovers in the folder, and in the run's own folders in it (snapshots/, ...).
std::size_t remove_leftovers(const fs::path& folder, const std::vector<std::string>& run_files) {
  std::size_t removed = 0;
  auto sweep = [&](const fs::path& dir, bool in_run_folder) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(dir, error)) {
      std::error_code ignored;
      if (entry.is_regular_file(ignored) && is_leftover_temporary(entry.path(), run_files, in_run_folder) &&
          fs::remove(entry.path(), ignored))
        ++removed;
    }
  };
  sweep(folder, false);
  for (const std::string& name : run_files) {
    std::error_code ignored;
    if (fs::is_directory(folder / name, ignored)) sweep(folder / name, true);
  }
  return removed;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace

std::vector<std::string> existing_run_files(const fs::path& folder, const std::vector<std::string>& run_files) {
  std::vector<std::string> found;
  for (const std::string& name : run_files) {
    std::error_code error;
    if (fs::exists(folder / name, error)) found.push_back(name);
  }
  return found;
}

OutputFolder::OutputFolder(fs::path folder, const OutputFolderPolicy& policy) : folder_(std::move(folder)) {
  require(!folder_.empty(), "output folder", "(empty)", "a folder path");
  const std::string where = "output folder " + folder_.string();
  std::error_code error;
  if (fs::exists(folder_, error) && !fs::is_directory(folder_, error))
    throw InputError(where + " is a file, not a folder: choose a folder for the results");
  fs::create_directories(folder_, error);
  if (error) throw InputError(where + " cannot be created: " + error.message());

  lock_ = std::make_unique<FolderLock>(folder_, ".lock", policy.program);

  // The lock file may be writable where new files are not (an old lock in a read-only folder).
  const fs::path probe = folder_ / (".write-test." + std::to_string(::getpid()));
  const int probe_fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (probe_fd < 0) {
    const std::string reason = std::strerror(errno);
    lock_.reset();
    throw InputError(where + " is not writable (" + reason + ")");
  }
  ::close(probe_fd);
  fs::remove(probe, error);

  // Leftovers are swept only once the folder is accepted: a refused run changes nothing in it.
  if (policy.continues_own_run) {
    leftovers_removed_ = remove_leftovers(folder_, policy.run_files);
    return;
  }
  const std::vector<std::string> found = existing_run_files(folder_, policy.run_files);
  if (found.empty()) {
    leftovers_removed_ = remove_leftovers(folder_, policy.run_files);
    return;
  }
  if (!policy.replace) {
    lock_.reset();
    throw InputError(where + " holds the results of another run (" + joined(found) + "): choose another folder, or " +
                     policy.replace_option + " to remove them first");
  }
  for (const std::string& name : found) {
    fs::remove_all(folder_ / name, error);
    if (error) throw InputError(where + ": cannot remove " + name + " of the run it held: " + error.message());
    replaced_.push_back(name);
  }
  leftovers_removed_ = remove_leftovers(folder_, policy.run_files);
}

OutputFolder::~OutputFolder() = default;

}  // namespace dem::io
