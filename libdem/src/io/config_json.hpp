// Private to the library: a configuration file's JSON read into key = value assignments, the form
// INI files take, so that both share every validation rule (config.cpp). nlohmann's SAX parser is
// not recursive, so a deeply nested file cannot overflow the stack; the reader refuses it by depth.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace dem::io {

/// The leaves of a JSON configuration as (key, value text): nested objects join their names with
/// '.', an array of numbers becomes their comma-separated list. InputError (prefixed with `where`)
/// with the line for a syntax error, a key or section given twice (also as "a.b" and {"a": {"b"}}),
/// nesting deeper than max_config_depth, a list where named keys belong, or a list of non-numbers.
std::vector<std::pair<std::string, std::string>> read_json_settings(const std::string& text, const std::string& where);

}  // namespace dem::io
