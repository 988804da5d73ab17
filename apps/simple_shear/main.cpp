// dem-simple-shear: the NGI-type simple-shear test of the study, end to end: specimen by radius
// expansion, consolidation, shear; or the shear alone from a restart file (--from). Under mpirun
// the simulation is spread over the ranks (World::spread_over), with the one-process results.
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include <dem/core/errors.hpp>

#include "cli/shear_command_line.hpp"
#include "cli/simple_shear_run.hpp"
#include "cli/spread_run.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  std::unique_ptr<dem::parallel::TaskFarm> farm;
  try {
    farm = dem::cli::open_task_farm(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "dem-simple-shear: " << e.what() << "\n";
    return 2;
  }
  try {
    std::ostringstream quiet;
    std::optional<dem::cli::ShearCommandLine> cli;
    farm->together([&] {  // a bad command line or configuration: every rank stops, the leader tells
      cli = dem::cli::parse_shear_command_line(
          argc, argv, "dem-simple-shear", "DEM simple-shear test (generate, consolidate, shear) with outputs in --out",
          farm->leads() ? static_cast<std::ostream&>(std::cout) : quiet);
    });
    if (!cli) return 0;
    dem::cli::SpreadRun spread(*farm, cli->out_dir);
    dem::cli::run_simple_shear(*cli, spread.log(std::cout), "dem-simple-shear", &spread);
    spread.log(std::cout) << "results in " << cli->out_dir.string()
                          << "/: history.csv, summary.json, fabric.csv, snapshots/ (ParaView: snapshots/*.pvd)\n";
  } catch (const dem::InputError& e) {
    return dem::cli::end_on_error(*farm, "dem-simple-shear", e, 2, std::cerr);
  } catch (const std::exception& e) {
    return dem::cli::end_on_error(*farm, "dem-simple-shear", e, 1, std::cerr);
  }
}
