// Reads a JSON file the library wrote (summary.json) for a test to check.
#pragma once

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace dem::testing {

inline nlohmann::ordered_json load_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + " cannot be opened");
  return nlohmann::ordered_json::parse(in);
}

}  // namespace dem::testing
