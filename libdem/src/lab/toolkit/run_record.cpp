// The protocol's record in a restart file: the JSON object lab/toolkit/run.cpp writes, or the "key
// value" lines of files written before.
#include <dem/lab/toolkit/run_record.hpp>

#include <cstdlib>
#include <limits>
#include <sstream>

#include <dem/core/errors.hpp>

#include "../../io/json_file.hpp"

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
    } else if (item.is_array()) {  // positions, e.g. by ball id with null for pebbles
      std::vector<Vec3>& points = record.points[key];
      for (const auto& x : item) {
        require(x.is_array() && x.size() == 3, source + ": " + key + " entry", x.dump(), "[x, y, z]");
        points.emplace_back(number_of(x[0], key, source), number_of(x[1], key, source), number_of(x[2], key, source));
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
      std::vector<Vec3>& points = record.points[key];
      points.resize(static_cast<std::size_t>(value));
      for (Vec3& x : points) {
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

}  // namespace dem::lab
