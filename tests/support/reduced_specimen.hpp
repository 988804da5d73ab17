// The reduced simple-shear specimen the integration tests run (30 mm x 12 mm, 4D balls: about
// 170), as a configuration each test completes with its own strains and outputs.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <dem/io/config.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::testing {

/// The 4D preset on a 30 mm x 12 mm specimen, one thread.
inline io::Config reduced_specimen() {
  io::Config c(lab::simple_shear_schema());
  for (const auto& [k, v] : lab::preset_values("4D")) c.set(k, v);
  c.set("specimen.diameter", "0.03");
  c.set("specimen.height", "0.012");
  c.set("engine.threads", "1");
  return c;
}

/// The whole file as text ("" if it cannot be read).
inline std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace dem::testing
