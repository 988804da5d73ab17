#include "simple_shear_run.hpp"

#include <memory>
#include <ostream>

#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

namespace dem::cli {

void run_simple_shear(const ShearCommandLine& cli, std::ostream& log, const std::string& program, SpreadRun* spread) {
  std::unique_ptr<lab::SimpleShearTest> test;
  const auto set_up = [&] {
    if (spread) lab::require_rings_spreadable(cli.config.rings.vertical, spread->farm().processes());
    test = std::make_unique<lab::SimpleShearTest>(cli.config, spread ? spread->out_dir() : cli.out_dir,
                                                  spread ? spread->log(log) : log);
    test->record_configuration(*cli.configuration);
    if (!cli.from.empty()) test->load_restart(cli.from);
    test->open_outputs({.replace = cli.replace, .program = program});  // before any work
  };
  // Over several processes, a set-up error on any of them (the leader's output folder) stops all.
  if (spread) {
    spread->farm().together(set_up);
    spread->spread(test->world());
  } else {
    set_up();
  }
  test->run();
  test->write_summary(cli.resolved_json);
}

}  // namespace dem::cli
