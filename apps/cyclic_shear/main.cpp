// dem-cyclic-shear: cyclic and multidirectional simple shear on the NGI ring stack: a specimen
// generated and consolidated here (or a consolidated restart, --from), then static, cyclic and
// post-cyclic stages (docs/cyclic-shear.md).
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>
#include <dem/lab/protocols/cyclic_shear.hpp>

#include "cli/cyclic_command_line.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  try {
    const auto cli = dem::cli::parse_cyclic_command_line(argc, argv, std::cout);
    if (!cli) return 0;
    dem::cli::require_one_process("dem-cyclic-shear");
    dem::lab::check_cyclic_inputs(cli->cyclic);  // before minutes of generation
    const dem::cli::ShearCommandLine& run = cli->specimen;
    dem::lab::CyclicShearTest test(run.config, cli->cyclic, run.out_dir, std::cout);
    test.record_configuration(*run.configuration);
    if (!run.from.empty()) test.load_restart(run.from);
    test.open_outputs({.replace = run.replace, .program = "dem-cyclic-shear"});
    test.run();
    test.write_summary(run.resolved_json);
    std::cout << "results in " << run.out_dir.string()
              << "/: cyclic_history.csv, cycles.csv, summary.json (figures: scripts/plot-cyclic " << run.out_dir.string() << ")\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-cyclic-shear: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-cyclic-shear: " << e.what() << "\n";
    return 1;
  }
}
