#include <dem/io/output_folder.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fstream>
#include <optional>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <dem/core/errors.hpp>

#include "json_file.hpp"

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

// A manifest's entry: a path inside the folder, as a run records it ("snapshots/balls_0.vtp").
bool is_inside_entry(const std::string& entry) {
  const fs::path path(entry);
  if (entry.empty() || path.is_absolute() || path.lexically_normal().string() != entry) return false;
  for (const auto& part : path)
    if (part == ".." || part == ".") return false;
  return true;
}

// The files the run that wrote `folder` listed (nullopt: no manifest, a run before manifests).
std::optional<std::vector<std::string>> read_manifest(const fs::path& folder) {
  const fs::path file = folder / manifest_file_name;
  std::error_code error;
  if (!fs::exists(file, error)) return std::nullopt;
  const std::string where = "the manifest " + file.string() + " (the files a run wrote, JSON)";
  if (!fs::is_regular_file(file, error) || fs::file_size(file, error) > (64u << 20))
    throw InputError(where + " is not a regular file under 64 MB: remove it, and the run files beside it, yourself");
  std::ifstream in(file);
  Json document;
  try {
    document = Json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(where + " cannot be read (" + quoted_excerpt(e.what()) +
                     "): remove it, and the run files beside it, yourself");
  }
  if (!document.is_object() || !document.contains("files") || !document["files"].is_array())
    throw InputError(where + " has no list \"files\": remove it, and the run files beside it, yourself");
  std::vector<std::string> entries;
  for (const auto& item : document["files"]) {
    const std::string entry = item.is_string() ? item.get<std::string>() : item.dump();
    if (!item.is_string() || !is_inside_entry(entry))
      throw InputError(where + " lists " + quoted_excerpt(entry) +
                       ", not a path inside the folder: remove the manifest, and the run files beside it, yourself");
    entries.push_back(entry);
  }
  return entries;
}

bool is_listed(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
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

OutputFolder::OutputFolder(fs::path folder, const OutputFolderPolicy& policy)
    : folder_(std::move(folder)), program_(policy.program) {
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

  // Leftovers are swept, and old results removed, only once the folder is accepted: a refused
  // run changes nothing in it.
  const std::optional<std::vector<std::string>> listed = read_manifest(folder_);
  const auto declare = [&] {
    for (const std::string& name : policy.run_files)
      if (!is_listed(manifest_, name)) manifest_.push_back(name);
  };
  if (policy.continues_own_run) {
    if (listed) manifest_ = *listed;
    declare();
    leftovers_removed_ = remove_leftovers(folder_, policy.run_files);
    save_manifest();
    return;
  }
  std::vector<std::string> found = existing_run_files(folder_, policy.run_files);
  if (listed)
    for (const std::string& entry : existing_run_files(folder_, *listed)) {
      const std::string top = fs::path(entry).begin()->string();
      if (!is_listed(found, top)) found.push_back(top);
    }
  if (!found.empty() && !policy.replace) {
    lock_.reset();
    throw InputError(where + " holds the results of another run (" + joined(found) + "): choose another folder, or " +
                     policy.replace_option + " to remove them first");
  }
  if (!found.empty()) {
    // What goes: the files the other run listed, or, before manifests, its plain files by name. A
    // run folder goes only once empty; before manifests nobody can tell its files from a user's.
    std::vector<std::string> doomed = listed ? *listed : policy.run_files;
    if (!listed)
      for (const std::string& name : found)
        if (fs::is_directory(folder_ / name, error) && !fs::is_empty(folder_ / name, error)) {
          lock_.reset();
          throw InputError(where + " holds " + name + "/ of a run that kept no " + manifest_file_name +
                           " (a libdem before manifests), so its files cannot be told from others': remove " + name +
                           "/ yourself, or choose another folder");
        }
    for (const std::string& entry : doomed) {
      const fs::path path = folder_ / entry;
      if (!fs::exists(fs::symlink_status(path, error)) || fs::is_directory(fs::symlink_status(path, error))) continue;
      fs::remove(path, error);
      if (error) throw InputError(where + ": cannot remove " + entry + " of the run it held: " + error.message());
      const std::string top = fs::path(entry).begin()->string();
      if (!is_listed(replaced_, top)) replaced_.push_back(top);
    }
    for (auto entry = doomed.rbegin(); entry != doomed.rend(); ++entry) {  // inner folders first
      const fs::path path = folder_ / *entry;
      if (!fs::is_directory(fs::symlink_status(path, error))) continue;
      if (fs::is_empty(path, error)) {
        fs::remove(path, error);
        if (!is_listed(replaced_, *entry)) replaced_.push_back(*entry);
      } else if (!is_listed(kept_, *entry)) {
        kept_.push_back(*entry);
      }
    }
    fs::remove(folder_ / manifest_file_name, error);
  }
  declare();
  leftovers_removed_ = remove_leftovers(folder_, policy.run_files);
  save_manifest();
}

void OutputFolder::record(const fs::path& file) {
  const std::string entry = file.lexically_normal().lexically_relative(folder_.lexically_normal()).string();
  if (!is_inside_entry(entry) || is_listed(manifest_, entry)) return;
  manifest_.push_back(entry);
  save_manifest();
}

void OutputFolder::save_manifest() const {
  Json document;
  document["program"] = program_;
  document["files"] = manifest_;
  save_json(folder_ / manifest_file_name, document);
}

OutputFolder::~OutputFolder() = default;

}  // namespace dem::io
