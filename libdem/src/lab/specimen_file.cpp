// Restart files of the simple-shear protocol as parts: the protocol's record (written by
// SimpleShearTest::protocol_state, simple_shear_state.cpp), the stage, a consolidated specimen.
#include <dem/lab/specimen_file.hpp>

#include <cstdlib>
#include <limits>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/lab/simple_shear_parts.hpp>
#include <dem/lab/specimen_guards.hpp>

#include "../io/json_file.hpp"

namespace dem::lab {

namespace {


double number_of(const io::Json& item, const std::string& key) {
  if (item.is_null()) return std::numeric_limits<double>::quiet_NaN();  // JSON has no NaN: written as null
  if (item.is_boolean()) return item.get<bool>() ? 1.0 : 0.0;
  require(item.is_number(), "restart file: protocol state '" + key + "'", item.dump(), "a number, true/false or null");
  return item.get<double>();
}

ProtocolRecord read_json_state(const std::string& text) {
  ProtocolRecord record;
  io::Json j;
  try {
    j = io::Json::parse(text);
  } catch (const io::Json::parse_error& e) {
    throw InputError(std::string("restart file: protocol state is not JSON: ") + e.what());
  }
  require(j.is_object(), "restart file: protocol state", j.type_name(), "a JSON object");
  for (const auto& [key, item] : j.items()) {
    if (key == "configuration") {  // the record: an object of value texts
      require(item.is_object(), "restart file: configuration", item.type_name(), "an object of key: value text");
      for (const auto& [name, value] : item.items()) {
        require(value.is_string(), "restart file: configuration key '" + name + "'", value.dump(), "a value text");
        record.configuration.emplace_back(name, value.get<std::string>());
      }
    } else if (key == "profile_reference") {  // one position per ball id, null for pebbles
      require(item.is_array(), "restart file: profile_reference", item.type_name(), "an array of [x, y, z]");
      for (const auto& x : item) {
        require(x.is_array() && x.size() == 3, "restart file: profile_reference entry", x.dump(), "[x, y, z]");
        record.profile_reference.emplace_back(number_of(x[0], key), number_of(x[1], key), number_of(x[2], key));
      }
    } else {
      record.values[key] = number_of(item, key);
    }
  }
  return record;
}

// Restart files written before the state was JSON: "key value" lines, then the configuration and
// profile_reference blocks.
ProtocolRecord read_line_state(const std::string& text) {
  ProtocolRecord record;
  std::istringstream in(text);
  std::string key, token;
  while (in >> key >> token) {
  const double value = std::strtod(token.c_str(), nullptr);  // "nan" too: states of older runs
  if (key == "configuration") {  // a count, then that many "key = value" lines
    require(value >= 0 && value <= 1e4, "restart file: configuration count", value, "a count of keys (<= 10000)");
    std::string line;
    std::getline(in, line);
    for (long k = 0; k < static_cast<long>(value); ++k) {
      require(static_cast<bool>(std::getline(in, line)), "restart file: configuration", "(truncated)", "one line per key");
      const auto eq = line.find(" = ");
      require(eq != std::string::npos, "restart file: configuration line", line, "key = value");
      record.configuration.emplace_back(line.substr(0, eq), line.substr(eq + 3));
    }
    continue;
  }
  if (key == "profile_reference") {  // a count, then that many positions
    require(value >= 0 && value <= 1e9, "restart file: profile_reference count", value, "a count of balls");
    record.profile_reference.resize(static_cast<std::size_t>(value));
    for (Vec3& x : record.profile_reference) {
      std::string a, b, c;  // "nan" for the ids of pebbles
      in >> a >> b >> c;
      require(static_cast<bool>(in), "restart file: profile_reference", "(truncated)", "one position per ball id");
      x = Vec3(std::strtod(a.c_str(), nullptr), std::strtod(b.c_str(), nullptr), std::strtod(c.c_str(), nullptr));
    }
    continue;
  }
  record.values[key] = value;
}
  return record;
}

}  // namespace

double ProtocolRecord::number(const std::string& key) const {
  const auto it = values.find(key);
  if (it == values.end()) throw InputError("restart file: protocol state has no '" + key + "'");
  return it->second;
}

double ProtocolRecord::number_or_nan(const std::string& key) const {
  const auto it = values.find(key);
  return it == values.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}

ProtocolRecord read_protocol_record(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  return first != std::string::npos && text[first] == '{' ? read_json_state(text) : read_line_state(text);
}

ShearStage restart_stage(const std::filesystem::path& file) {
  const double stage = read_protocol_record(io::read_checkpoint_protocol(file)).number("stage");
  require(stage >= 0 && stage <= 4, "restart file " + file.string() + ": stage", stage, "0 to 4");
  return static_cast<ShearStage>(static_cast<int>(stage));
}

ConsolidatedSpecimen load_consolidated_specimen(const std::filesystem::path& file, World& world, const ShearCell& cell,
                                                const SimpleShearConfig& config, std::ostream& log) {
  const World as_configured = world;
  const ProtocolRecord record = read_protocol_record(io::load_checkpoint(file, world));
  const double stage = record.number("stage");
  require(stage == static_cast<int>(ShearStage::Consolidated), "restart file " + file.string() + ": stage", stage,
          "2, a consolidated specimen (e.g. dem-consolidate's consolidated.restart)");
  require(record.flag("servo"), "restart file " + file.string() + ": servo", "(none)", "the top plate's servo of the consolidation");
  require_configured_grading(world, config, file);
  apply_restart_keys(world, as_configured, cell, config, file, log);
  release_rings(world, cell);
  ConsolidatedSpecimen specimen;
  specimen.height = record.number("consolidated_height");
  // The servo as SimpleShearTest restores it: the consolidation's, with the target and speed cap of
  // the file (files written before those were recorded: the shear's cap).
  specimen.servo = consolidation_servo(config);
  if (record.has("servo_target")) {
    specimen.servo.target_stress = record.number("servo_target");
    specimen.servo.max_speed = record.number("servo_max_speed");
  } else {
    specimen.servo.max_speed = shear_servo_speed(config, shear_strain_rate(config, world), specimen.height);
  }
  const double on_target = record.has("servo_steps_on_target") ? record.number("servo_steps_on_target") : 0.0;
  require(on_target >= 0 && on_target <= 9e15, "restart file: servo_steps_on_target", on_target, "a count of steps >= 0");
  specimen.servo_steps_on_target = static_cast<std::int64_t>(on_target);
  return specimen;
}

}  // namespace dem::lab
