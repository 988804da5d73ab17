#include "cyclic_command_line.hpp"

#include <ostream>

#include "common_options.hpp"

namespace po = boost::program_options;

namespace dem::cli {

io::Schema cyclic_shear_schema() {
  io::Schema schema = lab::simple_shear_schema();
  lab::add_cyclic_shear_keys(schema);
  return schema;
}

std::optional<CyclicCommandLine> parse_cyclic_command_line(int argc, char** argv, std::ostream& out) {
  po::options_description opts("Options");
  add_common_options(opts, "1D, 2D or 4D: the study's particle-size scale and Table 1 contact parameters",
                     "configuration file (.ini or .json); overrides the preset", "cyclic.csr=0.15");
  opts.add_options()("out,o", po::value<std::string>()->default_value("runs/cyclic-shear"), "output folder")(
      "from", po::value<std::string>(), "start from a consolidated restart file (consolidated.restart of dem-consolidate or another run)")(
      "replace", "remove the results of another run in --out first (without it such a folder is refused)");
  const po::variables_map vm = parse_options(argc, argv, opts);
  if (vm.count("help")) {
    out << "dem-cyclic-shear: cyclic and multidirectional simple shear (stress or strain control, constant volume or "
           "drained) on a specimen generated and consolidated here or read with --from\n\nUsage: dem-cyclic-shear [--preset 4D] "
           "[--config FILE] [--set key=value ...] [--out DIR] [--from FILE] [--replace]\n\n"
        << opts << "\nConfiguration keys (SI units; file sections are the part before the dot):\n"
        << cyclic_shear_schema().help_text();
    return std::nullopt;
  }
  const io::Config config = resolve_config(cyclic_shear_schema(), vm);
  if (vm.count("print-config")) {
    out << config.to_ini();
    return std::nullopt;
  }
  CyclicCommandLine cli;
  cli.specimen = lab::simple_shear_config(config);
  cli.cyclic = lab::cyclic_shear_config(config);
  cli.resolved_json = config.to_json();
  cli.out_dir = vm["out"].as<std::string>();
  cli.from = restart_file(vm);
  cli.replace = vm.count("replace") > 0;
  cli.configuration = config;
  return cli;
}

}  // namespace dem::cli
