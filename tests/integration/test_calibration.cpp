// Calibration (dem-calibrate's library): the lab-vs-model comparison glue on curves small enough
// to check by hand, the batched searches on analytic functions, and the whole calibration on the
// reduced specimen of test_simple_shear.cpp (30 mm x 12 mm, 4D balls, ~180 balls): a "lab" curve
// made by the tool itself from known parameters is fitted again from a start 40 % away, and a
// second run in the same folder reuses every trial.
#include <catch2/catch.hpp>


#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/calibration.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>
#include <dem/lab/toolkit/specimen_file.hpp>

#include "support/json.hpp"
#include "support/temp_dir.hpp"

using namespace dem;
using namespace dem::lab;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using dem::testing::TempDir;

fs::path write_file(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

LabCurve lab_from(const fs::path& dir, const std::string& text, LabCurveOptions options = {}) {
  return read_lab_curve(write_file(dir / "lab.csv", text), options);
}

// The reduced specimen of test_simple_shear.cpp; trials shear it to the lab's largest strain.
io::Config small_config() {
  io::Config c(calibration_schema());
  for (const auto& [k, v] : preset_values("4D")) c.set(k, v);
  c.set("specimen.diameter", "0.03");
  c.set("specimen.height", "0.012");
  // The dense specimen of a frictionless expansion in a closed cavity, in rings held at their
  // heights (the protocol before generation.plate = servo and rings.vertical = follow): its initial
  // slope follows E* closely, which these tests of the search need (a loose 182-ball specimen
  // rearranges when it is consolidated again at another E*, and E* came back 19 % off).
  c.set("specimen.porosity", "0.37");
  c.set("generation.plate", "fixed");
  c.set("generation.friction", "frictionless");
  c.set("generation.rolling_friction", "frictionless");
  c.set("rings.vertical", "fixed");
  c.set("rings.stack_height", "0.012");
  c.set("output.every_strain", "0.002");
  c.set("output.fabric_strains", "");
  c.set("output.snapshot_strains", "");
  c.set("engine.threads", "1");
  return c;
}

}  // namespace

// ---------------------------------------------------------------- comparison glue

TEST_CASE("calibration: the model is interpolated onto the lab strains and small lab values are skipped", "[calibration]") {
  const TempDir temp("compare");
  const fs::path& dir = temp.path;
  // Lab in percent strain and kPa: strains 0, 0.01, 0.02, 0.03; stresses 0, 10, 20, 40 kPa.
  const LabCurve lab = lab_from(dir,
                                "shear_strain_percent,shear_stress_kPa,volumetric_strain\n"
                                "0,0,0\n1,10,0.00005\n2,20,-0.002\n3,40,0.004\n");
  REQUIRE(lab.size() == 4);
  CHECK(lab.shear_strain[1] == Approx(0.01).margin(1e-15));
  CHECK(lab.shear_stress[3] == Approx(40e3).margin(1e-9));
  // Model: tau = 1.1e6 * gamma up to 0.02, then 22 kPa + 0.9e6 (gamma - 0.02); sampled at other strains.
  ModelCurve model;
  model.shear_strain = {0.0, 0.005, 0.02, 0.04};
  model.shear_stress = {0.0, 5.5e3, 22e3, 40e3};
  model.volumetric_strain = {0.0, 0.0, -0.001, 0.005};
  const CurveComparison c = compare_curves(lab, model, {.eps_stress = 1000.0, .eps_strain = 1e-4});
  // Stress: point 0 skipped (0 < eps); RD = |10-11|/10 = 0.1, |20-22|/20 = 0.1, |40-31|/40 = 0.225.
  CHECK(c.stress.points_used == 3);
  CHECK(c.stress.points_skipped == 1);
  CHECK(c.stress.max_percent == Approx(22.5).margin(1e-9));
  CHECK(c.stress.mean_percent == Approx(100.0 * (0.1 + 0.1 + 0.225) / 3).margin(1e-9));
  CHECK(c.model_stress[1] == Approx(11e3).margin(1e-9));
  CHECK(c.model_stress[3] == Approx(31e3).margin(1e-9));
  CHECK(c.stress_rd_percent[0] == -1.0);
  CHECK(c.stress_rd_percent[3] == Approx(22.5).margin(1e-9));
  // Volumetric: 0 and 5e-5 are below eps_strain = 1e-4 and skipped; model at 0.02 is -0.001
  // (RD 50 %), at 0.03 it is 0.002 (RD 50 %).
  REQUIRE(c.volumetric);
  CHECK(c.volumetric->points_used == 2);
  CHECK(c.volumetric->points_skipped == 2);
  CHECK(c.volumetric->mean_percent == Approx(50.0).margin(1e-9));
  CHECK(c.volumetric_rd_percent[1] == -1.0);
  // A larger eps skips more; the initial slope and the peak on the lab points.
  CHECK(compare_curves(lab, model, {.eps_stress = 15e3, .eps_strain = 1e-4}).stress.points_used == 2);
  CHECK(slope_strain_limit(lab, 0.5) == Approx(0.02).margin(1e-15));  // 20 kPa = half of the 40 kPa peak
  CHECK(slope_strain_limit(lab, 0.1) == Approx(0.01).margin(1e-15));  // at least the second point
  // Through the origin on (0.01, 10e3), (0.02, 20e3): exactly 1e6 Pa.
  CHECK(initial_slope(lab, lab.shear_stress, 0.02) == Approx(1e6).epsilon(1e-12));
  // Model on the same points: (0.01, 11e3), (0.02, 22e3) -> 1.1e6 Pa.
  CHECK(initial_slope(lab, c.model_stress, 0.02) == Approx(1.1e6).epsilon(1e-12));
  // Points beyond the limit do not count; (0.01, 12e3), (0.02, 20e3): (120 + 400) / (1 + 4) Pa/1e-2.
  CHECK(initial_slope(lab, {0.0, 12e3, 20e3, 99e3}, 0.02) == Approx(1.04e6).epsilon(1e-12));
  CHECK(peak_value(c.model_stress) == Approx(31e3).margin(1e-9));
  // Late dilatancy: the mean over the lab points from a strain on; the model's NaN outside its range
  // is left out. Lab from 0.02: (-0.002 + 0.004) / 2; model: (-0.001 + 0.002) / 2.
  CHECK(late_mean(lab, lab.volumetric_strain, 0.02) == Approx(0.001).margin(1e-15));
  CHECK(late_mean(lab, c.model_volumetric, 0.02) == Approx(0.0005).margin(1e-15));
  CHECK(late_mean(lab, {1.0, 2.0, 3.0, std::nan("")}, 0.015) == Approx(3.0).margin(1e-15));
  CHECK(std::isnan(late_mean(lab, lab.volumetric_strain, 0.5)));  // no point that late
}

TEST_CASE("calibration: stage 3 matches the late dilatancy only when the lab curve has one", "[calibration]") {
  const TempDir temp("target");
  const fs::path& dir = temp.path;
  io::Config c(calibration_schema());
  for (const auto& [k, v] : preset_values("4D")) c.set(k, v);
  c.set("calibration.rolling_target", "dilatancy");
  const CalibrationSettings settings = calibration_settings(c);
  CHECK(settings.rolling_target == CalibrationSettings::RollingTarget::Dilatancy);
  std::ostringstream log;
  // No volumetric column: refused before any simulation, naming the key and what is allowed.
  const LabCurve no_volume = lab_from(dir, "shear_strain,shear_stress\n0,0\n0.002,12000\n0.005,25000\n0.01,50000\n0.02,80000\n");
  CHECK_THROWS_WITH(Calibration(c, settings, no_volume, dir / "a", {}, log),
                    Contains("calibration.rolling_target = dilatancy") && Contains("no volumetric strain") && Contains("peak"));
  // A volumetric strain that stays below eps_strain (1e-4) late in the curve: refused too.
  const LabCurve flat = lab_from(dir, "shear_strain,shear_stress,volumetric_strain\n0,0,0\n0.002,12000,0\n0.005,25000,0.0005\n0.01,50000,0.001\n0.02,80000,0.00005\n");
  CHECK_THROWS_WITH(Calibration(c, settings, flat, dir / "b", {}, log), Contains("late dilatancy of 5e-05"));
  CHECK_THROWS_WITH(c.set("calibration.rolling_target", "sideways"), Contains("calibration.rolling_target") && Contains("sideways"));
  // Too few points for what the stages read: one point below 30 % of the peak (the slope would be
  // any line through it), or one point in the last 20 % of the strains (the late dilatancy).
  const LabCurve two_points = lab_from(dir, "shear_strain,shear_stress\n0,0\n0.4,80000\n");
  c.set("calibration.rolling_target", "peak");
  CHECK_THROWS_WITH(Calibration(c, calibration_settings(c), two_points, dir / "c", {}, log),
                    Contains("points with 0 < shear strain <= 0.4") && Contains("= 1") && Contains(">= 2 to fit the initial slope"));
  const LabCurve one_late = lab_from(dir, "shear_strain,shear_stress,volumetric_strain\n0,0,0\n0.002,12000,0\n0.005,25000,0.001\n"
                                          "0.01,50000,0.003\n0.02,80000,0.004\n");
  c.set("calibration.rolling_target", "dilatancy");
  CHECK_THROWS_WITH(Calibration(c, calibration_settings(c), one_late, dir / "d", {}, log),
                    Contains("points with shear strain >= 0.016") && Contains(">= 2 for the late dilatancy"));
}

TEST_CASE("calibration: strain units are explicit: fraction, _percent suffix or the percent flag", "[calibration]") {
  const TempDir temp("units");
  const fs::path& dir = temp.path;
  const std::string text = "shear_strain,shear_stress,volumetric_strain\n0,0,0\n2,1000,0.5\n";
  // Never guessed to be percent: a strain above 1 without the suffix or the flag is refused.
  CHECK_THROWS_WITH(lab_from(dir, text), Contains("above 1 (100 %)") && Contains("--strain-percent"));
  const LabCurve fraction = lab_from(dir, "shear_strain,shear_stress,volumetric_strain\n0,0,0\n0.02,1000,0.005\n");
  CHECK(fraction.shear_strain[1] == 0.02);
  CHECK(fraction.volumetric_strain[1] == 0.005);
  const LabCurve percent = lab_from(dir, text, {.strain_percent = true});
  CHECK(percent.shear_strain[1] == Approx(0.02).margin(1e-15));
  CHECK(percent.volumetric_strain[1] == Approx(0.005).margin(1e-15));
  CHECK(percent.shear_stress[1] == 1000.0);  // Pa
  const LabCurve kpa = lab_from(dir, "shear_stress_kPa,shear_strain,other\n1.5,0.001,7\n");
  CHECK(kpa.shear_stress[0] == Approx(1500.0).margin(1e-9));
  CHECK_FALSE(kpa.has_volumetric());
}

// ---------------------------------------------------------------- searches

TEST_CASE("calibration: the root search brackets and converges on a monotonic function", "[calibration]") {
  // g(u) = 0.8 (u - 0.37) with a small curvature; start far away, batch of 2.
  auto g = [](double u) { return 0.8 * (u - 0.37) + 0.1 * (u - 0.37) * (u - 0.37); };
  RootSearch search({.start = 1.0, .lower = 0.0, .upper = 2.0, .first_step = 0.3, .max_step = 0.5, .slope_guess = 1.0,
                     .tolerance = 1e-4, .u_tolerance = 1e-6, .batch_size = 2, .max_evaluations = 20});
  for (auto us = search.propose(); !us.empty(); us = search.propose()) {
    CHECK(us.size() <= 2);
    std::vector<double> gs;
    for (double u : us) gs.push_back(g(u));
    search.tell(us, gs);
  }
  CHECK(search.best() == Approx(0.37).margin(2e-4));
  CHECK(search.evaluations() <= 10);
  CHECK_THAT(search.reason(), Contains("converged"));
  // A root beyond the bound: the search stops at the bound instead of running on.
  RootSearch bounded({.start = 0.5, .lower = 0.0, .upper = 1.0, .first_step = 0.2, .max_step = 0.5, .slope_guess = 1.0,
                      .tolerance = 1e-3, .u_tolerance = 1e-6, .batch_size = 1, .max_evaluations = 10});
  for (auto us = bounded.propose(); !us.empty(); us = bounded.propose()) bounded.tell(us, {us[0] - 3.0});
  CHECK(bounded.best() == 1.0);
  CHECK(bounded.evaluations() <= 4);
}

TEST_CASE("calibration: the pattern search walks downhill and shrinks its step", "[calibration]") {
  auto f = [](const std::vector<double>& x) { return std::pow(x[0] - 0.42, 2) + 2 * std::pow(x[1] - 0.15, 2); };
  PatternSearch search({.start = {0.5, 0.3}, .start_value = f({0.5, 0.3}), .lower = {0, 0}, .upper = {1, 1},
                        .step = {0.05, 0.05}, .min_step = {0.005, 0.005}, .shrink = 0.5, .max_evaluations = 60});
  for (auto xs = search.propose(); !xs.empty(); xs = search.propose()) {
    std::vector<double> fs_;
    for (const auto& x : xs) fs_.push_back(f(x));
    search.tell(xs, fs_);
  }
  CHECK(search.best()[0] == Approx(0.42).margin(0.01));
  CHECK(search.best()[1] == Approx(0.15).margin(0.01));
}

// ---------------------------------------------------------------- whole calibration

namespace {

// A lab curve made by the tool from `truth`: the calibration's own specimen (same start
// configuration, so the same generated state), sheared with the true parameters, every second
// history row written as lab points.
fs::path make_lab_curve(const io::Config& start, const ContactFit& truth, double strain, const fs::path& dir) {
  std::ostringstream log;
  SimpleShearConfig config = simple_shear_config(start);
  config.output.every_strain = strain / 100;
  ShearTrials trials(config, dir / "maker", {}, true, log);
  trials.prepare({truth.modulus}, 1, 1);
  const ModelCurve curve = trials.shear(truth, strain, 1, 1);
  io::CsvTable lab({"shear_strain", "shear_stress", "volumetric_strain"});
  for (std::size_t k = 0; k < curve.shear_strain.size() && curve.shear_strain[k] <= strain; k += 2)
    lab.add_row({curve.shear_strain[k], curve.shear_stress[k], curve.volumetric_strain[k]});
  lab.save(dir / "lab.csv");
  return dir / "lab.csv";
}

}  // namespace

TEST_CASE("calibration: a trial shears its own E*'s consolidated specimen, loaded by the toolkit's parts", "[calibration]") {
  const TempDir temp("trial");
  std::ostringstream log;
  const SimpleShearConfig config = simple_shear_config(small_config());
  const double start = config.ball_ball.stiffness(), other = 1.5 * start;
  ShearTrials trials(config, temp.path, {}, true, log);
  trials.prepare({start, other}, 1, 1);
  const fs::path generated = temp.path / "specimen" / "generated" / "generated.restart";
  const fs::path consolidated = temp.path / "specimen" / ("E_" + lab::detail::exact_text(other)) / "consolidated.restart";
  CHECK(restart_stage(generated) == ShearStage::Generated);
  CHECK(restart_stage(consolidated) == ShearStage::Consolidated);

  // The trial's first row is the state its specimen was consolidated to (the last row the
  // specimen's own run wrote, after consolidating the starting E*'s specimen again at `other`),
  // measured again after the restart file has been loaded: the same bits.
  const ContactFit fit{other, config.ball_ball.friction(), config.ball_ball.rolling_friction()};
  const ModelCurve curve = trials.shear(fit, 0.01, 1, 1);
  const io::CsvData trial = io::read_csv(trials.trial_dir(1) / "history.csv");
  const io::CsvData made = io::read_csv(consolidated.parent_path() / "history.csv", io::Missing::Allowed);
  REQUIRE(made.rows.size() == 2);  // the starting E*'s consolidation row, then this E*'s
  for (const char* column : {"time", "shear_stress", "vertical_stress", "height", "lateral_stress"})
    CHECK(trial.rows.front()[trial.column(column)] == made.rows.back()[made.column(column)]);
  CHECK(made.rows.front()[made.column("height")] != made.rows.back()[made.column("height")]);
  CHECK(trial.rows.front()[trial.column("shear_strain")] == 0.0);
  // Then a row every output.every_strain to the trial's strain, none with a ball outside.
  CHECK(trial.rows.size() == curve.shear_strain.size());
  CHECK(trial.rows.size() >= static_cast<std::size_t>(0.01 / config.output.every_strain));
  CHECK(curve.shear_strain.back() >= 0.01 * (1 - 1e-12));
  for (const auto& row : trial.rows) CHECK(row[trial.column("balls_outside")] == 0.0);

  // A world of the same configuration takes a consolidated specimen only.
  World world(world_settings(config));
  const ShearCell cell = build_shear_cell(world, shear_cell_spec(config));
  set_contact_laws(world, config, config.ball_ball.friction(), config.ball_ball.rolling_friction(), false);
  CHECK_THROWS_WITH(load_consolidated_specimen(generated, world, cell, config, log),
                    Contains(generated.string()) && Contains("stage") && Contains("consolidated"));
  CHECK_THROWS_WITH(restart_stage(consolidated.parent_path()), Contains("is a folder") && Contains("consolidated.restart"));
  CHECK_THROWS_WITH(restart_stage(consolidated.parent_path() / "history.csv"), Contains("not a libdem restart file"));
}

TEST_CASE("calibration: E* and mu are recovered from a curve made with known values, and a rerun reuses every trial",
          "[calibration]") {
  const TempDir temp("identify");
  const ContactFit truth{1.2e7, 0.5, 0.4};
  io::Config start = small_config();
  start.set("ball_ball.effective_modulus", "1.68e7");  // +40 %
  start.set("ball_ball.friction", "0.3");              // -40 %
  start.set("calibration.tolerance", "0.005");
  start.set("calibration.cycles", "3");
  // The volumetric strain of 182 balls to 4 % strain is mostly noise (4-1000 % relative difference
  // between nearby trials): the whole-curve stage weighs the shear stress alone.
  start.set("calibration.volumetric_weight", "0");
  CalibrationSettings settings = calibration_settings(start);
  parse_fit_list("emod,friction", settings);

  // On 182 balls the staged search can stop away from the truth: stage 1 fits the initial slope
  // at the starting mu, a stiffer E* makes up for the low friction and the peak then agrees with
  // that mu (one packing: E* +50 %, mu -41 %, shear-stress RD 4.3 %); or mu ends 11-13 % off at
  // an RD below 1 %. Which packings do so follows the last bits of their trajectories: of seeds
  // 1-3 under two orders of the particles in memory, one per order; the others came within 4 %.
  // Two of three packings are held to 10 %.
  std::vector<CalibrationResult> runs;
  std::vector<fs::path> labs;
  int recovered = 0;
  std::ostringstream log;
  for (const int seed : {1, 2, 3}) {
    start.set("specimen.seed", std::to_string(seed));
    const fs::path dir = temp.path / ("seed" + std::to_string(seed));
    labs.push_back(make_lab_curve(start, truth, 0.04, dir));
    Calibration calibration(start, settings, read_lab_curve(labs.back()), dir / "cal", {}, log);
    runs.push_back(calibration.run());
    const CalibrationResult& r = runs.back();
    log << "seed " << seed << ": E* " << r.best.modulus << ", mu " << r.best.friction << ", RD "
        << r.best_trial.stress_rd_mean << " %\n";
    if (std::abs(r.best.modulus / truth.modulus - 1) <= 0.10 && std::abs(r.best.friction / truth.friction - 1) <= 0.10) {
      ++recovered;
      CHECK(r.best_trial.stress_rd_mean < 3.0);
    }
  }
  INFO(log.str());
  CHECK(recovered >= 2);

  // The first packing's calibration, whatever it found, is the one a rerun must reproduce.
  start.set("specimen.seed", "1");
  const fs::path& lab_file = labs.front();
  const fs::path out = temp.path / "seed1" / "cal";
  const CalibrationResult& first = runs.front();
  CHECK(first.new_trials <= first.trials);
  for (const char* f : {"trials.csv", "calibrated.ini", "comparison.csv", "summary.json", "setup.txt"}) CHECK(fs::exists(out / f));

  // calibrated.ini is a plain simple-shear configuration with the best values.
  io::Config shear(simple_shear_schema());
  shear.load_file(out / "calibrated.ini");
  CHECK(shear.real("ball_ball.effective_modulus") == first.best.modulus);
  CHECK(shear.real("ball_ball.friction") == first.best.friction);
  CHECK(shear.real("specimen.diameter") == 0.03);
  const io::CsvData trials = io::read_csv(out / "trials.csv");
  CHECK(trials.rows.size() == static_cast<std::size_t>(first.new_trials));
  const io::CsvData comparison = io::read_csv(out / "comparison.csv");
  CHECK(comparison.rows.size() == read_lab_curve(lab_file).size());
  const auto summary = dem::testing::load_json(out / "summary.json");
  CHECK(summary.at("best").at("friction").get<double>() == first.best.friction);

  // A calibration killed after some trials: its trials.csv holds only the first ones, and the
  // later trials never ran (no folder). The search asks for the same parameters again, reuses
  // those and runs the rest. The columns are read by name: here in reverse order, as a
  // spreadsheet may have saved them.
  const std::size_t kept = trials.rows.size() / 2;
  io::CsvTable partial(std::vector<std::string>(trials.columns.rbegin(), trials.columns.rend()));
  for (std::size_t r = 0; r < kept; ++r) partial.add_row(std::vector<double>(trials.rows[r].rbegin(), trials.rows[r].rend()));
  partial.save(out / "trials.csv");
  for (const auto& folder : fs::directory_iterator(out / "trials"))
    if (std::stoul(folder.path().filename().string()) > kept) fs::remove_all(folder.path());
  std::ostringstream log2;
  {
    Calibration resumed(start, settings, read_lab_curve(lab_file), out, {}, log2);
    const CalibrationResult second = resumed.run();
    CHECK(second.new_trials == first.new_trials - static_cast<int>(kept));
    CHECK(second.best == first.best);
    CHECK(second.best_trial.stress_rd_mean == first.best_trial.stress_rd_mean);
  }
  // Complete: nothing new at all.
  std::ostringstream log3;
  {  // (ended before the next calibration: one at a time holds the folder)
    Calibration again(start, settings, read_lab_curve(lab_file), out, {}, log3);
    const CalibrationResult third = again.run();
    CHECK(third.new_trials == 0);
    CHECK(third.trials == first.trials);
    CHECK(third.best == first.best);
    const io::CsvData final_trials = io::read_csv(out / "trials.csv");
    REQUIRE(final_trials.rows.size() == trials.rows.size());
    for (std::size_t r = 0; r < trials.rows.size(); ++r)  // all but the seconds of the re-run trials
      for (std::size_t c = 0; c + 1 < trials.columns.size(); ++c) CHECK(final_trials.rows[r][c] == trials.rows[r][c]);
  }

  // Another lab curve in the same folder is refused rather than mixed with these trials.
  const fs::path other = temp.path / "other.csv";
  std::ofstream(other) << "shear_strain,shear_stress\n0,0\n0.002,12000\n0.005,25000\n0.01,50000\n0.02,80000\n";
  CHECK_THROWS_WITH(Calibration(start, settings, read_lab_curve(other), out, {}, log3), Contains("another calibration set-up"));
}

TEST_CASE("calibration: with Hertz-Mindlin contacts, Young's modulus is the fitted modulus and is recovered",
          "[calibration][hertz]") {
  // The law's stiffness role is what stage 1 fits: E for the Hertz laws. A curve made with
  // E = 5e8 Pa, the search started 40 % above it, friction and rolling at their true values:
  // the initial slope grows monotonically with E (about as E^(2/3) for Hertz contacts at a fixed
  // load), so the root search finds it; 10 %, as the linear law's identification on this specimen.
  const TempDir temp("hertz");
  io::Config start = small_config();
  start.set("ball_ball.law", "hertz-mindlin");
  start.set("ball_ball.restitution", "1");
  const ContactFit truth{5e8, start.real("ball_ball.friction"), start.real("ball_ball.rolling_friction")};
  start.set("ball_ball.youngs_modulus", "7e8");  // +40 %
  start.set("calibration.tolerance", "0.005");
  CalibrationSettings settings = calibration_settings(start);
  parse_fit_list("emod", settings);
  const fs::path lab = make_lab_curve(start, truth, 0.02, temp.path);
  std::ostringstream log;
  Calibration calibration(start, settings, read_lab_curve(lab), temp.path / "cal", {}, log);
  const CalibrationResult result = calibration.run();
  INFO(log.str());
  CHECK(result.best.modulus == Approx(truth.modulus).epsilon(0.10));
  CHECK_THAT(log.str(), Contains("E = ") && !Contains("E* = "));
  // The files name it by its key: trials.csv's column, calibrated.ini and summary.json.
  const io::CsvData trials = io::read_csv(temp.path / "cal" / "trials.csv");
  CHECK(trials.column("youngs_modulus") == 2);
  io::Config shear(simple_shear_schema());
  shear.load_file(temp.path / "cal" / "calibrated.ini");
  CHECK(shear.text("ball_ball.law") == "hertz-mindlin");
  CHECK(shear.real("ball_ball.youngs_modulus") == result.best.modulus);
  CHECK(dem::testing::load_json(temp.path / "cal" / "summary.json").at("best").at("youngs_modulus_Pa").get<double>() ==
        result.best.modulus);
}

TEST_CASE("calibration: parallel trials give the same trials as serial ones, from a consolidated restart", "[calibration]") {
  const TempDir temp("parallel");
  const fs::path& dir = temp.path;
  const ContactFit truth{1.2e7, 0.5, 0.4};
  io::Config start = small_config();
  start.set("ball_ball.friction", "0.35");
  start.set("calibration.cycles", "1");
  start.set("calibration.max_trials_per_stage", "4");
  const fs::path lab_file = make_lab_curve(start, truth, 0.03, dir);
  // The lab maker's consolidated specimen has the starting E*: fitting mu alone needs no other.
  fs::path consolidated;
  for (const auto& entry : fs::directory_iterator(dir / "maker" / "specimen"))
    if (entry.path().filename().string().rfind("E_", 0) == 0) consolidated = entry.path() / "consolidated.restart";
  REQUIRE(fs::exists(consolidated));
  CalibrationSettings settings = calibration_settings(start);
  std::ostringstream log;
  // A new packing per E* needs the generated state, which a consolidated restart no longer holds.
  settings.modulus_specimen = ModulusSpecimen::Generated;
  CHECK_THROWS_WITH(Calibration(start, settings, read_lab_curve(lab_file), dir / "refused", consolidated, log),
                    Contains("--from") && Contains("E* is fitted") && Contains("modulus_specimen"));
  settings.modulus_specimen = ModulusSpecimen::Reconsolidated;

  parse_fit_list("friction", settings);
  std::vector<io::CsvData> runs;
  std::vector<ContactFit> best;
  for (int parallel : {1, 2}) {
    settings.parallel_trials = parallel;
    settings.threads = parallel;
    const fs::path out = dir / ("run" + std::to_string(parallel));
    std::ostringstream run_log;
    Calibration calibration(start, settings, read_lab_curve(lab_file), out, consolidated, run_log);
    const CalibrationResult result = calibration.run();
    CHECK(result.new_trials >= 4);
    CHECK_FALSE(fs::exists(out / "specimen" / "generated"));  // nothing generated or consolidated
    runs.push_back(io::read_csv(out / "trials.csv"));
    best.push_back(result.best);
    // Each progress line names its trial by trials.csv's number, with that trial's friction (two
    // trials at a time finish out of number order: a count in place of the number misnamed them).
    const io::CsvData& rows = runs.back();
    const std::regex progress_line(R"(trial (\d+) \(\d+ of at most \d+\), stage [^:]*: [^|]*mu = ([0-9.e+-]+))");
    const std::string text = run_log.str();
    int lines = 0;
    for (std::sregex_iterator m(text.begin(), text.end(), progress_line), end; m != end; ++m, ++lines) {
      const auto number = static_cast<std::size_t>(std::stoul((*m)[1].str()));
      REQUIRE(number >= 1);
      REQUIRE(number <= rows.rows.size());
      CHECK(std::stod((*m)[2].str()) == Approx(rows.rows[number - 1][rows.column("friction")]).epsilon(1e-3));
    }
    CHECK(lines >= result.new_trials);
    log << text;
  }
  INFO(log.str());
  CHECK(best[0] == best[1]);
  REQUIRE(runs[0].rows.size() == runs[1].rows.size());
  const std::size_t seconds = runs[0].column("seconds");
  for (std::size_t r = 0; r < runs[0].rows.size(); ++r)
    for (std::size_t c = 0; c < runs[0].columns.size(); ++c)
      if (c != seconds) CHECK(runs[0].rows[r][c] == runs[1].rows[r][c]);
  CHECK(best[0].friction == Approx(truth.friction).epsilon(0.10));
}

TEST_CASE("calibration: E*, mu and mu_r are recovered together from 40 % away on the 4D specimen",
          "[calibration]") {
  // The whole 4D preset specimen (1,712 balls). The lab curve is made the way the calibration
  // makes its trials: the specimen consolidated at the starting E*, consolidated again at the
  // true E* (calibration.modulus_specimen = reconsolidated), sheared with the true mu and mu_r to
  // 20 %. Starting 40 % away on all three, stages 1-3 (three cycles) reach E* 1.228e7, mu 0.478,
  // mu_r 0.453 and the stage-4 polish keeps them: +2.3 %, -4.4 %, +13.3 %, shear-stress RD 0.32 %,
  // 34 trials, about 2 min on 2 cores. With a new packing per E* (modulus_specimen = generated)
  // the same run cannot get there: E* lands 0.5 % off, and the other packing changes the curve
  // more than a 20 % change of mu_r does on 1,712 balls. With the study's rule for stage 3 (the
  // peak again) mu_r stays where it started. The tolerance is the issue's 10 % on E* and mu; mu
  // and mu_r trade against each other, and another trajectory of the same specimen (the particles
  // stored in another cell order, which moves the last bits of every force) ended at -1.9 %,
  // +2.8 %, -6.0 %, RD 0.42 %: mu_r, weaker on the curve than the packing's own noise, is held to 20 %.
  const TempDir temp("joint");
  const fs::path& dir = temp.path;
  const ContactFit truth{1.2e7, 0.5, 0.4};
  io::Config start(calibration_schema());
  for (const auto& [k, v] : preset_values("4D")) start.set(k, v);
  // The dense specimen and fixed rings the numbers above were measured on (see small_config).
  start.set("specimen.porosity", "0.37");
  start.set("generation.plate", "fixed");
  start.set("generation.friction", "frictionless");
  start.set("generation.rolling_friction", "frictionless");
  start.set("rings.vertical", "fixed");
  start.set("rings.stack_height", "0.022");
  start.set("output.fabric_strains", "");
  start.set("output.snapshot_strains", "");
  start.set("engine.threads", "2");
  start.set("ball_ball.effective_modulus", "1.68e7");  // +40 %
  start.set("ball_ball.friction", "0.3");               // -40 %
  start.set("ball_ball.rolling_friction", "0.24");      // -40 %
  const fs::path lab_file = make_lab_curve(start, truth, 0.2, dir);
  const fs::path consolidated = dir / "maker" / "specimen" / "E_16800000" / "consolidated.restart";
  REQUIRE(fs::exists(consolidated));

  CalibrationSettings settings = calibration_settings(start);
  settings.threads = 2;
  settings.parallel_trials = 2;
  std::ostringstream log;
  Calibration calibration(start, settings, read_lab_curve(lab_file), dir / "cal", consolidated, log);
  const CalibrationResult result = calibration.run();
  INFO(log.str());
  CHECK(result.best.modulus == Approx(truth.modulus).epsilon(0.10));
  CHECK(result.best.friction == Approx(truth.friction).epsilon(0.10));
  CHECK(result.best.rolling_friction == Approx(truth.rolling_friction).epsilon(0.20));
  CHECK(result.best_trial.stress_rd_mean < 3.0);
}
