// A resumable run: what every protocol's run has, whatever it does to its specimen. It owns the
// World, claims the output folder (locked, checked writable, refused when it holds another run's
// results: io/output_folder.hpp), writes restart files at a steady cadence and on demand, prints
// progress lines with the time left, and keeps the protocol's cursor: the values its stages and
// loops need to go on where a restart file left them (the stage, loop counters, a servo's state).
//
// Each part of a protocol keeps its values under its own keys (keep()); a restart file holds them
// all, beside the World's state and the configuration the run was made with. Resuming, load()
// restores the World and every kept value; the protocol then runs its script from the top: each
// stage skips what its kept values say is done, and each loop starts at its kept counter. Restart
// files are written only between chunks of steps, after the loops have counted the chunk, so a
// resumed run repeats the uninterrupted one exactly.
//
//   Run run(std::make_unique<World>(settings), "out", std::cout);
//   int& stage = ...; run.keep("stage", stage);            // a protocol's cursor
//   if (resuming) run.load("out/restart.restart");          // the World and every kept value
//   for (; increment < 10; ++increment) run.step(50);      // restart.restart every N steps
//   run.save(run.folder() / "final.restart");
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/io/config.hpp>
#include <dem/io/output_folder.hpp>
#include <dem/lab/toolkit/run_record.hpp>

namespace dem::lab {

/// How the output folder is claimed (io::OutputFolderPolicy): the command line's part.
struct OutputOptions {
  bool replace = false;                  // remove the results of another run in the folder
  std::string program = "libdem";        // named in the lock file
  std::string replace_option = "--replace";
  std::vector<std::string> more_run_files{};  // results of a protocol built on this one (cyclic shear)
};

/// The results a protocol writes in its folder, relative to it.
struct RunFiles {
  std::vector<std::string> results;  // every file and folder a run writes (a --replace removes these)
  /// Of them, the ones a run resumed from another folder's restart file goes on writing (a second
  /// shear of one consolidated specimen): copied there first, then trimmed to the restart point.
  std::vector<std::string> carried;
};

class Run {
 public:
  /// `log` receives progress lines and notes; it must outlive the run.
  Run(std::unique_ptr<World> world, std::filesystem::path folder, RunFiles files, std::ostream& log);
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  World& world() { return *world_; }
  const World& world() const { return *world_; }
  std::ostream& log() const { return *log_; }
  /// Where progress lines and notes go from now on (`log` must outlive the run).
  void set_log(std::ostream& log) { log_ = &log; }
  const std::filesystem::path& folder() const { return folder_; }

  // --- the output folder --------------------------------------------------------------------
  /// Claims the folder (io/output_folder.hpp) and, after a load() from another folder, brings the
  /// carried files here. Once per run; the first stage that writes calls claim_if_needed().
  /// Going on in the restart file's own folder removes the summary.json of the session before;
  /// InputError for a run that ended (final.restart there) loaded from an earlier restart file:
  /// that is a second run, for another folder.
  void claim(const OutputOptions& options = {});
  void claim_if_needed() {
    if (!folder_claim_) claim();
  }
  bool claimed() const { return folder_claim_ != nullptr; }
  /// The results of a protocol built on parts made before it knew them (before claim()).
  void set_files(RunFiles files) { files_ = std::move(files); }
  /// Runs `f` at the end of claim(): a part that continues files of a loaded run (the carried
  /// files are here by then).
  void on_claim(std::function<void()> f) { on_claim_.push_back(std::move(f)); }
  /// Lists files this run wrote inside a folder of its results (snapshots/...) in the folder's
  /// manifest, so that a --replace removes them and nothing else (io/output_folder.hpp). The
  /// results named in RunFiles are listed at claim(). Before claim(), and on ranks that do not
  /// claim the folder, nothing.
  void record_outputs(const std::vector<std::filesystem::path>& files);

  // --- the cursor: values restart files keep ------------------------------------------------
  /// Keeps `value` under `key` in every restart file, and sets it from a loaded one (now, if the
  /// run was loaded already, or at load()). Keys are unique; the value must outlive the run.
  void keep(const std::string& key, double& value);
  void keep(const std::string& key, std::int64_t& value);
  void keep(const std::string& key, int& value);
  void keep(const std::string& key, std::size_t& value);
  void keep(const std::string& key, bool& value);
  /// A list of positions (m), written as [[x, y, z], ...] (NaN as null).
  void keep_points(const std::string& key, std::vector<Vec3>& points);
  /// A value kept through two functions: `save` returns the number written, `restore` takes the
  /// number read (range checks belong there: InputError naming the key).
  void keep(const std::string& key, std::function<double()> save, std::function<void(double)> restore);

  // --- restart files ------------------------------------------------------------------------
  /// Steps the world `steps` steps, then writes restart.restart if output.restart_every_steps have
  /// passed since the last one (save_if_due). The kept values must say what comes next by then.
  void step(std::int64_t steps, World::StepEnd end = World::StepEnd::Whole);
  /// restart.restart, if `restart_every` steps have passed since the last restart file.
  void save_if_due();
  void set_restart_every(std::int64_t steps) { restart_every_ = steps; }
  /// Writes the World, the kept values and the configuration record to `file` (atomically).
  void save(const std::filesystem::path& file) const;
  /// Reads a restart file into the World (whose walls, clumps and laws the protocol has made as
  /// configured) and the kept values; returns the file's record (its configuration among it).
  /// Once per run, before claim().
  const ProtocolRecord& load(const std::filesystem::path& file);
  bool loaded() const { return !loaded_from_.empty(); }
  /// The folder of the loaded restart file (empty: none).
  const std::filesystem::path& loaded_folder() const { return loaded_from_; }
  /// The loaded restart file (absolute; empty: none) and the World's step count in it.
  std::filesystem::path loaded_file() const { return loaded() ? loaded_from_ / loaded_name_ : std::filesystem::path(); }
  std::int64_t loaded_step() const { return loaded_step_; }
  const ProtocolRecord& loaded_record() const { return record_; }
  /// Runs `f` at the end of load(), after every kept value is restored.
  void on_load(std::function<void()> f) { on_load_.push_back(std::move(f)); }

  // --- the configuration the run was made with ----------------------------------------------
  /// Keeps every key of `resolved` with its exact value in the restart files (docs/restart.md).
  void record_configuration(const io::Config& resolved);
  const std::vector<std::pair<std::string, std::string>>& configuration() const { return configuration_; }
  /// The keys of the recorded configuration, with their resume rules (empty: none recorded).
  const io::Schema& schema() const { return schema_; }
  /// Notes a key a resumed run changed (key, the file's value, this run's): logged and listed.
  void note_change(const std::string& key, const std::string& file_value, const std::string& new_value);
  const std::vector<std::array<std::string, 3>>& changes() const { return changes_; }

  // --- time and progress --------------------------------------------------------------------
  /// Seconds of wall clock the simulation took so far, over every session of the run (kept).
  double wall_seconds() const { return wall_seconds_; }
  void add_wall_seconds(double seconds) { wall_seconds_ += seconds; }
  void set_progress_every(double seconds) { progress_every_ = seconds; }
  /// A progress line "[stage] detail", at most one every set_progress_every() seconds; with
  /// `done` and `total` (any unit, e.g. a strain), ", N s left" from this session's pace in `stage`.
  void progress(const std::string& stage, const std::string& detail, double done = -1.0, double total = -1.0);

 private:
  struct Kept {
    std::string key;
    std::function<double()> save;
    std::function<void(double)> restore;
    bool integer = false, flag = false;
  };
  void restore(const Kept& kept) const;
  std::string cursor_text() const;

  std::unique_ptr<World> world_;
  std::filesystem::path folder_;
  RunFiles files_;
  std::ostream* log_;
  std::unique_ptr<io::OutputFolder> folder_claim_;
  std::vector<Kept> kept_;
  std::vector<std::pair<std::string, std::vector<Vec3>*>> kept_points_;
  std::vector<std::function<void()>> on_claim_, on_load_;
  std::filesystem::path loaded_from_;
  std::string loaded_name_;  // the loaded restart file's name
  std::int64_t loaded_step_ = 0;
  ProtocolRecord record_;
  std::vector<std::pair<std::string, std::string>> configuration_;
  io::Schema schema_;
  std::vector<std::array<std::string, 3>> changes_;
  std::int64_t restart_every_ = 20000;
  std::int64_t last_restart_step_ = 0;
  double wall_seconds_ = 0.0;
  double progress_every_ = 5.0;
  double last_progress_ = -1e9;
  std::string pace_stage_;
  double pace_start_seconds_ = 0.0, pace_start_done_ = 0.0;
};

}  // namespace dem::lab
