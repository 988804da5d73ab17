// Private to the library: the JSON documents it writes (summary.json of a run and of a
// calibration) are nlohmann::ordered_json values, so their keys stay in the order written. JSON
// has no NaN or infinity: nlohmann writes them as null (a quantity that could not be measured).
#pragma once

#include <filesystem>
#include <ostream>

#include <nlohmann/json.hpp>

#include <dem/io/atomic_file.hpp>

namespace dem::io {

using Json = nlohmann::ordered_json;

/// Writes `document` with two-space indents and a final newline, atomically (atomic_file.hpp).
inline void save_json(const std::filesystem::path& path, const Json& document) {
  write_atomically(path, [&](std::ostream& out) { out << document.dump(2) << '\n'; });
}

}  // namespace dem::io
