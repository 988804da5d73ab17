// A specimen in the NGI-type simple-shear cell, made and consolidated, as a part of a protocol
// (the simple-shear, cyclic and calibration protocols share it): a cylinder of balls grown by
// radius expansion inside a stack of clump rings between two facet plates, against a servo plate
// at a low stress, with the generation friction lowered step by step until the target porosity
// (docs/model.md 7, 7.1); the rings then ride on the specimen (rings.vertical, docs/model.md 4);
// then consolidation by the servo-controlled top plate to the vertical stress.
//
// The part builds the cell in its run's World and adds the cell's one controller (the servo, the
// generation floor of the top plate, the rings, and the plates' damping frame while a protocol
// shears). It keeps its state in the run's restart files (lab/toolkit/run.hpp): a generation or a
// consolidation resumed from a file written between any two chunks goes on exactly where it was.
// It writes no outputs: the protocol records its rows where its method says.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>

#include <dem/control/servo_wall.hpp>
#include <dem/lab/toolkit/radius_expansion.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>
#include <dem/lab/toolkit/specimen_file.hpp>
#include <dem/measure/measurement_sphere.hpp>

namespace dem::lab {

/// What a restart file is loaded for: to continue the run that wrote it, or to consolidate a
/// consolidated specimen again with new contact parameters (NgiSpecimen::reconsolidate;
/// dem-consolidate --from), which may then differ from the file's, as may the consolidation keys
/// and the time step.
enum class ResumeIntent { Continue, Reconsolidate };

/// The cell and its specimen now (SI; stresses compression positive, as soil mechanics quotes them).
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
  double principal_rotation_deg = 0;                  // deg, in the plane of the shear direction
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

class NgiSpecimen {
 public:
  /// Builds the cell of `config` in `run`'s World with the configured contact laws, adds the
  /// controller and keeps the specimen's state in `run`. `config` and `run` must outlive it.
  NgiSpecimen(Run& run, const SimpleShearConfig& config);

  /// Radius expansion in the ring stack, then the friction schedule (docs/model.md 7): Empty ->
  /// Generated. Resumes a generation the run was loaded in.
  void generate();
  /// The servo brings the top plate to consolidation.vertical_stress until stress and kinetic
  /// energy have settled: Generated -> Consolidated.
  void consolidate();
  /// Consolidates a consolidated specimen again with this configuration's contact parameters
  /// (another E*): the same packing, a new time step for the new stiffness, the servo back on the
  /// vertical stress until it has settled.
  void reconsolidate();
  /// Installs the bonds of cementation.* (docs/cementation.md) if cementation.after is `moment`:
  /// generate() calls it at the generation's end; a protocol calls it with Consolidation when its
  /// loading starts, after consolidated.restart is written (so that file is the plain specimen),
  /// once: a run resumed past that point has its bonds in the file. The strengths are keyed by
  /// specimen.seed; an automatic time step is estimated again with the bonds. Returns the bonds made.
  std::size_t cement(CementAfter moment);
  /// Loads a restart file into the run (Run::load) and puts the specimen where the file left it,
  /// after the checks of docs/restart.md: the recorded configuration against the run's (when
  /// both have one), the grading, the specimen and engine keys (InputError naming the file).
  void load(const std::filesystem::path& file, ResumeIntent intent = ResumeIntent::Continue);

  /// The stage; a protocol that shears the specimen moves it to Shearing (the plates' damping
  /// frame, shear.damping_frame, is then set every step) and Done.
  ShearStage stage() const { return stage_; }
  void set_stage(ShearStage stage) { stage_ = stage; }
  /// How far the run has got, for the resume rules (docs/restart.md).
  RunProgress progress() const;
  /// For a protocol that goes on from the consolidated specimen without shearing it (the cyclic
  /// test): whether it has begun, which counts as the shear for the resume rules.
  void set_beyond_consolidation(std::function<bool()> begun) { beyond_consolidation_ = std::move(begun); }

  /// The cell and its specimen now; `direction` (unit, horizontal) is the shear direction the
  /// principal stress rotation is measured in.
  ShearState measure(const Vec3& direction) const;
  /// Porosity, coordination, K0 and height now, with the ball-ball friction in use.
  SpecimenState state() const;
  const SpecimenState& generated_state() const { return generated_state_; }
  const SpecimenState& consolidated_state() const { return consolidated_state_; }
  /// Throws InstabilityError naming the first ball that left the specimen (lab/toolkit/specimen_guards.hpp).
  void require_no_escape(double shear_strain) const;

  const SimpleShearConfig& config() const { return config_; }
  const ShearCell& cell() const { return cell_; }
  /// The top plate's vertical servo; nullptr before the generation's servo or the consolidation.
  ServoWall* servo() { return servo_.get(); }
  std::size_t ball_count() const { return ball_count_; }
  double generated_porosity() const { return generated_porosity_; }  // -, of the diameters drawn
  double consolidated_height() const { return consolidated_height_; }  // m, H_c
  double shear_rate() const;       // 1/s, shear_strain_rate of the configuration
  double inertial_number() const;  // -, at the shear rate and the vertical stress
  /// The cap of the servo plate's speed while a protocol shears (m/s).
  double shear_servo_speed() const;

  /// Where the generation is: the expansion stage and increment, the steps settled so far, and
  /// the friction schedule's round.
  struct GenerationProgress {
    enum Phase : int { Expanding = 0, Settling = 1, FirstSettle = 2, Reducing = 3, ScheduleSettle = 4 };
    int phase = Expanding;
    int stage = 1;          // expansion stage, 1..generation.stages
    int increment = 0;      // radius increments done in the stage
    long settled_steps = 0; // steps of the current settle so far
  };

 private:
  void keep_state();
  void control(World& world);
  /// Ball-ball with the given friction (the plates and rings frictionless while `growing`).
  void set_contact_models(double friction, double rolling_friction, bool growing,
                          ModelChange change = ModelChange::Rebuild);
  void expand_radii(const RadiusExpansion& expansion);
  void settle_generation(const std::function<bool()>& done);
  void friction_schedule();
  ServoSettings servo_settings() const;

  Run& run_;
  World& world_;
  const SimpleShearConfig& config_;
  ShearCell cell_;
  std::shared_ptr<ServoWall> servo_;
  ShearStage stage_ = ShearStage::Empty;
  std::function<bool()> beyond_consolidation_;
  bool generating_ = false;        // balls placed, generation under way
  bool generation_floor_ = false;  // the top plate may not sink below specimen.height
  GenerationProgress generation_;
  bool consolidating_ = false;
  std::int64_t consolidation_start_step_ = 0;
  double friction_now_ = 0.0, rolling_friction_now_ = 0.0;  // ball-ball, as set
  SpecimenState generated_state_, consolidated_state_;
  std::size_t ball_count_ = 0;
  double generated_porosity_ = 0.0;
  double consolidated_height_ = 0.0;  // m
  // The servo as a restart file keeps it (restored into servo_ after a load).
  struct ServoRecord {
    bool present = false, holding = false;
    double target = NAN, max_speed = NAN;
    std::int64_t steps_on_target = 0;
  } servo_record_;
};

}  // namespace dem::lab
