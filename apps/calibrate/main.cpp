// dem-calibrate: fits the ball-ball contact parameters (E*, mu, mu_r) to a laboratory simple-shear
// curve in the study's four stages; resumable with the same --out. See --help. Under mpirun the
// trials are spread over the ranks (the output folder on a file system they all see).
#include <exception>
#include <iostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/lab/protocols/calibration.hpp>

#include "cli/calibration_command_line.hpp"
#include "cli/task_farm.hpp"

int main(int argc, char** argv) {
  std::optional<dem::cli::CalibrationCommandLine> cli;
  std::unique_ptr<dem::parallel::TaskFarm> farm;
  try {
    cli = dem::cli::parse_calibration_command_line(argc, argv, std::cout);
    if (!cli) return 0;
    farm = dem::cli::open_task_farm(argc, argv);
  } catch (const dem::InputError& e) {
    std::cerr << "dem-calibrate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-calibrate: " << e.what() << "\n";
    return 1;
  }
  try {
    std::ostringstream quiet;  // progress is the leading rank's to print
    std::ostream& log = farm->leads() ? std::cout : quiet;
    const std::string modulus = dem::lab::detail::modulus_symbol(cli->config.text("ball_ball.law"));
    dem::lab::Calibration calibration(std::move(cli->config), cli->settings, std::move(cli->lab), cli->out_dir, cli->from, log,
                                      farm.get());
    const dem::lab::CalibrationResult result = calibration.run();
    if (!farm->leads()) return 0;
    const auto& best = result.best_trial;
    std::cout << "best: " << modulus << " = " << result.best.modulus << " Pa, mu = " << result.best.friction
              << ", mu_r = " << result.best.rolling_friction << "\nshear stress RD: max " << best.stress_rd_max << " %, mean "
              << best.stress_rd_mean << " % (" << best.stress_points_skipped << " lab points skipped)";
    if (best.volumetric_points_used > 0)
      std::cout << "\nvolumetric strain RD: max " << best.volumetric_rd_max << " %, mean " << best.volumetric_rd_mean << " % ("
                << best.volumetric_points_skipped << " lab points skipped)";
    std::cout << "\n" << result.trials << " trials (" << result.new_trials << " new, " << result.trials - result.new_trials
              << " reused) in " << result.seconds << " s";
    if (farm->processes() > 1) std::cout << " on " << farm->processes() << " MPI ranks";
    std::cout << "\nresults in " << cli->out_dir.string()
              << "/: calibrated.ini (dem-simple-shear --config), comparison.csv, trials.csv, summary.json\n";
  } catch (const dem::InputError& e) {
    return dem::cli::end_on_error(*farm, "dem-calibrate", e, 2, std::cerr);
  } catch (const std::exception& e) {
    return dem::cli::end_on_error(*farm, "dem-calibrate", e, 1, std::cerr);
  }
}
