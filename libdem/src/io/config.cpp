// Schema-checked configuration. Text is parsed once, when a value is set, into a typed value;
// getters only check the type. INI files are read with Boost.PropertyTree, JSON files with
// nlohmann-json (config_json.cpp), both into key = value assignments, so that they share every
// validation rule.
#include "dem/io/config.hpp"

#include <algorithm>
#include <array>
#include <boost/property_tree/ini_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include <nlohmann/json.hpp>

#include "config_json.hpp"
#include "dem/base/input_file.hpp"
#include "dem/core/errors.hpp"

namespace dem::io {
namespace {

using Value = std::variant<double, long, bool, std::string, std::vector<double>>;

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// Shortest text that reads back as the same double (std::to_chars guarantees the round trip).
std::string format_real(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string format_list(const std::vector<double>& values) {
  std::string out;
  for (const double v : values) out += (out.empty() ? "" : ", ") + format_real(v);
  return out;
}

template <class T>
std::optional<T> parse_number(std::string text) {
  text = trim(text);
  std::string_view digits(text);
  if (!digits.empty() && digits.front() == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && digits.front() == '-') return std::nullopt;
  }
  T value{};
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size())
    return std::nullopt;
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(value)) return std::nullopt;
  return value;
}

// "> 0", "in [0, 1]", "<= 5" or "" for the bounds of a key.
std::string range_text(const KeySpec& spec) {
  const std::string low = spec.min ? format_real(*spec.min) : "";
  const std::string high = spec.max ? format_real(*spec.max) : "";
  if (spec.min && spec.max)
    return "in " + std::string(spec.min_exclusive ? "(" : "[") + low + ", " + high + "]";
  if (spec.min) return (spec.min_exclusive ? "> " : ">= ") + low;
  if (spec.max) return "<= " + high;
  return {};
}

std::string allowed_text(const KeySpec& spec) {
  const std::string range = range_text(spec);
  std::string out;
  switch (spec.type) {
    case ValueType::Real: out = "a finite real number"; break;
    case ValueType::Integer: out = "an integer"; break;
    case ValueType::Boolean: out = "true/false, 1/0, yes/no or on/off"; break;
    case ValueType::RealList: out = "a comma-separated list of finite real numbers"; break;
    case ValueType::Text:
      out = "text on one line";
      if (!spec.choices.empty()) {
        out = "one of:";
        for (const auto& choice : spec.choices) out += " '" + choice + "'";
      }
  }
  if (!range.empty()) out += (spec.type == ValueType::RealList ? ", each " : " ") + range;
  if (!spec.unit.empty() && spec.unit != "-") out += " (unit: " + spec.unit + ")";
  return out;
}

bool in_range(const KeySpec& spec, double value) {
  if (spec.min && (spec.min_exclusive ? value <= *spec.min : value < *spec.min)) return false;
  return !(spec.max && value > *spec.max);
}

// The typed value of `text` for `spec`, or InputError naming key, value and what is allowed.
Value parse_value(const KeySpec& spec, const std::string& raw) {
  const std::string text = trim(raw);
  const auto fail = [&]() -> Value {
    throw InputError("config key '" + spec.key + "' = '" + quoted_excerpt(text) + "': must be " +
                     allowed_text(spec));
  };
  switch (spec.type) {
    case ValueType::Real: {
      const auto value = parse_number<double>(text);
      return value && in_range(spec, *value) ? Value(*value) : fail();
    }
    case ValueType::Integer: {
      const auto value = parse_number<long>(text);
      return value && in_range(spec, static_cast<double>(*value)) ? Value(*value) : fail();
    }
    case ValueType::Boolean: {
      const std::string word = lower(text);
      if (word == "true" || word == "1" || word == "yes" || word == "on") return true;
      if (word == "false" || word == "0" || word == "no" || word == "off") return false;
      return fail();
    }
    case ValueType::Text: {
      const bool listed = spec.choices.empty() ||
          std::find(spec.choices.begin(), spec.choices.end(), text) != spec.choices.end();
      return listed && text.find_first_of("\r\n") == std::string::npos ? Value(text) : fail();
    }
    case ValueType::RealList: {
      std::vector<double> values;
      if (text.empty()) return values;
      std::istringstream cells(text);
      for (std::string cell; std::getline(cells, cell, ',');) {
        const auto value = parse_number<double>(cell);
        if (!value || !in_range(spec, *value)) return fail();
        values.push_back(*value);
      }
      if (text.back() == ',') return fail();  // getline drops an empty last cell
      return values;
    }
  }
  return fail();
}

std::string format_value(const Value& value) {
  if (const auto* v = std::get_if<double>(&value)) return format_real(*v);
  if (const auto* v = std::get_if<long>(&value)) return std::to_string(*v);
  if (const auto* v = std::get_if<bool>(&value)) return *v ? "true" : "false";
  if (const auto* v = std::get_if<std::string>(&value)) return *v;
  return format_list(std::get<std::vector<double>>(value));
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

std::string section_of(const std::string& key) { return key.substr(0, key.find('.')); }
std::string name_of(const std::string& key) { return key.substr(key.find('.') + 1); }

// Key indices grouped by section, sections in order of first appearance: a schema declared out
// of order must still print each INI section once (read_ini rejects a repeated section).
std::vector<std::vector<std::size_t>> by_section(const std::vector<KeySpec>& keys) {
  std::vector<std::vector<std::size_t>> groups;
  std::map<std::string, std::size_t> group_of;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const auto [it, added] = group_of.emplace(section_of(keys[i].key), groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  return groups;
}

[[noreturn]] void unknown_key(const Schema& schema, const std::string& key) {
  // Suggest the nearest keys by edit distance, and the same name filed under another section.
  std::size_t best = key.size() / 3 + 2;  // farther than this is not a typo
  for (const auto& spec : schema.keys()) best = std::min(best, edit_distance(key, spec.key));
  std::string message = "unknown config key '" + quoted_excerpt(key) + "'";
  std::string near;
  for (const auto& spec : schema.keys())
    if (edit_distance(key, spec.key) == best || name_of(spec.key) == name_of(key))
      near += (near.empty() ? "" : " or ") + ("'" + spec.key + "'");
  if (!near.empty()) throw InputError(message + "; did you mean " + near + "?");
  message += "; no similar key, the sections are:";
  for (const auto& group : by_section(schema.keys()))
    message += " [" + section_of(schema.keys()[group.front()].key) + "]";
  throw InputError(message);
}

bool valid_key(const std::string& key) {
  const auto dot = key.find('.');
  const bool one_inner_dot = dot != 0 && dot != std::string::npos && dot + 1 != key.size() &&
                             std::count(key.begin(), key.end(), '.') == 1;
  return one_inner_dot && std::all_of(key.begin(), key.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
         });
}

// The assignments of an INI property tree: section.key = value (read_ini refuses repeats).
void ini_settings(const boost::property_tree::ptree& node, const std::string& prefix,
                  std::vector<std::pair<std::string, std::string>>& settings) {
  for (const auto& [name, child] : node) {
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    if (child.empty()) settings.emplace_back(key, child.data());
    else ini_settings(child, key, settings);
  }
}

// read_ini refuses a repeated key or section by line only; this adds its name.
std::string ini_duplicate(const std::string& text, std::size_t at_line, const std::string& problem) {
  std::istringstream lines(text);
  std::string line, section;
  for (std::size_t n = 1; std::getline(lines, line) && n <= at_line; ++n) {
    line = trim(line);
    if (line.empty() || line[0] != '[') {
      if (n == at_line) {
        const std::string name = trim(line.substr(0, line.find('=')));
        return problem + " '" + (section.empty() ? name : section + "." + name) + "'";
      }
      continue;
    }
    section = trim(line.substr(1, line.find(']') - 1));
    if (n == at_line) return problem + " '" + section + "'";
  }
  return problem;
}

}  // namespace

std::string to_string(ValueType type) {
  switch (type) {
    case ValueType::Real: return "real";
    case ValueType::Integer: return "integer";
    case ValueType::Boolean: return "boolean";
    case ValueType::Text: return "text";
    case ValueType::RealList: return "real list";
  }
  return "unknown";
}

Schema& Schema::add(KeySpec spec) {
  const auto reject = [&](const std::string& why) {
    throw std::logic_error("config schema key '" + spec.key + "': " + why);
  };
  if (!valid_key(spec.key)) reject("must be section.name of letters, digits, '_' or '-'");
  if (index_.count(spec.key)) reject("declared twice");
  const bool numeric = spec.type == ValueType::Real || spec.type == ValueType::Integer ||
                       spec.type == ValueType::RealList;
  if ((spec.min || spec.max) && !numeric) reject("bounds need a numeric type");
  if (spec.min && spec.max && *spec.min > *spec.max) reject("min > max");
  if (!spec.choices.empty() && spec.type != ValueType::Text) reject("choices need type text");
  if ((spec.unit + spec.help).find_first_of("\r\n") != std::string::npos)
    reject("unit and help must be single lines");
  try {
    parse_value(spec, spec.default_value);
  } catch (const InputError& e) {
    reject(std::string("invalid default: ") + e.what());
  }
  index_.emplace(spec.key, keys_.size());
  keys_.push_back(std::move(spec));
  return *this;
}

const KeySpec* Schema::find(const std::string& key) const {
  const auto it = index_.find(key);
  return it == index_.end() ? nullptr : &keys_[it->second];
}

std::string Schema::help_text() const {
  std::vector<std::array<std::string, 5>> rows;  // key, type, default, unit, allowed
  std::array<std::size_t, 5> width{};
  for (const auto& spec : keys_) {
    const std::string range = spec.choices.empty() ? range_text(spec) : allowed_text(spec);
    const std::string shown_default = format_value(parse_value(spec, spec.default_value));
    const std::string any = spec.type == ValueType::Boolean ? "true/false" : "any";
    rows.push_back({spec.key, to_string(spec.type), shown_default,
                    spec.unit.empty() ? "-" : spec.unit, range.empty() ? any : range});
    for (std::size_t c = 0; c < width.size(); ++c)
      width[c] = std::max(width[c], rows.back()[c].size());
  }
  std::string out;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < width.size(); ++c)
      out += rows[r][c] + std::string(width[c] - rows[r][c].size() + 2, ' ');
    out += keys_[r].help + "\n";
  }
  return out;
}

Config::Config(const Schema& schema) : schema_(schema) {
  for (const auto& spec : schema_.keys()) values_.push_back(parse_value(spec, spec.default_value));
}

void Config::set(const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos)
    throw InputError("setting '" + quoted_excerpt(assignment) + "': must have the form section.key=value");
  set(trim(assignment.substr(0, equals)), assignment.substr(equals + 1));
}

void Config::set(const std::string& key, const std::string& value) {
  const KeySpec* spec = schema_.find(key);
  if (!spec) unknown_key(schema_, key);
  values_[static_cast<std::size_t>(spec - schema_.keys().data())] = parse_value(*spec, value);
}

void Config::load_file(const std::filesystem::path& path) {
  const std::string extension = lower(path.extension().string());
  const std::string where = "config file " + path.string() + ": ";
  if (extension != ".ini" && extension != ".json")
    throw InputError(where + "extension '" + path.extension().string() +
                     "' not supported: must be .ini or .json");
  std::error_code ec;
  // Its size is checked below, as it is read.
  require_input_file(path, "config file", "an .ini or .json configuration file", std::numeric_limits<std::uintmax_t>::max());
  const auto refuse_size = [&](const std::string& size) {
    throw InputError(where + "size " + size + " bytes: must be at most " +
                     std::to_string(max_config_file_bytes) + " bytes (a configuration is a few KB)");
  };
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > max_config_file_bytes) refuse_size(std::to_string(bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where + "cannot be opened");
  std::string text;
  std::array<char, 65536> chunk;
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_config_file_bytes) refuse_size("> " + std::to_string(max_config_file_bytes));  // it grew
  }
  if (in.bad()) throw InputError(where + "cannot be read");

  std::vector<std::pair<std::string, std::string>> settings;
  if (extension == ".ini") {
    boost::property_tree::ptree tree;
    try {
      std::istringstream stream(text);
      boost::property_tree::read_ini(stream, tree);
    } catch (const boost::property_tree::file_parser_error& e) {
      const std::string problem = e.message().rfind("duplicate", 0) == 0 ? ini_duplicate(text, e.line(), e.message())
                                                                         : e.message();
      throw InputError(where + "line " + std::to_string(e.line()) + ": " + problem);
    }
    ini_settings(tree, "", settings);
  } else {
    settings = read_json_settings(text, where);
  }
  const auto before = values_;  // all or nothing: a bad file changes no value
  try {
    for (const auto& [key, value] : settings) set(key, value);
  } catch (const InputError& e) {
    values_ = before;
    throw InputError(where + e.what());
  }
}

template <class T>
const T& Config::get(const std::string& key, ValueType type) const {
  const KeySpec* spec = schema_.find(key);
  if (!spec) throw std::logic_error("config key '" + key + "' is not in the schema");
  if (spec->type != type)
    throw std::logic_error("config key '" + key + "' is " + to_string(spec->type) +
                           ", read as " + to_string(type));
  return std::get<T>(values_[static_cast<std::size_t>(spec - schema_.keys().data())]);
}

double Config::real(const std::string& key) const { return get<double>(key, ValueType::Real); }
long Config::integer(const std::string& key) const { return get<long>(key, ValueType::Integer); }
bool Config::boolean(const std::string& key) const { return get<bool>(key, ValueType::Boolean); }
std::string Config::text(const std::string& key) const {
  return get<std::string>(key, ValueType::Text);
}
std::vector<double> Config::real_list(const std::string& key) const {
  return get<std::vector<double>>(key, ValueType::RealList);
}

std::string Config::exact_text(const std::string& key) const {
  const KeySpec* spec = schema_.find(key);
  if (spec == nullptr) throw std::logic_error("Config::exact_text: no key '" + key + "' in the schema");
  auto shortest = [](double v) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
  };
  switch (spec->type) {
    case ValueType::Real: return shortest(real(key));
    case ValueType::Integer: return std::to_string(integer(key));
    case ValueType::Boolean: return boolean(key) ? "true" : "false";
    case ValueType::Text: return text(key);
    case ValueType::RealList: {
      std::string out;
      for (double v : real_list(key)) out += (out.empty() ? "" : ",") + shortest(v);
      return out;
    }
  }
  return {};
}

std::string Config::to_ini() const {
  const auto& keys = schema_.keys();
  std::string out = "# Resolved configuration: every key, SI units.\n";
  for (const auto& group : by_section(keys)) {
    out += "\n[" + section_of(keys[group.front()].key) + "]\n";
    for (const std::size_t i : group) {
      out += "# " + keys[i].help + (keys[i].unit.empty() ? "" : " [" + keys[i].unit + "]") + "\n";
      out += name_of(keys[i].key) + " = " + format_value(values_[i]) + "\n";
    }
  }
  return out;
}

std::string Config::to_json() const {
  const auto& keys = schema_.keys();
  nlohmann::ordered_json document = nlohmann::ordered_json::object();
  for (const auto& group : by_section(keys)) {
    nlohmann::ordered_json& section = document[section_of(keys[group.front()].key)];
    section = nlohmann::ordered_json::object();
    for (const std::size_t i : group)
      std::visit([&](const auto& value) { section[name_of(keys[i].key)] = value; }, values_[i]);
  }
  return document.dump(2) + "\n";
}

}  // namespace dem::io
