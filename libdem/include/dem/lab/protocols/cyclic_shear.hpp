// Cyclic and multidirectional simple shear on the NGI ring stack (docs/cyclic-shear.md), as a
// protocol over the lab toolkit: a consolidated specimen of the NGI cell (lab/toolkit/ngi_specimen.hpp),
// an optional static shear stress, a cyclic stage along a path in the horizontal plane
// (lab/toolkit/cyclic_path.hpp) under stress or strain control, drained or at constant volume,
// until a stop criterion, then an optional monotonic shear.
//
// Control: the plates' horizontal motion is a HorizontalDrive (lab/toolkit/horizontal_drive.hpp):
// strain control moves the bottom plate exactly on the path, stress control servoes the top plate
// on its own horizontal force, capped at cyclic.servo_max_speed.
// Drainage. Constant volume holds both plates' heights (the equivalent of an undrained test);
// the excess pore pressure is du = sigma_v0 - sigma_v and r_u = du / sigma_v0, with sigma_v the
// top plate's vertical stress and sigma_v0 its value when the cyclic test begins (the end of
// the consolidation). Drained keeps the vertical servo on sigma_v.
//
// Time. The path's clock is the step count: one cycle is cyclic.period over the time step at the
// start of the stage, rounded to a whole number of steps per history row (rows_per_cycle rows a
// cycle), so rows fall at exact cycle fractions. The automatic time step is re-estimated at
// neighbour-list rebuilds (by a few per cent at most), and a cycle's duration in seconds (the
// history's time column) varies by as much; a quasi-static test does not notice. The stop criteria
// (r_u, double-amplitude strain over the last cycle, the number of cycles) are checked at every
// row, and the run stops at the first row that meets one.
//
// Resumable anywhere (lab/toolkit/run.hpp): restart files are written between rows in every stage;
// the cycle table is rebuilt from the history rows a resumed run keeps.
//
// Outputs in the run's folder: cyclic_history.csv (columns below), cycles.csv
// (lab/toolkit/cycle_log.hpp), summary.json (the specimen, the settings, N_L by each criterion, the
// stop), cyclic_fabric.csv and cyclic_snapshots/ at the chosen cycles; history.csv, fabric.csv and
// snapshots/ of the consolidation when the test makes its own specimen.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <dem/io/csv.hpp>
#include <dem/lab/protocols/cyclic_shear_config.hpp>
#include <dem/lab/toolkit/cycle_log.hpp>
#include <dem/lab/toolkit/cyclic_path.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/horizontal_drive.hpp>
#include <dem/lab/toolkit/ngi_specimen.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/shear_outputs.hpp>

namespace dem::lab {

class BrokenBondLog;
class FabricLog;
class SnapshotWriter;

/// The stages of the test, as the history's phase column numbers them.
enum class CyclicPhase : int { Static = 0, Cyclic = 1, Post = 2 };

/// How the cyclic stage ended and when each liquefaction criterion was first met.
struct CyclicOutcome {
  double cycles = 0.0;           // -, N at the last cyclic row
  std::string stop;              // "pore pressure ratio", "double-amplitude strain", "cycles", "series end"
  double cycles_to_ru = NAN;     // -, N at the first row with r_u >= cyclic.ru_limit (NaN: never)
  double cycles_to_da_strain = NAN;  // -, N at the first row with double-amplitude strain >= cyclic.da_strain_limit
  double vertical_stress_initial = 0.0;  // Pa, sigma_v0
  double consolidated_height = 0.0;      // m, H_c
  double period = 0.0;                   // s, as stepped
  double wall_seconds = 0.0;             // s
};

/// Reads what the configuration names outside itself (the series file), so that a program can
/// refuse bad input before it makes a specimen: InputError naming the file and the problem.
void check_cyclic_inputs(const CyclicShearConfig& config);

class CyclicShearTest {
 public:
  /// A test that makes its own specimen in `out_dir` (or goes on from load_restart()): the NGI
  /// specimen of `specimen_config`, then the cyclic stages of `config`.
  CyclicShearTest(SimpleShearConfig specimen_config, CyclicShearConfig config, std::filesystem::path out_dir, std::ostream& log);
  /// The cyclic stages on a specimen made by another protocol in `run` (its folder, its restart
  /// files); both must outlive the test, and the specimen must be consolidated when run() starts.
  /// With `log`, the run's lines go there from now on (it must outlive the run).
  CyclicShearTest(Run& run, NgiSpecimen& specimen, CyclicShearConfig config, std::ostream* log = nullptr);
  ~CyclicShearTest();
  CyclicShearTest(const CyclicShearTest&) = delete;
  CyclicShearTest& operator=(const CyclicShearTest&) = delete;

  void record_configuration(const io::Config& resolved) { run_.record_configuration(resolved); }
  /// Goes on from a restart file: a consolidated specimen, or one in any cyclic stage.
  void load_restart(const std::filesystem::path& file);
  void open_outputs(const OutputOptions& options = {});
  /// Whatever remains of the generation and consolidation (a test that makes its own specimen),
  /// the static, cyclic and post-cyclic stages with their outputs, then final.restart.
  void run();
  /// summary.json: the specimen, the cyclic settings, the outcome, timing and the configuration.
  void write_summary(const std::string& resolved_config_json) const;

  /// The files and folders, relative to the output folder, that this test adds to a run's.
  static std::vector<std::string> run_files();

  World& world() { return run_.world(); }
  /// The rows of cyclic_history.csv so far.
  const io::CsvTable& history() const { return history_.table(); }
  const CycleLog& cycles() const { return cycles_; }
  const CyclicOutcome& outcome() const { return outcome_; }
  const CyclicShearConfig& config() const { return config_; }
  /// Steps of one history row: the period is rows_per_cycle x this x dt.
  std::int64_t steps_per_row() const { return steps_per_row_; }

 private:
  /// Where the test is (kept in restart files): each stage's rows, in order.
  enum class Step : int { Start = 0, StaticRows = 1, CyclicStart = 2, CyclicRows = 3, PostRows = 4, Done = 5 };
  void keep_state();
  void begin();
  // The specimen must be consolidated (or, for a run that makes its own, not yet): InputError otherwise.
  void require_cyclic_stage() const;
  void make_drive();
  void start_phase(CyclicPhase phase, std::int64_t start_step);
  void add_history_columns();
  /// Measures the specimen now: one history row, and a sample of the cycle log in the cyclic stage.
  void record_row();
  void progress(double cycles);
  void write_outputs() const;
  Vec3 stress_target(double cycles) const;  // Pa
  Vec3 strain_target(double cycles) const;  // -

  SimpleShearConfig own_config_;  // a test that makes its own specimen: its keys, run and parts
  std::unique_ptr<Run> own_run_;
  std::unique_ptr<NgiSpecimen> own_specimen_;
  std::unique_ptr<ShearOutputs> own_outputs_;
  Run& run_;
  NgiSpecimen& specimen_;
  CyclicShearConfig config_;
  CyclicPath path_;
  std::shared_ptr<HorizontalDrive> drive_;  // made when the stages begin; the controller calls it
  HistoryLog history_;  // cyclic_history.csv, saved at every row
  struct Row {
    ShearState state;
    double cycles = 0.0;              // -, cycles of the current phase's path
    Vec3 target = Vec3::Zero();       // Pa or -, the drive's target
    double excess_pore_pressure = 0;  // Pa, sigma_v0 - sigma_v
    double double_amplitude = NAN;    // -, of the last full cycle
    double non_coaxiality_deg = NAN;  // deg
  } row_;
  CycleLog cycles_;
  CyclicOutcome outcome_;
  std::unique_ptr<FabricLog> fabric_;
  std::unique_ptr<SnapshotWriter> snapshots_;
  std::unique_ptr<BrokenBondLog> broken_bonds_;  // a cemented run's: cyclic_snapshots/broken_bonds_<label>.vtp
  // The cursor.
  Step step_ = Step::Start;
  std::int64_t rows_done_ = 0;  // of the current stage (steps left, in the post-cyclic stage)
  CyclicPhase current_phase_ = CyclicPhase::Static;
  std::int64_t phase_start_step_ = 0;
  CyclicSample last_sample_;
  double last_double_amplitude_ = NAN;
  std::size_t next_fabric_ = 0, next_snapshot_ = 0;
  std::int64_t steps_per_row_ = 1;
  double shear_rate_ = 0.0;   // 1/s, of the post-cyclic shear
  Vec3 static_stress_ = Vec3::Zero();  // Pa
  Vec3 cyclic_start_strain_ = Vec3::Zero();
  std::int64_t post_every_ = 1;  // steps per post-cyclic row
  double loaded_work_ = 0.0;     // the drive's work when a loaded file was written
};

}  // namespace dem::lab
