// Restart files of the simple-shear protocol as parts: the protocol's record (written by
// SimpleShearTest::protocol_state, simple_shear_state.cpp), the stage, a consolidated specimen.
#include <dem/lab/specimen_file.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/lab/simple_shear_parts.hpp>
#include <dem/lab/specimen_guards.hpp>

#include "../io/json_file.hpp"

namespace dem::lab {

namespace {

double number_of(const io::Json& item, const std::string& key, const std::string& source) {
  if (item.is_null()) return std::numeric_limits<double>::quiet_NaN();  // JSON has no NaN: written as null
  if (item.is_boolean()) return item.get<bool>() ? 1.0 : 0.0;
  require(item.is_number(), source + ": protocol state '" + key + "'", item.dump(), "a number, true/false or null");
  return item.get<double>();
}

ProtocolRecord read_json_state(const std::string& text, const std::string& source) {
  ProtocolRecord record;
  record.source = source;
  io::Json j;
  try {
    j = io::Json::parse(text);
  } catch (const io::Json::parse_error& e) {
    throw InputError(source + ": protocol state is not JSON: " + e.what());
  }
  require(j.is_object(), source + ": protocol state", j.type_name(), "a JSON object");
  for (const auto& [key, item] : j.items()) {
    if (key == "configuration") {  // the record: an object of value texts
      require(item.is_object(), source + ": configuration", item.type_name(), "an object of key: value text");
      for (const auto& [name, value] : item.items()) {
        require(value.is_string(), source + ": configuration key '" + name + "'", value.dump(), "a value text");
        record.configuration.emplace_back(name, value.get<std::string>());
      }
    } else if (key == "profile_reference") {  // one position per ball id, null for pebbles
      require(item.is_array(), source + ": profile_reference", item.type_name(), "an array of [x, y, z]");
      for (const auto& x : item) {
        require(x.is_array() && x.size() == 3, source + ": profile_reference entry", x.dump(), "[x, y, z]");
        record.profile_reference.emplace_back(number_of(x[0], key, source), number_of(x[1], key, source), number_of(x[2], key, source));
      }
    } else {
      record.values[key] = number_of(item, key, source);
    }
  }
  return record;
}

// Restart files written before the state was JSON: "key value" lines, then the configuration and
// profile_reference blocks.
ProtocolRecord read_line_state(const std::string& text, const std::string& source) {
  ProtocolRecord record;
  record.source = source;
  std::istringstream in(text);
  std::string key, token;
  while (in >> key >> token) {
    const double value = std::strtod(token.c_str(), nullptr);  // "nan" too: states of older runs
    if (key == "configuration") {  // a count, then that many "key = value" lines
      require(value >= 0 && value <= 1e4, source + ": configuration count", value, "a count of keys (<= 10000)");
      std::string line;
      std::getline(in, line);
      for (long k = 0; k < static_cast<long>(value); ++k) {
        require(static_cast<bool>(std::getline(in, line)), source + ": configuration", "(truncated)", "one line per key");
        const auto eq = line.find(" = ");
        require(eq != std::string::npos, source + ": configuration line", line, "key = value");
        record.configuration.emplace_back(line.substr(0, eq), line.substr(eq + 3));
      }
      continue;
    }
    if (key == "profile_reference") {  // a count, then that many positions
      require(value >= 0 && value <= 1e9, source + ": profile_reference count", value, "a count of balls");
      record.profile_reference.resize(static_cast<std::size_t>(value));
      for (Vec3& x : record.profile_reference) {
        std::string a, b, c;  // "nan" for the ids of pebbles
        in >> a >> b >> c;
        require(static_cast<bool>(in), source + ": profile_reference", "(truncated)", "one position per ball id");
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
  if (it == values.end()) throw InputError(source + ": protocol state has no '" + key + "'");
  return it->second;
}

double ProtocolRecord::number_or_nan(const std::string& key) const {
  const auto it = values.find(key);
  return it == values.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}

ProtocolRecord read_protocol_record(const std::string& text, const std::string& source) {
  const auto first = text.find_first_not_of(" \t\r\n");
  return first != std::string::npos && text[first] == '{' ? read_json_state(text, source) : read_line_state(text, source);
}

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
