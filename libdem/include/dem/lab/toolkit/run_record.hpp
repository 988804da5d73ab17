// A protocol's record in a restart file (lab/toolkit/run.hpp writes it): the values its parts keep
// (numbers by key, and lists of positions by key) and the configuration the run was made with.
// Written as one JSON object; restart files of older versions, as "key value" lines, still read.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <dem/core/math.hpp>

namespace dem::lab {

/// The record: numbers by key (JSON null reads as NaN, true and false as 1 and 0), lists of
/// positions by key (m; NaN where a list has no position, e.g. the pebbles of a list by ball id)
/// and the configuration (key, value text).
struct ProtocolRecord {
  std::map<std::string, double> values;
  std::map<std::string, std::vector<Vec3>> points;
  std::vector<std::pair<std::string, std::string>> configuration;
  std::string source = "restart file";  // where the record came from, for error messages

  bool has(const std::string& key) const { return values.count(key) != 0; }
  /// The number of `key`; InputError naming the source when the record has none.
  double number(const std::string& key) const;
  /// The number of `key`, NaN when the record has none (keys that older files lack).
  double number_or_nan(const std::string& key) const;
  /// Whether `key` is there and above zero (true in JSON).
  bool flag(const std::string& key) const { return has(key) && values.at(key) > 0; }
};

/// Reads a record: a JSON object (InputError naming `source` when it does not parse, is not an
/// object or holds a value that is not a number, true/false, null, a list of [x, y, z] or, under
/// "configuration", an object of value texts), or, for text that does not start with '{', the
/// "key value" lines of restart files written before the record was JSON.
ProtocolRecord read_protocol_record(const std::string& text, const std::string& source = "restart file");

}  // namespace dem::lab
