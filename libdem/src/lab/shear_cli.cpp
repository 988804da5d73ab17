#include <dem/lab/shear_cli.hpp>

#include <boost/program_options.hpp>
#include <ostream>

#include <dem/core/errors.hpp>

namespace po = boost::program_options;

namespace dem::lab {

std::optional<ShearCommandLine> parse_shear_command_line(int argc, char** argv, const std::string& program,
                                                         const std::string& purpose, std::ostream& out) {
  po::options_description opts("Options");
  opts.add_options()("help,h", "print this help and every configuration key")(
      "preset", po::value<std::string>()->default_value("4D"), "1D, 2D or 4D: the study's particle-size scale and Table 1 contact parameters")(
      "config,c", po::value<std::string>(), "configuration file (.ini or .json); overrides the preset")(
      "set,s", po::value<std::vector<std::string>>()->composing(), "override one key, e.g. --set shear.target_strain=0.1 (repeatable)")(
      "out,o", po::value<std::string>()->default_value("runs/simple-shear"), "output folder")(
      "from", po::value<std::string>(), "continue from a restart file (from dem-consolidate or an interrupted run)")(
      "threads", po::value<int>(), "OpenMP threads (same as --set engine.threads=N; default OMP_NUM_THREADS)")(
      "print-config", "print the resolved configuration (INI) and exit");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, opts), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw InputError(std::string("command line: ") + e.what() + " (see --help)");
  }
  const io::Schema schema = simple_shear_schema();
  if (vm.count("help")) {
    out << program << ": " << purpose << "\n\nUsage: " << program << " [--preset 4D] [--config FILE] [--set key=value ...] [--out DIR] [--from FILE]\n\n"
        << opts << "\nConfiguration keys (SI units; file sections are the part before the dot):\n"
        << schema.help_text();
    return std::nullopt;
  }
  io::Config config(schema);
  for (const auto& [key, value] : preset_values(vm["preset"].as<std::string>())) config.set(key, value);
  if (vm.count("config")) config.load_file(vm["config"].as<std::string>());
  if (vm.count("set"))
    for (const std::string& assignment : vm["set"].as<std::vector<std::string>>()) config.set(assignment);
  if (vm.count("threads")) {
    const int threads = vm["threads"].as<int>();
    require(threads >= 1, "--threads", threads, ">= 1");
    config.set("engine.threads", std::to_string(threads));
  }
  if (vm.count("print-config")) {
    out << config.to_ini();
    return std::nullopt;
  }
  ShearCommandLine cli;
  cli.config = simple_shear_config(config);
  cli.resolved_json = config.to_json();
  cli.out_dir = vm["out"].as<std::string>();
  if (vm.count("from")) {
    cli.from = vm["from"].as<std::string>();
    require(std::filesystem::exists(cli.from), "--from", cli.from.string(), "an existing restart file");
  }
  return cli;
}

}  // namespace dem::lab
