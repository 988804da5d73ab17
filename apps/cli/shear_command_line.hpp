// Command line of dem-simple-shear and dem-consolidate: a configuration from defaults, a preset, a file
// and --set overrides (in that order of precedence), an output folder and an optional restart
// file. Every problem is an InputError that names the option or key, the value and what is allowed.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

#include <dem/io/config.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::cli {

struct ShearCommandLine {
  lab::SimpleShearConfig config;
  std::string resolved_json;      // every key, for summary.json and --print-config
  std::filesystem::path out_dir;  // --out
  std::filesystem::path from;     // --from restart file, empty if none
  bool replace = false;           // --replace: remove another run's results in --out
  std::optional<io::Config> configuration;  // resolved, for SimpleShearTest::record_configuration
};

/// Parses argv against `schema` (the simple-shear keys, or those and a protocol's own). Returns
/// nullopt when the program should stop successfully (--help or --print-config, whose text goes
/// to `out`).
std::optional<ShearCommandLine> parse_shear_command_line(int argc, char** argv, const std::string& program,
                                                         const std::string& purpose, std::ostream& out,
                                                         const io::Schema& schema = lab::simple_shear_schema(),
                                                         const std::string& default_out = "runs/simple-shear");

}  // namespace dem::cli
