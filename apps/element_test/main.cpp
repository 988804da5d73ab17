// dem-element-test: element tests in a periodic cell (lab/protocols/element_test.hpp): a specimen
// of a preset's balls compressed isotropically by the cell, then a triaxial, simple-shear or cyclic simple-shear path
// by the cell's velocity gradient; resumable from its restart files (--from).
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>
#include <dem/lab/protocols/element_test.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

#include "cli/common_options.hpp"

namespace po = boost::program_options;

namespace {

// The schema's defaults, the preset's material (grading.scale and ball_ball; the simple-shear
// cell's keys of a preset are not this test's), then the file, each --set and --threads.
dem::io::Config resolve(const dem::io::Schema& schema, const po::variables_map& vm) {
  dem::io::Config config(schema);
  for (const auto& [key, value] : dem::lab::preset_values(vm["preset"].as<std::string>()))
    if (schema.find(key) != nullptr) config.set(key, value);
  if (vm.count("config")) config.load_file(vm["config"].as<std::string>());
  if (vm.count("set"))
    for (const std::string& assignment : vm["set"].as<std::vector<std::string>>()) config.set(assignment);
  if (vm.count("threads")) {
    const int threads = vm["threads"].as<int>();
    dem::require(threads >= 1, "--threads", threads, ">= 1");
    config.set("engine.threads", std::to_string(threads));
  }
  return config;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    po::options_description opts("Options");
    dem::cli::add_common_options(opts, "particle size scale and contact parameters of the study: 1D, 2D or 4D",
                                 "configuration file (.ini or .json)", "element.test=triaxial-drained");
    opts.add_options()("out,o", po::value<std::string>()->default_value("element-test"), "output folder")(
        "from", po::value<std::string>(), "continue from a restart file of an earlier run")(
        "replace", "remove the results of another run in --out first (without it such a folder is refused)");
    const po::variables_map vm = dem::cli::parse_options(argc, argv, opts);
    const dem::io::Schema schema = dem::lab::element_test_schema();
    if (vm.count("help")) {
      std::cout << "dem-element-test: element tests (isotropic, triaxial, simple shear, cyclic simple shear) in a periodic cell\n\nUsage: dem-element-test "
                << "[--preset 1D|2D|4D] [--config FILE] [--set key=value ...] [--out DIR] [--from FILE] [--replace]\n\n"
                << opts << "\nConfiguration keys (SI units; file sections are the part before the dot):\n" << schema.help_text();
      return 0;
    }
    const dem::io::Config config = resolve(schema, vm);
    if (vm.count("print-config")) {
      std::cout << config.to_ini();
      return 0;
    }
    const std::string out = vm["out"].as<std::string>();
    dem::lab::ElementTest test(dem::lab::element_test_config(config), out, std::cout);
    test.record_configuration(config);
    if (const auto from = dem::cli::restart_file(vm); !from.empty()) test.load_restart(from);
    test.open_outputs({.replace = vm.count("replace") > 0, .program = "dem-element-test"});
    test.run();
    test.write_summary(config.to_json());
    std::cout << "results in " << out << "/: history.csv, summary.json, restart files\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-element-test: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-element-test: " << e.what() << "\n";
    return 1;
  }
}
