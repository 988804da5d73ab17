// Command line of dem-calibrate: a calibration configuration (defaults, preset, file, --set), the
// lab curve, the parameters to fit and the output folder. Every problem is an InputError that
// names the option or key, the value and what is allowed.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>

#include <dem/io/config.hpp>
#include <dem/lab/protocols/calibration.hpp>

namespace dem::cli {

/// Command line of dem-calibrate (see its --help).
struct CalibrationCommandLine {
  io::Config config;  // lab::calibration_schema()
  lab::CalibrationSettings settings;
  lab::LabCurve lab;
  std::filesystem::path out_dir, from;
};

/// Parses argv; nullopt after --help or --print-config (text written to `out`).
std::optional<CalibrationCommandLine> parse_calibration_command_line(int argc, char** argv, std::ostream& out);

}  // namespace dem::cli
