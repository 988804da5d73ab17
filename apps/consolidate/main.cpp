// dem-consolidate: makes the specimen and consolidates it, leaving consolidated.restart in --out,
// from which dem-simple-shear --from shears the same specimen in as many ways as wanted. Given a
// consolidated specimen (--from), it consolidates that packing again with this configuration's
// contact parameters (e.g. another E*).
#include <exception>
#include <iostream>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/lab/simple_shear.hpp>

#include "cli/shear_command_line.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  try {
    const auto cli = dem::cli::parse_shear_command_line(
        argc, argv, "dem-consolidate", "generate and consolidate a simple-shear specimen; writes consolidated.restart", std::cout);
    if (!cli) return 0;
    dem::cli::require_one_process("dem-consolidate");
    dem::lab::SimpleShearTest test(cli->config, cli->out_dir, std::cout);
    test.record_configuration(*cli->configuration);
    // A consolidated specimen is consolidated again with this configuration's contact parameters.
    if (!cli->from.empty()) test.load_restart(cli->from, dem::lab::ResumeIntent::Reconsolidate);
    if (test.stage() >= dem::lab::ShearStage::Shearing)
      throw dem::InputError("--from " + cli->from.string() + ": stage " + std::to_string(static_cast<int>(test.stage())) +
                            " (shearing or sheared): must be a restart of the generation (0), after it (1) or after the "
                            "consolidation (2); continue a shear with dem-simple-shear --from");
    test.open_outputs({.replace = cli->replace, .program = "dem-consolidate"});  // before any work
    if (test.stage() == dem::lab::ShearStage::Empty) test.generate();
    if (test.stage() == dem::lab::ShearStage::Generated) test.consolidate();
    else if (test.stage() == dem::lab::ShearStage::Consolidated) test.reconsolidate();
    test.write_summary(cli->resolved_json);
    std::cout << "consolidated specimen: " << (cli->out_dir / "consolidated.restart").string()
              << "\nshear it with: dem-simple-shear --from " << (cli->out_dir / "consolidated.restart").string() << "\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-consolidate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-consolidate: " << e.what() << "\n";
    return 1;
  }
}
