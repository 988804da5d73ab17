// Cyclic and multidirectional simple shear on the NGI ring stack (docs/cyclic-shear.md): a
// consolidated SimpleShearTest specimen, an optional static shear stress, a cyclic stage along a
// path in the horizontal plane (lab/cyclic_path.hpp) under stress or strain control, drained or at
// constant volume, until a stop criterion, then an optional monotonic shear.
//
// Control: the plates' horizontal motion is a HorizontalDrive (lab/horizontal_drive.hpp): strain
// control moves the bottom plate exactly on the path, stress control servoes the top plate on its
// own horizontal force, capped at cyclic.servo_max_speed.
// Drainage. Constant volume holds both plates' heights (the equivalent of an undrained test);
// the excess pore pressure is du = sigma_v0 - sigma_v and r_u = du / sigma_v0, with sigma_v the
// top plate's vertical stress and sigma_v0 its value when the cyclic test begins (the end of
// the consolidation). Drained keeps the vertical servo on sigma_v.
//
// Time. The path's clock is the step count: one cycle is cyclic.period over the time step at the
// start of the stage, rounded to a whole number of steps per history row (rows_per_cycle rows a
// cycle), so rows fall at exact cycle fractions. The automatic time step is re-estimated at
// neighbour-list rebuilds (by a few per cent at most), and a cycle's duration in seconds (the
// history's time column) varies by as much; a quasi-static test does not notice. The stop criteria (r_u,
// double-amplitude strain over the last cycle, the number of cycles) are checked at every row, and
// the run stops at the first row that meets one. The cyclic stage is not resumable mid-way: its
// restart file is the consolidated one (--from), and final.restart is written at the end.
//
// Outputs in the test's folder: cyclic_history.csv (columns below), cycles.csv (lab/cycle_log.hpp),
// summary.json (the specimen, the settings, N_L by each criterion, the stop), cyclic_fabric.csv and
// cyclic_snapshots/ at the chosen cycles.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <dem/io/csv.hpp>
#include <dem/lab/cycle_log.hpp>
#include <dem/lab/cyclic_path.hpp>
#include <dem/lab/cyclic_shear_config.hpp>
#include <dem/lab/history_log.hpp>
#include <dem/lab/horizontal_drive.hpp>
#include <dem/lab/simple_shear.hpp>

namespace dem::lab {

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
  /// `specimen` must be consolidated (Consolidated stage) and outlive this test. Validates the
  /// configuration against it (InputError naming the key), reads a series file.
  CyclicShearTest(SimpleShearTest& specimen, CyclicShearConfig config, std::ostream& log);
  ~CyclicShearTest();
  CyclicShearTest(const CyclicShearTest&) = delete;
  CyclicShearTest& operator=(const CyclicShearTest&) = delete;

  /// The static, cyclic and post-cyclic stages with their outputs, then final.restart.
  void run();
  /// summary.json: the specimen, the cyclic settings, the outcome, timing and the configuration.
  void write_summary(const std::string& resolved_config_json) const;

  /// The files and folders, relative to the output folder, that this test adds to a run's.
  static std::vector<std::string> run_files();

  /// The rows of cyclic_history.csv so far.
  const io::CsvTable& history() const { return history_.table(); }
  const CycleLog& cycles() const { return cycles_; }
  const CyclicOutcome& outcome() const { return outcome_; }
  const CyclicShearConfig& config() const { return config_; }
  /// Steps of one history row: the period is rows_per_cycle x this x dt.
  std::int64_t steps_per_row() const { return steps_per_row_; }

 private:
  void start_phase(CyclicPhase phase);
  /// What one history row reports, measured by record_row.
  struct Row {
    ShearState state;
    double cycles = 0.0;              // -, cycles of the current phase's path
    Vec3 target = Vec3::Zero();       // Pa or -, the drive's target
    double excess_pore_pressure = 0;  // Pa, sigma_v0 - sigma_v
    double double_amplitude = NAN;    // -, of the last full cycle
    double non_coaxiality_deg = NAN;  // deg
  };
  /// The columns of cyclic_history.csv, each read from row_.
  void add_history_columns();
  /// Measures the specimen now: one history row, and a sample of the cycle log in the cyclic stage.
  void record_row();
  void progress(double cycles) const;
  void write_outputs() const;
  Vec3 stress_target(double cycles) const;  // Pa
  Vec3 strain_target(double cycles) const;  // -

  SimpleShearTest& specimen_;
  CyclicShearConfig config_;
  std::ostream& log_;
  CyclicPath path_;
  std::shared_ptr<HorizontalDrive> drive_;  // the World's controller holds it weakly
  HistoryLog history_;  // cyclic_history.csv, saved at every row
  Row row_;
  CycleLog cycles_;
  CyclicOutcome outcome_;
  std::unique_ptr<FabricLog> fabric_;
  std::unique_ptr<SnapshotWriter> snapshots_;
  CyclicPhase current_phase_ = CyclicPhase::Static;
  CyclicSample last_sample_;
  double last_double_amplitude_ = NAN;
  std::size_t next_fabric_ = 0, next_snapshot_ = 0;
  std::int64_t steps_per_row_ = 1;
  double shear_rate_ = 0.0;   // 1/s, of the post-cyclic shear
  Vec3 static_stress_ = Vec3::Zero();  // Pa
  Vec3 cyclic_start_strain_ = Vec3::Zero();
  mutable double last_progress_ = -1e9;
};

}  // namespace dem::lab
