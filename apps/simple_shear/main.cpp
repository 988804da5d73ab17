// dem-simple-shear: the NGI-type simple-shear test of the study, end to end: specimen by radius
// expansion, consolidation, shear; or the shear alone from a restart file (--from).
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>

#include "cli/shear_command_line.hpp"
#include "cli/simple_shear_run.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  try {
    const auto cli = dem::cli::parse_shear_command_line(
        argc, argv, "dem-simple-shear", "DEM simple-shear test (generate, consolidate, shear) with outputs in --out", std::cout);
    if (!cli) return 0;
    dem::cli::require_one_process("dem-simple-shear");
    dem::cli::run_simple_shear(*cli, std::cout, "dem-simple-shear");
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
