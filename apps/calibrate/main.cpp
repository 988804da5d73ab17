// dem-calibrate: fits the ball-ball contact parameters (E*, mu, mu_r) to a laboratory simple-shear
// curve in the study's four stages; resumable with the same --out. See --help.
#include <exception>
#include <iostream>

#include <dem/core/errors.hpp>
#include <dem/lab/calibration.hpp>

#include "cli/calibration_command_line.hpp"

int main(int argc, char** argv) {
  try {
    auto cli = dem::cli::parse_calibration_command_line(argc, argv, std::cout);
    if (!cli) return 0;
    dem::lab::Calibration calibration(std::move(cli->config), cli->settings, std::move(cli->lab), cli->out_dir, cli->from,
                                      std::cout);
    const dem::lab::CalibrationResult result = calibration.run();
    const auto& best = result.best_trial;
    std::cout << "best: E* = " << result.best.effective_modulus << " Pa, mu = " << result.best.friction
              << ", mu_r = " << result.best.rolling_friction << "\nshear stress RD: max " << best.stress_rd_max << " %, mean "
              << best.stress_rd_mean << " % (" << best.stress_points_skipped << " lab points skipped)";
    if (best.volumetric_points_used > 0)
      std::cout << "\nvolumetric strain RD: max " << best.volumetric_rd_max << " %, mean " << best.volumetric_rd_mean << " % ("
                << best.volumetric_points_skipped << " lab points skipped)";
    std::cout << "\n" << result.trials << " trials (" << result.new_trials << " new, " << result.trials - result.new_trials
              << " reused) in " << result.seconds << " s\nresults in " << cli->out_dir.string()
              << "/: calibrated.ini (dem-simple-shear --config), comparison.csv, trials.csv, summary.json\n";
  } catch (const dem::InputError& e) {
    std::cerr << "dem-calibrate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dem-calibrate: " << e.what() << "\n";
    return 1;
  }
}
