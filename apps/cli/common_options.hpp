// The options the apps' command lines share and the one order in which they resolve a
// configuration, so that every app reads presets, files, --set and --threads identically.
#pragma once

#include <boost/program_options.hpp>
#include <filesystem>
#include <string>

#include <dem/io/config.hpp>

namespace dem::cli {

/// Adds --help, --preset (unless `preset_help` is empty: a protocol without presets), --config,
/// --set, --threads and --print-config.
void add_common_options(boost::program_options::options_description& opts, const std::string& preset_help,
                        const std::string& config_help, const std::string& set_example);

/// Parses argv against `opts`; a malformed command line is an InputError that points to --help.
boost::program_options::variables_map parse_options(int argc, char** argv,
                                                    const boost::program_options::options_description& opts);

/// The configuration from schema defaults, then the preset, the --config file, each --set and
/// --threads, later ones overriding earlier ones.
io::Config resolve_config(io::Schema schema, const boost::program_options::variables_map& vm);

/// The --from restart file, checked to exist; empty when not given.
std::filesystem::path restart_file(const boost::program_options::variables_map& vm);

}  // namespace dem::cli
