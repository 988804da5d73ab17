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
#include <dem/lab/shear_cell.hpp>
#include <dem/lab/simple_shear_config.hpp>

namespace dem::lab {

/// How far the simple-shear protocol has brought a specimen.
enum class ShearStage : int { Empty = 0, Generated = 1, Consolidated = 2, Shearing = 3, Done = 4 };

/// The protocol's record in a restart file: numbers by key (JSON null reads as NaN, true and false
/// as 1 and 0), the configuration the file was made with (key, value text) and the positions that
/// start the current profile interval, by ball id (NaN for pebbles).
struct ProtocolRecord {
  std::map<std::string, double> values;
  std::vector<std::pair<std::string, std::string>> configuration;
  std::vector<Vec3> profile_reference;

  bool has(const std::string& key) const { return values.count(key) != 0; }
  /// The number of `key`; InputError when the record has none.
  double number(const std::string& key) const;
  /// The number of `key`, NaN when the record has none (keys that older files lack).
  double number_or_nan(const std::string& key) const;
  /// Whether `key` is there and not zero.
  bool flag(const std::string& key) const { return has(key) && values.at(key) > 0; }
};

/// Reads a record: a JSON object, or the "key value" lines of restart files written before the
/// record was JSON. InputError for a record that is neither.
ProtocolRecord read_protocol_record(const std::string& text);

/// The stage of the specimen in a restart file, read without loading its world.
ShearStage restart_stage(const std::filesystem::path& file);

/// A consolidated specimen as its restart file holds it, beyond the world's state.
struct ConsolidatedSpecimen {
  double height = 0.0;                     // m, H_c: the plate gap after consolidation
  ServoSettings servo;                     // the top plate's servo as the file left it
  std::int64_t servo_steps_on_target = 0;  // steps the servo has been on its target
};

/// Loads the consolidated specimen of `file` into `world`, which holds the shear cell `cell` built
/// from `config` (build_shear_cell with shear_cell_spec) and the protocol's contact laws
/// (set_contact_laws): the balls, rings, plates, contacts, time and step of the file. Then the guards
/// of lab/specimen_guards.hpp (grading, engine and specimen keys, changes logged to `log`), and the
/// rings released as `config` says (release_rings). InputError naming the file when it holds no
/// consolidated specimen (stage 2) or a guard refuses it.
ConsolidatedSpecimen load_consolidated_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                                                const SimpleShearConfig& config, std::ostream& log);

}  // namespace dem::lab
