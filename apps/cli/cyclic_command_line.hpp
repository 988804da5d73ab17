// Command line of dem-cyclic-shear: the simple-shear command line (shear_command_line.hpp) over
// the simple-shear keys and the [cyclic] keys (lab::cyclic_shear_schema()).
#pragma once

#include <iosfwd>
#include <optional>

#include <dem/lab/protocols/cyclic_shear_config.hpp>

#include "shear_command_line.hpp"

namespace dem::cli {

struct CyclicCommandLine {
  ShearCommandLine specimen;  // the specimen's configuration, folders and the resolved record
  lab::CyclicShearConfig cyclic;
};

/// Parses argv; nullopt when the program should stop successfully (--help, --print-config).
std::optional<CyclicCommandLine> parse_cyclic_command_line(int argc, char** argv, std::ostream& out);

}  // namespace dem::cli
