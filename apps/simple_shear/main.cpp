// dem-simple-shear: the NGI-type simple-shear test of the study, end to end: specimen by radius
// expansion, consolidation, shear; or the shear alone from a restart file (--from).
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>
#include <dem/lab/simple_shear.hpp>

#include "cli/shear_command_line.hpp"

int main(int argc, char** argv) {
  try {
    const auto cli = dem::cli::parse_shear_command_line(
        argc, argv, "dem-simple-shear", "DEM simple-shear test (generate, consolidate, shear) with outputs in --out", std::cout);
    if (!cli) return 0;
    dem::lab::SimpleShearTest test(cli->config, cli->out_dir, std::cout);
    test.record_configuration(*cli->configuration);
    if (!cli->from.empty()) test.load_restart(cli->from);
    test.open_outputs({.replace = cli->replace, .program = "dem-simple-shear"});  // before any work
    test.run();
    test.write_summary(cli->resolved_json);
    std::cout << "results in " << cli->out_dir.string()
              << "/: history.csv, summary.json, fabric.csv, snapshots/ (ParaView: snapshots/*.pvd)\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-simple-shear: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-simple-shear: " << e.what() << "\n";
    return 1;
  }
}
