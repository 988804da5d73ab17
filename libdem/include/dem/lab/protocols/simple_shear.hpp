// The NGI-type simple-shear test of the study, as a protocol over the lab toolkit: a specimen made
// and consolidated in the NGI cell (lab/toolkit/ngi_specimen.hpp), then sheared by moving the
// bottom plate horizontally along one or several directions while the top plate keeps the
// vertical stress (drained) or the height (constant volume), with the outputs of
// lab/toolkit/shear_outputs.hpp. The apps, the Python module and the calibration's specimens run
// this one script; simple_shear.cpp reads as its method section.
//
// Kinematics (docs/model.md 8; the study's convention): the top plate is held horizontally and the
// bottom plate moves along the shear direction d of the current leg: shear strain
// gamma = (u_bottom - u_top)_horizontal / H_c, with H_c the height after consolidation. Shear
// stress is the horizontal force the sand puts on the top plate over the specimen area, positive
// along the shear. The major principal stress then tilts from vertical towards +d, and contact
// forces rotate towards 45 deg from +d in the d-z plane, as the study's figures show. Principal
// stresses and their rotation come from a measurement sphere at mid-height, which follows the
// mean horizontal displacement of the specimen.
//
// A run is resumable anywhere (lab/toolkit/run.hpp): restart files are written between chunks of
// steps in every stage, and a run resumed from one repeats the uninterrupted run exactly.
// docs/restart.md says which keys a resumed run may change. The output folder is claimed by
// open_outputs(), or by the first stage that writes; nothing in it is touched before, so a refused
// restart or configuration leaves the folder as it was.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <dem/lab/toolkit/ngi_specimen.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/shear_legs.hpp>
#include <dem/lab/toolkit/shear_outputs.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>
#include <dem/lab/toolkit/specimen_guards.hpp>

namespace dem::lab {

class SimpleShearTest {
 public:
  /// Sets up the run; nothing is simulated yet. `log` receives progress lines.
  SimpleShearTest(SimpleShearConfig config, std::filesystem::path out_dir, std::ostream& log);
  SimpleShearTest(const SimpleShearTest&) = delete;
  SimpleShearTest& operator=(const SimpleShearTest&) = delete;

  /// Specimen by radius expansion in the ring stack (docs/model.md 7).
  void generate();
  /// Servo consolidation to the vertical stress; the history's first row, consolidated.restart.
  void consolidate();
  /// Consolidates again a consolidated specimen loaded with ResumeIntent::Reconsolidate, with this
  /// run's contact parameters (another E*), as consolidate() does.
  void reconsolidate();
  /// All shear legs, with history, fabric, snapshots and restart files in the output folder.
  void shear();
  /// Whatever remains of generate, consolidate and shear.
  void run();

  /// Writes the world, the protocol's progress and the recorded configuration (atomically).
  void save_restart(const std::filesystem::path& file) const { run_.save(file); }
  /// The resolved configuration this run was made from (every key), which restart files carry;
  /// a restart loaded later is checked against it key by key (docs/restart.md).
  void record_configuration(const io::Config& resolved) { run_.record_configuration(resolved); }
  /// Continues from a restart file: anywhere in the generation, the consolidation or the shear
  /// (NgiSpecimen::load's checks). Once per test, before any stage has run. Nothing is written:
  /// open_outputs() (or the first stage) trims the outputs written past the restart point and,
  /// for a restart in another folder, first copies its history.csv, fabric.csv and snapshots/ here.
  void load_restart(const std::filesystem::path& file, ResumeIntent intent = ResumeIntent::Continue);
  /// Claims the output folder (io/output_folder.hpp) and brings the outputs of a loaded restart up
  /// to its point. Called by the first stage that writes if not before.
  void open_outputs(const OutputOptions& options = {}) { run_.claim(options); }
  bool outputs_open() const { return run_.claimed(); }
  /// The files and folders, relative to the output folder, that hold a run's results.
  static std::vector<std::string> run_files();
  /// summary.json: counts, porosity, ASTM D6528 ratios, peak and final values, timing, and the
  /// keys a resume changed (simple_shear_summary.cpp).
  void write_summary(const std::string& resolved_config_json) const;

  /// The cell and specimen now, in the current leg's direction.
  ShearState measure() const { return specimen_.measure(legs_.direction()); }
  SpecimenState specimen_state() const { return specimen_.state(); }
  const SpecimenState& generated_state() const { return specimen_.generated_state(); }
  const SpecimenState& consolidated_state() const { return specimen_.consolidated_state(); }
  std::size_t balls_outside() const { return lab::balls_outside(run_.world(), cell()); }
  void require_no_escape() const { specimen_.require_no_escape(legs_.strain()); }

  const World& world() const { return run_.world(); }
  World& world() { return run_.world(); }
  Run& resumable_run() { return run_; }
  NgiSpecimen& specimen() { return specimen_; }
  const HistoryLog& history() const { return outputs_.history(); }
  const ShearCell& cell() const { return specimen_.cell(); }
  WallId top_plate() const { return cell().top; }
  WallId bottom_plate() const { return cell().bottom; }
  ServoWall* vertical_servo() { return specimen_.servo(); }
  double area() const { return cell().area; }  // m^2
  const std::filesystem::path& output_folder() const { return run_.folder(); }
  ShearStage stage() const { return specimen_.stage(); }
  const SimpleShearConfig& config() const { return config_; }
  double consolidated_height() const { return specimen_.consolidated_height(); }  // m
  double shear_rate() const { return specimen_.shear_rate(); }                     // 1/s
  double inertial_number() const { return specimen_.inertial_number(); }           // -
  std::size_t ball_count() const { return specimen_.ball_count(); }
  double generated_porosity() const { return specimen_.generated_porosity(); }
  static constexpr std::int64_t chunk_steps = 10;

 private:
  void start_leg(const ShearLeg& leg);

  SimpleShearConfig config_;
  ShearLegs legs_;  // config_.shear.legs(), and the shear's cursor
  Run run_;
  NgiSpecimen specimen_;
  ShearOutputs outputs_;
  std::int64_t steps_at_shear_start_ = 0;
};

}  // namespace dem::lab
