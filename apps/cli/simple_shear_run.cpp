#include "simple_shear_run.hpp"

#include <ostream>

#include <dem/lab/simple_shear.hpp>

namespace dem::cli {

void run_simple_shear(const ShearCommandLine& cli, std::ostream& log, const std::string& program) {
  lab::SimpleShearTest test(cli.config, cli.out_dir, log);
  test.record_configuration(*cli.configuration);
  if (!cli.from.empty()) test.load_restart(cli.from);
  test.open_outputs({.replace = cli.replace, .program = program});  // before any work
  test.run();
  test.write_summary(cli.resolved_json);
}

}  // namespace dem::cli
