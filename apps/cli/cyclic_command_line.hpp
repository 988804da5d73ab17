// Command line of dem-cyclic-shear: the simple-shear keys (specimen, contacts, consolidation) and
// the [cyclic] keys, resolved as every app resolves them (common_options.hpp).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

#include <dem/io/config.hpp>
#include <dem/lab/cyclic_shear_config.hpp>
#include <dem/lab/simple_shear_config.hpp>

namespace dem::cli {

struct CyclicCommandLine {
  lab::SimpleShearConfig specimen;
  lab::CyclicShearConfig cyclic;
  std::string resolved_json;      // every key, for summary.json
  std::filesystem::path out_dir;  // --out
  std::filesystem::path from;     // --from consolidated restart file, empty if none
  bool replace = false;
  std::optional<io::Config> configuration;
};

/// The schema of dem-cyclic-shear: simple_shear_schema() and the [cyclic] keys.
io::Schema cyclic_shear_schema();

/// Parses argv; nullopt when the program should stop successfully (--help, --print-config).
std::optional<CyclicCommandLine> parse_cyclic_command_line(int argc, char** argv, std::ostream& out);

}  // namespace dem::cli
