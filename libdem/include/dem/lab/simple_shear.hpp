// The NGI-type simple-shear test of the study, as a reusable protocol: a cylindrical specimen made
// by radius expansion between two facet plates inside a stack of clump rings, consolidated by a
// servo-controlled top plate, then sheared by moving the bottom plate horizontally along one or
// several directions while the top plate keeps the vertical stress (drained) or the height
// (constant volume). Apps drive it; a calibration runs many shears from one consolidated state.
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
// The specimen grows against the servo plate at a low stress, with the generation friction lowered
// step by step until the target porosity (docs/model.md 7.1); the rings then ride on the specimen
// between the plates (rings.vertical, docs/model.md 4). History rows also measure how uniformly the
// specimen shears (docs/model.md 8.1); a ball that leaves the specimen stops the run.
//
// Runs are steps in chunks; outputs and restart files are written only between chunks, in every
// stage (generation, consolidation, shear), so a run resumed from a restart file repeats the
// uninterrupted run exactly. docs/restart.md says which keys a resumed run may change.
//
// The output folder is claimed (io/output_folder.hpp: locked, checked writable, refused when it
// holds another run) by open_outputs(), or by the first stage that writes; nothing in it is
// touched before, so a refused restart or configuration leaves the folder as it was.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/io/config.hpp>
#include <dem/io/output_folder.hpp>
#include <dem/lab/history_log.hpp>
#include <dem/lab/radius_expansion.hpp>
#include <dem/lab/resume_rules.hpp>
#include <dem/lab/shear_cell.hpp>
#include <dem/lab/shear_leg.hpp>
#include <dem/lab/simple_shear_config.hpp>
#include <dem/lab/simple_shear_parts.hpp>
#include <dem/lab/specimen_file.hpp>
#include <dem/lab/specimen_guards.hpp>
#include <dem/lab/uniformity_probe.hpp>
#include <dem/measure/measurement_sphere.hpp>

namespace dem::lab {

class FabricLog;
class SnapshotWriter;

/// What a restart file is loaded for: to continue the run that wrote it, or to consolidate a
/// consolidated specimen again with new contact parameters (reconsolidate(); dem-consolidate
/// --from), which may then differ from the file's, as may the consolidation keys and the time step.
enum class ResumeIntent { Continue, Reconsolidate };

/// How the output folder is claimed (io::OutputFolderPolicy).
struct OutputOptions {
  bool replace = false;                  // remove the results of another run in the folder
  std::string program = "libdem";        // named in the lock file
  std::string replace_option = "--replace";
  std::vector<std::string> more_run_files{};  // results of a protocol built on this test (cyclic shear)
};

/// One history row (SI; stresses compression positive, as soil mechanics quotes them).
struct ShearState {
  double time = 0.0;                                  // s
  double shear_strain_x = 0, shear_strain_y = 0, shear_strain = 0;     // -
  double shear_stress_x = 0, shear_stress_y = 0, shear_stress = 0;     // Pa, top plate
  double shear_stress_bottom = 0;                     // Pa, bottom plate, along the resultant
  double vertical_stress = 0;                         // Pa, top plate
  double vertical_stress_bottom = 0;                  // Pa, bottom plate
  double height = 0;                                  // m
  double volumetric_strain = 0;                       // -, sign per config
  double lateral_stress = 0;                          // Pa, radial push on the rings
  SphereMeasurement sphere;                           // measurement sphere
  double principal_rotation_deg = 0;                  // deg, in the plane of the current leg
  std::size_t contacts = 0;                           // ball-ball contacts
  double mean_contact_force = 0;                      // N, ball-ball
  double kinetic_energy = 0;                          // J
  double specimen_porosity = 0;                       // -, 1 - ball volume / (area x height)
  std::size_t balls_outside = 0;                      // ball centres beyond the rings or the plates
};

/// The specimen when its radii have grown (generation) or it has settled (consolidation).
struct SpecimenState {
  double porosity = 0;             // -, 1 - ball volume / (area x height), overlaps ignored
  double sphere_porosity = 0;      // -, measurement sphere
  double coordination_number = 0;  // -, measurement sphere, boundary contacts included
  double mechanical_coordination_number = 0;  // -, rattlers out
  double vertical_stress = 0;      // Pa, top plate
  double k0 = 0;                   // -, ring lateral stress / vertical stress
  double height = 0;               // m
  double friction = 0, rolling_friction = 0;  // -, ball-ball at that moment
};

class SimpleShearTest {
 public:
  /// Sets up the run; nothing is simulated yet. `log` receives progress lines.
  SimpleShearTest(SimpleShearConfig config, std::filesystem::path out_dir, std::ostream& log);
  ~SimpleShearTest();
  SimpleShearTest(const SimpleShearTest&) = delete;
  SimpleShearTest& operator=(const SimpleShearTest&) = delete;

  /// Specimen by radius expansion in the ring stack (docs/model.md 7).
  void generate();
  /// Servo consolidation to the vertical stress, until stress and kinetic energy have settled.
  void consolidate();
  /// Consolidates again a consolidated specimen (loaded from its restart) with this run's contact
  /// parameters, e.g. another E*: the same packing, a new time step for the new stiffness, and the
  /// servo back on the vertical stress until it has settled. Writes consolidated.restart as
  /// consolidate() does. A calibration uses it so that specimens of nearby E* differ only in their
  /// overlaps, not in their packing.
  void reconsolidate();
  /// All shear legs, with history, fabric, snapshots and restart files in the output folder.
  void shear();
  /// Whatever remains of generate, consolidate and shear, then the summary.
  void run();

  /// Writes the world, the protocol's progress and the recorded configuration (atomically); the
  /// progress is a JSON object in the file's protocol text (simple_shear_state.cpp).
  void save_restart(const std::filesystem::path& file) const;
  /// The resolved configuration this run was made from (every key); restart files carry it, and a
  /// restart loaded later is checked against it key by key (docs/restart.md). Without it (a test
  /// built from the struct alone) only the specimen checks of load_restart apply.
  void record_configuration(const io::Config& resolved);
  /// Continues from a restart file: anywhere in the generation, the consolidation or the shear.
  /// Once per test, before any stage has run.
  /// When both the file and this run have a recorded configuration, a key that changes what is
  /// already done (docs/restart.md: geometry, grading, densities, contact parameters and engine
  /// keys of the stages already run, the time step) is refused with an InputError that names every
  /// such key with the file's value and this run's; the keys that may change are applied, logged
  /// and listed in summary.json. Independently of the record, the specimen's ball sizes, density,
  /// height and ring stack must match this configuration's. Nothing is written: open_outputs()
  /// (or the first stage) trims the outputs written past the restart point and, for a restart in
  /// another folder, first copies its history.csv, fabric.csv and snapshots/ here.
  void load_restart(const std::filesystem::path& file, ResumeIntent intent = ResumeIntent::Continue);
  /// Claims the output folder (io/output_folder.hpp) and brings the outputs of a loaded restart up
  /// to its point. Called by the first stage that writes if not before; call it earlier to claim
  /// the folder before any work, with the options of the command line.
  void open_outputs(const OutputOptions& options = {});
  bool outputs_open() const { return folder_ != nullptr; }
  /// The files and folders, relative to the output folder, that hold a run's results.
  static std::vector<std::string> run_files();

  /// The current state, measured now.
  ShearState measure() const;
  /// Porosity, coordination, K0 and height now, with the ball-ball friction in use.
  SpecimenState specimen_state() const;
  const SpecimenState& generated_state() const { return generated_state_; }
  const SpecimenState& consolidated_state() const { return consolidated_state_; }
  /// Balls whose centre has left the specimen (lab/specimen_guards.hpp). Each history row counts
  /// them; any stops the run.
  std::size_t balls_outside() const { return lab::balls_outside(*world_, cell_); }
  /// Throws InstabilityError naming the first ball that left the specimen, where it is and the
  /// likely cause; nothing when none has.
  void require_no_escape() const { lab::require_no_escape(*world_, cell_, path_.strain()); }
  /// summary.json: counts, porosity, ASTM D6528 ratios, peak and final values, timing, and the
  /// keys a resume changed.
  void write_summary(const std::string& resolved_config_json) const;

  const World& world() const { return *world_; }
  /// The world, for a protocol that drives the consolidated specimen further (lab/cyclic_shear.hpp):
  /// the plates, the servo and the rings stay this test's, its controller keeps running first.
  World& world() { return *world_; }
  WallId top_plate() const { return cell_.top; }
  WallId bottom_plate() const { return cell_.bottom; }
  /// The top plate's vertical servo; nullptr before the consolidation.
  ServoWall* vertical_servo() { return servo_.get(); }
  double area() const { return cell_.area; }  // m^2, the specimen's cross-section
  const ShearCell& cell() const { return cell_; }
  const std::filesystem::path& output_folder() const { return out_dir_; }
  ShearStage stage() const { return stage_; }
  const SimpleShearConfig& config() const { return config_; }
  double consolidated_height() const { return consolidated_height_; }  // m
  double shear_rate() const;       // 1/s
  double inertial_number() const;  // -, at the shear rate and the vertical stress
  std::size_t ball_count() const { return ball_count_; }
  double generated_porosity() const { return generated_porosity_; }
  static constexpr std::int64_t chunk_steps = 10;

  /// Where the generation is (restart files written during it resume here): the expansion stage
  /// and increment, the steps settled so far, and the friction schedule's round.
  struct GenerationProgress {
    enum Phase : int { Expanding = 0, Settling = 1, FirstSettle = 2, Reducing = 3, ScheduleSettle = 4 };
    int phase = Expanding;
    int stage = 1;          // expansion stage, 1..generation.stages
    int increment = 0;      // radius increments done in the stage
    long settled_steps = 0; // steps of the current settle so far
  };

 private:
  void build_world();
  /// Ball-ball with the given friction (the plates and rings frictionless while `growing`).
  /// KeepContacts: the same laws with these parameters, the contact lists left as they are.
  void set_contact_models(double friction, double rolling_friction, bool growing, ModelChange change = ModelChange::Rebuild);
  /// The one controller of the protocol, every step: the servo, the generation floor of the top
  /// plate, then the ring kinematics (rings.vertical), which read the plate velocities just set.
  void control(World& world);
  void friction_schedule();
  /// Steps the settle of the generation (generation.steps_per_stage at most) until `done`.
  void settle_generation(const std::function<bool()>& done);
  void expand_radii(const RadiusExpansion& expansion);
  /// Registers the history's columns: the state of the row (measure()), the uniformity probe's,
  /// the rings' displacements.
  void add_history_columns();
  void record_history();
  void record_outputs(bool force);
  void maybe_save_restart();
  void open_outputs_if_needed() {
    if (!folder_) open_outputs();
  }
  /// Applies or refuses the keys of a restart's recorded configuration (docs/restart.md).
  void apply_configuration_record(const std::vector<std::pair<std::string, std::string>>& file_record,
                                  const std::filesystem::path& file, ResumeIntent intent);
  void progress(const std::string& stage, const std::string& detail) const;
  std::string protocol_state() const;
  void restore_protocol_state(const std::string& text);
  RunProgress progress_made() const;
  Vec3 leg_direction(std::size_t leg) const;
  ServoSettings servo_settings() const;
  double shear_servo_speed() const;  // m/s, cap of the servo plate while shearing
  void start_leg();

  SimpleShearConfig config_;
  std::vector<ShearLeg> legs_;         // config_.shear.legs()
  std::filesystem::path out_dir_;
  std::unique_ptr<io::OutputFolder> folder_;   // claimed by open_outputs()
  std::filesystem::path restart_folder_;       // folder of the loaded restart file, if any
  std::vector<std::pair<std::string, std::string>> configuration_;  // key, value (record_configuration)
  std::vector<std::pair<std::string, std::string>> file_configuration_;  // of the loaded restart file
  std::vector<std::array<std::string, 3>> resume_changes_;          // key, file value, value now
  std::ostream& log_;
  std::unique_ptr<World> world_;
  std::shared_ptr<ServoWall> servo_;
  bool generation_floor_ = false;      // the top plate may not sink below specimen.height
  bool generating_ = false;            // balls placed, generation under way
  GenerationProgress generation_;
  bool consolidating_ = false;         // consolidation under way
  std::int64_t consolidation_start_step_ = 0;
  double friction_now_ = 0.0, rolling_friction_now_ = 0.0;  // ball-ball, as set
  SpecimenState generated_state_, consolidated_state_;
  ShearCell cell_;                     // plates and rings
  std::unique_ptr<FabricLog> fabric_;
  std::unique_ptr<SnapshotWriter> snapshots_;
  HistoryLog history_;                 // history.csv
  std::unique_ptr<UniformityProbe> uniformity_;  // columns of history_
  ShearState row_;                     // measured for the history row being written

  ShearStage stage_ = ShearStage::Empty;
  std::size_t ball_count_ = 0;
  double generated_porosity_ = 0.0;
  double consolidated_height_ = 0.0;   // m
  std::size_t leg_ = 0;                // current shear leg
  double leg_start_strain_ = 0.0;      // path strain at the start of the leg
  ShearPath path_;                     // accumulated |d gamma| along the legs
  double next_output_strain_ = 0.0;
  std::size_t next_fabric_ = 0, next_snapshot_ = 0;
  std::int64_t last_restart_step_ = 0;
  double wall_seconds_ = 0.0;          // s, simulated-run wall clock so far (all sessions)
  std::int64_t steps_at_shear_start_ = 0;
  mutable double last_progress_ = -1e9;
};

}  // namespace dem::lab
