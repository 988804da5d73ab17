// The folder a run writes its results into (--out). Claiming it is the first thing a run does to
// it, after its inputs have been accepted and before any simulation: so a run that would fail on
// the folder fails at once, and a refused run has touched nothing.
//
// Claiming
// - takes an exclusive lock (flock on "<folder>/.lock", released by the kernel when the process
//   ends, even when it is killed): a second run into the folder stops with a message naming the
//   one that holds it (its pid, program and start time, written into the lock file);
// - checks that the folder can be written (a probe file, created and removed);
// - refuses a folder that holds the results of another run (any of `run_files`, or a file its
//   manifest lists), unless the run continues from a restart file in that same folder, or the
//   caller asks to replace it: then the files the other run wrote, as its manifest lists them, are
//   removed together before the run starts, so old and new are never mixed, and nothing else is:
//   a user's file survives in any folder, under any name a run does not write (a run folder
//   such as snapshots/ that still holds one is kept). Results without a manifest (a run of a
//   libdem before manifests) are replaced only where they are plain files named in `run_files`;
// - keeps the manifest, "manifest.json": the files and folders this run writes, as a JSON list
//   of paths relative to the folder, rewritten (atomically) whenever the run records a new one;
// - removes the temporary files ("<name>.tmp.<pid>", see atomic_file.hpp) that a killed run left
//   behind, in the folder and one level below it, when their process is gone.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <dem/io/folder_lock.hpp>

namespace dem::io {

struct OutputFolderPolicy {
  /// Results of another run in the folder are removed instead of refused (--replace).
  bool replace = false;
  /// The run continues from a restart file in this folder: its results are this run's own.
  bool continues_own_run = false;
  /// Files and folders, relative to the folder, that make up a run's results.
  std::vector<std::string> run_files;
  /// How the user asks to replace (named in the refusal), e.g. "--replace".
  std::string replace_option = "--replace";
  /// Who asks, for the lock file and messages, e.g. "dem-simple-shear".
  std::string program = "libdem";
};

/// A claimed output folder; the lock is held until this object is destroyed.
class OutputFolder {
 public:
  /// Creates the folder (with parents) and claims it as described above. Throws dem::InputError
  /// for a folder in use, not writable, a path that is a file, or results of another run without
  /// `policy.replace`; the message names the folder and what to do.
  OutputFolder(std::filesystem::path folder, const OutputFolderPolicy& policy);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& path() const { return folder_; }
  /// Results of an earlier run that were removed (policy.replace), relative to the folder.
  const std::vector<std::string>& replaced() const { return replaced_; }
  /// Temporary files of killed runs that were removed.
  std::size_t leftovers_removed() const { return leftovers_removed_; }
  /// Run folders of the replaced run that were kept because they hold files it did not write.
  const std::vector<std::string>& kept() const { return kept_; }

  /// Lists `file` (a path under path(), as path() / "snapshots/balls_0.vtp") in the manifest as
  /// one of this run's results. A file outside the folder is not a result and is not listed.
  void record(const std::filesystem::path& file);
  /// This run's results, relative to the folder ("name/" for a folder), in the order recorded.
  const std::vector<std::string>& manifest() const { return manifest_; }

 private:
  void save_manifest() const;

  std::filesystem::path folder_;
  std::string program_;
  std::unique_ptr<FolderLock> lock_;  // ".lock" in the folder
  std::vector<std::string> replaced_, kept_, manifest_;
  std::size_t leftovers_removed_ = 0;
};

/// The manifest's file name in a run's folder.
inline constexpr const char* manifest_file_name = "manifest.json";

/// The run files of `run_files` that exist in `folder` (relative names), in the order given.
std::vector<std::string> existing_run_files(const std::filesystem::path& folder, const std::vector<std::string>& run_files);

}  // namespace dem::io
