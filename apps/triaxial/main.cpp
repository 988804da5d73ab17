// dem-triaxial: a drained triaxial test on a cube of balls between six servo walls
// (lab/protocols/triaxial.hpp): isotropic compression to the confining stress, then axial
// compression at a constant strain rate; resumable from its restart files (--from).
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>
#include <dem/lab/protocols/triaxial.hpp>

#include "cli/common_options.hpp"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  try {
    po::options_description opts("Options");
    dem::cli::add_common_options(opts, "", "configuration file (.ini or .json)", "axial.target_strain=0.2");
    opts.add_options()("out,o", po::value<std::string>()->default_value("triaxial"), "output folder")(
        "from", po::value<std::string>(), "continue from a restart file of an earlier run")(
        "replace", "remove the results of another run in --out first (without it such a folder is refused)");
    const po::variables_map vm = dem::cli::parse_options(argc, argv, opts);
    const dem::io::Schema schema = dem::lab::triaxial_schema();
    if (vm.count("help")) {
      std::cout << "dem-triaxial: drained triaxial test on a cube of balls between six servo walls\n\nUsage: dem-triaxial "
                << "[--config FILE] [--set key=value ...] [--out DIR] [--from FILE] [--replace]\n\n"
                << opts << "\nConfiguration keys (SI units; file sections are the part before the dot):\n" << schema.help_text();
      return 0;
    }
    const dem::io::Config config = dem::cli::resolve_config(schema, vm);
    if (vm.count("print-config")) {
      std::cout << config.to_ini();
      return 0;
    }
    const std::string out = vm["out"].as<std::string>();
    dem::lab::TriaxialTest test(dem::lab::triaxial_config(config), out, std::cout);
    test.record_configuration(config);
    if (const auto from = dem::cli::restart_file(vm); !from.empty()) test.load_restart(from);
    test.open_outputs({.replace = vm.count("replace") > 0, .program = "dem-triaxial"});
    test.run();
    test.write_summary(config.to_json());
    std::cout << "results in " << out << "/: history.csv, summary.json\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-triaxial: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-triaxial: " << e.what() << "\n";
    return 1;
  }
}
