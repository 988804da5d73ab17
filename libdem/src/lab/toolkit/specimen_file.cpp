// Restart files of the NGI cell's protocols as parts: the servo and the stage in a record, a
// specimen loaded at any stage, a consolidated specimen.
#include <dem/lab/toolkit/specimen_file.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>
#include <dem/lab/toolkit/specimen_guards.hpp>

namespace dem::lab {

ServoSettings recorded_servo(const ProtocolRecord& record, ServoSettings configured) {
  if (record.has("servo_target")) {
    configured.target_stress = record.number("servo_target");
    configured.max_speed = record.number("servo_max_speed");
  }
  return configured;
}

std::int64_t recorded_steps_on_target(const ProtocolRecord& record) {
  if (!record.has("servo_steps_on_target")) return 0;
  const double on_target = record.number("servo_steps_on_target");
  require(on_target >= 0 && on_target <= 9e15, record.source + ": servo_steps_on_target", on_target, "a count of steps >= 0");
  return static_cast<std::int64_t>(on_target);
}

ShearStage restart_stage(const std::filesystem::path& file) {
  const std::string source = "restart file " + file.string();
  const double stage = read_protocol_record(io::read_checkpoint_protocol(file), source).number("stage");
  require(stage >= 0 && stage <= 4 && stage == std::floor(stage), source + ": stage", stage, "0, 1, 2, 3 or 4");
  return static_cast<ShearStage>(static_cast<int>(stage));
}

ProtocolRecord load_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                             const SimpleShearConfig& config, std::ostream& log) {
  const World as_configured = world;
  ProtocolRecord record = read_protocol_record(io::load_checkpoint(file, world), "restart file " + file.string());
  if (!record.flag("generating")) require_configured_grading(world, config, file);  // growing balls are smaller
  apply_restart_keys(world, as_configured, cell, config, file, log);
  return record;
}

ConsolidatedSpecimen load_consolidated_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                                                const SimpleShearConfig& config, std::ostream& log) {
  const ProtocolRecord record = load_specimen(file, world, cell, config, log);
  const std::string& source = record.source;
  const double stage = record.number("stage");
  require(stage == static_cast<int>(ShearStage::Consolidated), source + ": stage", stage,
          "2, a consolidated specimen (e.g. dem-consolidate's consolidated.restart)");
  require(record.flag("servo"), source + ": servo", "(none)", "the top plate's servo of the consolidation");
  release_rings(world, cell);
  ConsolidatedSpecimen specimen;
  specimen.height = record.number("consolidated_height");
  require(std::isfinite(specimen.height) && specimen.height > 0, source + ": consolidated_height", specimen.height, "> 0 m");
  // The servo as SimpleShearTest restores it: the consolidation's, with the target and speed cap of
  // the file (files written before those were recorded: the shear's cap).
  ServoSettings configured = consolidation_servo(config);
  configured.max_speed = shear_servo_speed(config, shear_strain_rate(config, world), specimen.height);
  specimen.servo = recorded_servo(record, configured);
  specimen.servo_steps_on_target = recorded_steps_on_target(record);
  return specimen;
}

}  // namespace dem::lab
