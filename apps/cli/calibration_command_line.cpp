#include "calibration_command_line.hpp"

#include <omp.h>

#include <algorithm>
#include <ostream>

#include <dem/base/input_file.hpp>
#include <dem/core/errors.hpp>

#include "common_options.hpp"

namespace po = boost::program_options;

namespace dem::cli {

std::optional<CalibrationCommandLine> parse_calibration_command_line(int argc, char** argv, std::ostream& out) {
  po::options_description opts("Options");
  add_common_options(opts, "1D, 2D or 4D: particle-size scale and the study's Table 1 values as the start",
                             "configuration file (.ini or .json; may hold a [calibration] section)", "calibration.friction_max=1");
  opts.add_options()("lab", po::value<std::string>(), "laboratory curve, CSV (format below); required")(
      "out,o", po::value<std::string>()->default_value("runs/calibration"), "output folder; run again with the same folder to resume")(
      "fit", po::value<std::string>()->default_value("emod,friction,rolling"), "parameters to fit: comma-separated emod (the law's modulus: E* of rrlinear and linear, E of the Hertz laws), friction (mu), rolling (mu_r)")(
      "from", po::value<std::string>(), "restart file of the specimen: right after generation, or consolidated with the starting E* (dem-consolidate)")(
      "parallel-trials", po::value<int>()->default_value(1), "trials run at the same time, each with threads/parallel-trials threads; results do not depend on it")(
      "strain-percent", "strain columns of the lab CSV without a _percent suffix are in % (never guessed)")(
      "eps-stress", po::value<double>(), "Pa: lab shear stresses with |value| below this are skipped by the relative difference (calibration.eps_stress, default 1000)")(
      "eps-strain", po::value<double>(), "lab volumetric strains with |value| below this are skipped (calibration.eps_strain, default 1e-4)");
  const po::variables_map vm = parse_options(argc, argv, opts);
  const io::Schema schema = lab::calibration_schema();
  if (vm.count("help")) {
    out << "dem-calibrate: fits the ball-ball contact parameters E*, mu and mu_r so that a simulated simple-shear curve\n"
           "matches a laboratory one, in the study's four stages: (1) E* from the initial slope of shear stress against\n"
           "strain, (2) mu from the peak shear stress, (3) mu_r from the peak, (4) mu and mu_r together on the mean\n"
           "relative difference of the whole curve. The specimen is generated and consolidated once, and again per E*; every\n"
           "trial shears it along the first shear direction to the lab's largest strain. With ball_ball.law = hertz-mindlin\n"
           "or hertz-dmt, Young's modulus E takes E*'s place (its bounds are calibration.effective_modulus_min/max).\n\n"
           "Usage: dem-calibrate --lab lab.csv [--preset 4D] [--config FILE] [--set key=value ...] [--out DIR]\n"
           "                     [--fit emod,friction,rolling] [--from FILE] [--threads N] [--parallel-trials N]\n"
           "       mpirun --bind-to none -n RANKS dem-calibrate ... (each round's trials spread over the ranks, --threads\n"
           "       each; --out on a file system every rank sees; trials.csv the same on any rank count but for its seconds)\n\n"
        << opts << "\nLab curve (--lab), CSV: " << lab::lab_curve_columns_help
        << "\nSpecimen: generated once (or --from), consolidated with the starting E*, mu and mu_r, and consolidated again\n"
           "at each other E* (same packing; calibration.modulus_specimen); every trial of an E* loads its specimen with its\n"
           "own mu and mu_r. History rows every min(output.every_strain, largest lab\n"
           "strain / 50). Stages 1-3 are repeated calibration.cycles times (the initial slope also depends on mu).\n"
           "\nOutputs in --out: trials.csv (one row per finished trial: stage, parameters, max/mean relative difference of\n"
           "shear stress and volumetric strain in % (-1: no volumetric strain), initial slope and peak of the model, seconds),\n"
           "calibrated.ini (the configuration with the best parameters, for dem-simple-shear --config), comparison.csv\n"
           "(lab points, lab and best-model values, relative difference in %, -1 where skipped), summary.json, specimen/\n"
           "(generated and consolidated restarts) and trials/<n>/history.csv. Relative difference: |lab - model| / |lab| on\n"
           "the lab strain points, the model interpolated onto them (docs/model.md 8).\n"
           "\nConfiguration keys (SI units; file sections are the part before the dot; the ball_ball values are the start):\n"
        << schema.help_text();
    return std::nullopt;
  }
  io::Config config = resolve_config(schema, vm);
  if (vm.count("eps-stress")) config.set("calibration.eps_stress", lab::detail::exact_text(vm["eps-stress"].as<double>()));
  if (vm.count("eps-strain")) config.set("calibration.eps_strain", lab::detail::exact_text(vm["eps-strain"].as<double>()));
  if (vm.count("print-config")) {
    out << config.to_ini();
    return std::nullopt;
  }
  lab::CalibrationSettings settings = lab::calibration_settings(config);
  lab::parse_fit_list(vm["fit"].as<std::string>(), settings);
  const int threads = lab::thread_count(config.text("engine.threads"), "engine.threads");
  settings.threads = threads > 0 ? threads : std::max(1, omp_get_max_threads());
  settings.parallel_trials = vm["parallel-trials"].as<int>();
  require(settings.parallel_trials >= 1, "--parallel-trials", settings.parallel_trials, ">= 1");
  require(vm.count("lab") > 0, "--lab", "(missing)", "the laboratory curve CSV (see --help)");
  lab::LabCurveOptions lab_options;
  lab_options.strain_percent = vm.count("strain-percent") > 0;
  require_input_file(vm["lab"].as<std::string>(), "--lab", "a CSV file of the laboratory curve", max_text_input_bytes);
  lab::LabCurve lab = lab::read_lab_curve(vm["lab"].as<std::string>(), lab_options);
  const std::filesystem::path from = restart_file(vm);
  return CalibrationCommandLine{std::move(config), settings, std::move(lab), vm["out"].as<std::string>(), from};
}

}  // namespace dem::cli
