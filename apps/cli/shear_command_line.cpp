#include "shear_command_line.hpp"

#include <ostream>

#include "common_options.hpp"

namespace po = boost::program_options;

namespace dem::cli {

std::optional<ShearCommandLine> parse_shear_command_line(int argc, char** argv, const std::string& program,
                                                         const std::string& purpose, std::ostream& out,
                                                         const io::Schema& schema, const std::string& default_out) {
  po::options_description opts("Options");
  add_common_options(opts, "1D, 2D or 4D: the study's particle-size scale and Table 1 contact parameters",
                             "configuration file (.ini or .json); overrides the preset", "shear.target_strain=0.1");
  opts.add_options()("out,o", po::value<std::string>()->default_value(default_out), "output folder")(
      "from", po::value<std::string>(), "continue from a restart file (from dem-consolidate or an interrupted run)")(
      "replace", "remove the results of another run in --out first (without it such a folder is refused)");
  const po::variables_map vm = parse_options(argc, argv, opts);
  if (vm.count("help")) {
    out << program << ": " << purpose << "\n\nUsage: " << program << " [--preset 4D] [--config FILE] [--set key=value ...] [--out DIR] [--from FILE] [--replace]\n\n"
        << opts << "\nConfiguration keys (SI units; file sections are the part before the dot):\n"
        << schema.help_text();
    return std::nullopt;
  }
  const io::Config config = resolve_config(schema, vm);
  if (vm.count("print-config")) {
    out << config.to_ini();
    return std::nullopt;
  }
  ShearCommandLine cli;
  cli.config = lab::simple_shear_config(config);
  cli.resolved_json = config.to_json();
  cli.out_dir = vm["out"].as<std::string>();
  cli.from = restart_file(vm);
  cli.replace = vm.count("replace") > 0;
  cli.configuration = config;
  return cli;
}

}  // namespace dem::cli
