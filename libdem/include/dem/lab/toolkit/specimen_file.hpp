// A specimen from a restart file of the simple-shear protocol (SimpleShearTest::save_restart, e.g.
// dem-consolidate's consolidated.restart), as parts for a protocol that goes on from it: the
// protocol's record in the file, the stage the specimen is in, and a consolidated specimen loaded
// into a world that the caller has built with its shear cell.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/toolkit/run_record.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

/// How far the simple-shear protocol has brought a specimen.
enum class ShearStage : int { Empty = 0, Generated = 1, Consolidated = 2, Shearing = 3, Done = 4 };

/// The top plate's servo as a record left it: `configured` with the record's target stress and
/// speed cap, or `configured` as it is for records written before those were kept.
ServoSettings recorded_servo(const ProtocolRecord& record, ServoSettings configured);
/// The steps the record's servo had been on its target (0 for records without it); InputError for
/// a count below zero.
std::int64_t recorded_steps_on_target(const ProtocolRecord& record);

/// The stage of the specimen in a restart file, read without loading its world.
ShearStage restart_stage(const std::filesystem::path& file);

/// Loads the specimen of `file`, at any stage, into `world`, which holds the shear cell `cell` built
/// from `config` (build_shear_cell with shear_cell_spec) and the protocol's contact laws
/// (set_contact_laws): the balls, rings, plates, contacts, time and step of the file. Then the guards
/// of lab/toolkit/specimen_guards.hpp: the grading (unless the balls are still growing), the engine and
/// specimen keys (changes logged to `log`). Returns the file's record; InputError naming the file
/// when a guard refuses it.
ProtocolRecord load_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                             const SimpleShearConfig& config, std::ostream& log);

/// A consolidated specimen as its restart file holds it, beyond the world's state.
struct ConsolidatedSpecimen {
  double height = 0.0;                     // m, H_c: the plate gap after consolidation
  ServoSettings servo;                     // the top plate's servo as the file left it
  std::int64_t servo_steps_on_target = 0;  // steps the servo has been on its target
};

/// Loads the consolidated specimen of `file` as load_specimen does, then releases the rings as
/// `config` says (release_rings). InputError naming the file when it holds no consolidated
/// specimen (stage 2) or a guard refuses it. The servo and the controller are the caller's, as in a
/// shear from it:
///
///   ServoWall servo(cell.top, specimen.servo);
///   servo.resume_steps_on_target(specimen.servo_steps_on_target);
///   world.add_controller([&](World& w) { servo(w); move_rings(w, cell, true); });
///   start_shear_leg(world, cell, servo, shear_leg_motion(config, 0.0, rate, specimen.height));
ConsolidatedSpecimen load_consolidated_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                                                const SimpleShearConfig& config, std::ostream& log);

}  // namespace dem::lab
