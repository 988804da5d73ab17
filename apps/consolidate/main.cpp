// dem-consolidate: makes the specimen and consolidates it, leaving consolidated.restart in --out,
// from which dem-simple-shear --from shears the same specimen in as many ways as wanted. Given a
// consolidated specimen (--from), it consolidates that packing again with this configuration's
// contact parameters (e.g. another E*). Under mpirun the simulation is spread over the ranks
// (World::spread_over), with the one-process results.
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

#include "cli/shear_command_line.hpp"
#include "cli/spread_run.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  std::unique_ptr<dem::parallel::TaskFarm> farm;
  try {
    farm = dem::cli::open_task_farm(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "dem-consolidate: " << e.what() << "\n";
    return 2;
  }
  try {
    std::ostringstream quiet;
    std::optional<dem::cli::ShearCommandLine> cli;
    std::unique_ptr<dem::cli::SpreadRun> spread;  // outlives the test, whose files are in its folder
    std::unique_ptr<dem::lab::SimpleShearTest> test;
    farm->together([&] {  // a bad command line, configuration or folder: every rank stops, the leader tells
      cli = dem::cli::parse_shear_command_line(
          argc, argv, "dem-consolidate", "generate and consolidate a simple-shear specimen; writes consolidated.restart",
          farm->leads() ? static_cast<std::ostream&>(std::cout) : quiet);
      if (!cli) return;
      dem::lab::require_rings_spreadable(cli->config.rings.vertical, farm->processes());
      spread = std::make_unique<dem::cli::SpreadRun>(*farm, cli->out_dir);
      test = std::make_unique<dem::lab::SimpleShearTest>(cli->config, spread->out_dir(), spread->log(std::cout));
      test->record_configuration(*cli->configuration);
      // A consolidated specimen is consolidated again with this configuration's contact parameters.
      if (!cli->from.empty()) test->load_restart(cli->from, dem::lab::ResumeIntent::Reconsolidate);
      if (test->stage() >= dem::lab::ShearStage::Shearing)
        throw dem::InputError("--from " + cli->from.string() + ": stage " + std::to_string(static_cast<int>(test->stage())) +
                              " (shearing or sheared): must be a restart of the generation (0), after it (1) or after the "
                              "consolidation (2); continue a shear with dem-simple-shear --from");
      test->open_outputs({.replace = cli->replace, .program = "dem-consolidate"});  // before any work
    });
    if (!cli) return 0;
    spread->spread(test->world());
    if (test->stage() == dem::lab::ShearStage::Empty) test->generate();
    if (test->stage() == dem::lab::ShearStage::Generated) test->consolidate();
    else if (test->stage() == dem::lab::ShearStage::Consolidated) test->reconsolidate();
    test->write_summary(cli->resolved_json);
    spread->log(std::cout) << "consolidated specimen: " << (cli->out_dir / "consolidated.restart").string()
                           << "\nshear it with: dem-simple-shear --from " << (cli->out_dir / "consolidated.restart").string() << "\n";
  } catch (const dem::InputError& e) {
    return dem::cli::end_on_error(*farm, "dem-consolidate", e, 2, std::cerr);
  } catch (const std::exception& e) {
    return dem::cli::end_on_error(*farm, "dem-consolidate", e, 1, std::cerr);
  }
}
