// Calibration of the ball-ball contact parameters (E*, mu, mu_r) against a laboratory
// simple-shear curve, in the study's four stages: (1) E* from the initial slope of shear stress
// against strain, (2) mu from the peak, (3) mu_r from the peak (the study) or from the late
// dilatancy (the default when the lab curve has volumetric strain), (4) a joint polish of mu and mu_r
// on the mean relative difference of the whole curve (docs/model.md 8). Stages 1-3 are 1-D root
// searches on a signed mismatch, stage 4 a compass search (RootSearch, PatternSearch). Stages 1-3
// run `cycles` times (default 3, the study did one by hand): over the first per cent of strain a
// granular specimen's stress depends on mu too, so E* fitted with a wrong mu is biased, and the
// next pass corrects it; a pass that changes nothing ends the cycles. "Initial slope" is a least-
// squares slope through the origin on the lab points up to a fraction of the lab peak, "peak" the
// largest stress on the lab points, the model being interpolated onto the lab strains.
//
// One specimen for all trials: it is generated once (or taken from --from) and consolidated with
// the starting E*, mu and mu_r of the configuration; every trial loads a consolidated restart with
// its own contact parameters (the restart holds state, the configuration the laws) and shears it
// along the first shear direction to the lab's largest strain, as a script over the lab toolkit's
// parts (lab/toolkit/specimen_file.hpp, lab/toolkit/shear_leg.hpp, lab/toolkit/history_log.hpp). Rule for E*: a consolidated
// specimen is only reused for trials of the same E*, because E* sets the stiffness of the
// contacts that carry the consolidation stress. A new E* consolidates the starting E*'s specimen
// again at the new stiffness (SimpleShearTest::reconsolidate: same packing, other overlaps, a new
// time step), so that nearby E* give nearby curves; calibration.modulus_specimen = generated
// consolidates the generated state afresh instead (a new packing per E*, which on a small specimen
// changes the curve more than mu_r does). Each E*'s specimen is kept for every later trial with it,
// so stages 2-4, which keep E* fixed, consolidate nothing.
// A trial writes a history row every min(output.every_strain, largest lab strain / 50).
//
// Resumable and deterministic: trials.csv holds every finished trial, keyed on the exact
// parameter values (17 significant digits), and each trial's folder its own row (result.csv); a
// calibration started again with the same --out reuses them, and because the searches decide only on whole batches, the same trials come back
// in the same order whatever --parallel-trials is. setup.txt guards against resuming with another
// lab file or configuration.
//
// Over MPI ranks (a parallel::TaskFarm of several processes): every rank runs the same searches;
// a batch's trials and the specimens of its E* are spread over the ranks, and every rank gets every
// result, so all take the same next step. The output folder must be on a file system all ranks
// see (they load the specimens' restart files); the leading rank writes the calibration's own
// files (setup.txt, trials.csv, comparison.csv, calibrated.ini, summary.json).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/io/output_folder.hpp>
#include <dem/lab/toolkit/lab_curve.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>
#include <dem/parallel/task_farm.hpp>

namespace dem::lab {

/// The parameters a calibration fits (ball-ball contacts): the law's modulus (its stiffness role,
/// core/law_registry.hpp: E* of rrlinear and linear, Young's modulus E of the Hertz laws), mu, mu_r.
struct ContactFit {
  double modulus = 0.0;            // Pa, E* or E (modulus_key())
  double friction = 0.0;           // -, mu
  double rolling_friction = 0.0;   // -, mu_r
  friend bool operator==(const ContactFit&, const ContactFit&) = default;
};

// ---------------------------------------------------------------- searches
// The searches of the calibration, free of any simulation so that tests can drive them with
// analytic functions: a 1-D root search for stages 1-3 (make one curve feature of the model
// equal the lab's) and a compass (pattern) search for stage 4 (polish mu and mu_r on the whole
// curve).
//
// Both work in rounds: propose() returns a batch of points, the caller evaluates all of them (in
// any order, in parallel or not) and passes the values to tell(), and only then does the search
// decide. The batch depends only on the values told so far, never on how the caller ran it, so a
// calibration gives the same trials with 1 or 8 parallel workers, and a resumed calibration that
// reads the values back from trials.csv proposes the same points again.
//
// Why these: a DEM response is noisy (a slightly different parameter gives a different particle
// trajectory), has no useful derivatives, and each evaluation costs minutes to hours; bracketing
// secant steps and a coarse compass search are robust to noise and need few evaluations, where
// gradient or surrogate methods would chase the noise.

/// Finds u in [lower, upper] with g(u) = 0 for a g that increases with u (up to noise): secant
/// steps from the best known points while no sign change is known, then regula falsi inside the
/// bracket, kept at least 10 % of the bracket away from its ends so that it always shrinks.
class RootSearch {
 public:
  struct Settings {
    double start = 0.0;         // first point, u
    double lower = 0.0;         // bounds of u
    double upper = 1.0;
    double first_step = 0.1;    // spacing of the first batch around start (batch_size > 1), in u
    double max_step = 1.0;      // largest move of an extrapolating step, in u
    double slope_guess = 1.0;   // dg/du assumed while fewer than two usable points are known, > 0
    double tolerance = 0.02;    // |g| <= tolerance: converged
    double u_tolerance = 1e-3;  // bracket narrower than this: converged, in u
    int batch_size = 1;         // points per round, >= 1
    int max_evaluations = 8;    // points proposed in all rounds together, >= 0
  };
  /// InputError for inconsistent settings (bounds, steps, sizes).
  explicit RootSearch(Settings settings);

  /// Adds a point evaluated elsewhere (e.g. in an earlier stage); it does not count as an evaluation.
  void seed(double u, double g);
  /// The next batch (at most batch_size points, within the remaining evaluations), in u; empty
  /// when the search has finished.
  std::vector<double> propose();
  /// The values g at the points of the last batch, in its order.
  void tell(const std::vector<double>& u, const std::vector<double>& g);

  bool done() const { return done_; }
  const std::string& reason() const { return reason_; }  // why it finished
  int evaluations() const { return evaluations_; }
  /// The known point with the smallest |g| (the first in u on ties). InputError if none is known.
  double best() const;
  double best_value() const;

 private:
  struct Point {
    double u, g;
  };
  std::vector<double> candidates() const;
  void check_done();
  void finish(const std::string& why);

  Settings s_;
  std::vector<Point> points_;  // sorted by u
  int evaluations_ = 0;
  bool done_ = false;
  std::string reason_;
};

/// Compass search minimising f over a box of up to a few dimensions: each round evaluates
/// centre +- step along every axis; the best point of the round becomes the centre if it is
/// lower, else every step is halved. Points evaluated before (the start included) are not
/// proposed again: they were not lower than the centre then, and the centre only gets lower.
/// Ends when the steps are below min_step or the budget is used.
class PatternSearch {
 public:
  struct Settings {
    std::vector<double> start;            // centre, one value per dimension
    double start_value = 0.0;             // f(start), known from earlier stages
    std::vector<double> lower, upper;     // bounds per dimension
    std::vector<double> step;             // initial step per dimension, > 0
    std::vector<double> min_step;         // per dimension, > 0
    double shrink = 0.5;                  // step factor after a round without improvement, in (0, 1)
    int max_evaluations = 8;              // >= 0
  };
  explicit PatternSearch(Settings settings);

  std::vector<std::vector<double>> propose();
  void tell(const std::vector<std::vector<double>>& x, const std::vector<double>& f);

  bool done() const { return done_; }
  const std::string& reason() const { return reason_; }
  int evaluations() const { return evaluations_; }
  const std::vector<double>& best() const { return centre_; }
  double best_value() const { return centre_value_; }

 private:
  bool shrink();  // halves the steps; false (and done) once they are all below min_step
  void finish(const std::string& why);

  Settings s_;
  std::vector<double> centre_, step_;
  std::vector<std::vector<double>> known_;  // start and every point told
  double centre_value_ = 0.0;
  int evaluations_ = 0;
  bool done_ = false;
  std::string reason_;
};

// ---------------------------------------------------------------- settings

/// Search settings (section "calibration" of the configuration, plus command-line choices).
/// How the specimen of an E* other than the starting one is made: `Reconsolidated` (default)
/// consolidates the starting E*'s specimen again at the new E* (same packing, other overlaps), so
/// that nearby E* give nearby curves; `Generated` consolidates the generated state afresh at each
/// E*, as a new specimen per E* (the packing then differs from one E* to the next).
enum class ModulusSpecimen { Reconsolidated, Generated };

struct CalibrationSettings {
  bool fit_modulus = true, fit_friction = true, fit_rolling = true;
  double effective_modulus_min = 1e6, effective_modulus_max = 1e10;  // Pa, bounds of the fitted modulus (E* or E)
  double friction_min = 0.01, friction_max = 2.0;
  double rolling_friction_min = 0.0, rolling_friction_max = 1.0;
  int max_trials_per_stage = 8;
  int cycles = 3;                     // passes of stages 1-3 before stage 4
  int batch_size = 2;                 // trials per round of a search (independent of parallel_trials)
  double tolerance = 0.01;            // -, relative slope or peak mismatch that ends stages 1-3
  double slope_stress_fraction = 0.3; // -, initial slope fitted up to this fraction of the lab peak
  double polish_step = 0.1;           // -, first step of stage 4, relative to mu and mu_r
  double polish_min_step = 0.02;      // -, stage 4 ends below this relative step
  double volumetric_weight = 0.2;     // -, weight of the volumetric mean RD in the stage-4 objective
  /// What stage 3 matches with mu_r: the peak shear stress (the study), or the late dilatancy
  /// (mean volumetric strain over the last part of the lab's strain range). Auto: dilatancy when
  /// the lab curve has volumetric strain. Matching the peak with mu and then again with mu_r
  /// leaves mu_r where it started (stage 2 has already matched the peak); the dilatancy is a
  /// second, independent feature of the curve.
  enum class RollingTarget { Auto, Peak, Dilatancy } rolling_target = RollingTarget::Auto;
  double dilatancy_from = 0.8;        // -, late dilatancy averaged from this fraction of the largest lab strain
  ModulusSpecimen modulus_specimen = ModulusSpecimen::Reconsolidated;
  ComparisonOptions comparison;       // eps of the relative difference
  int threads = 1;                    // OpenMP threads in all
  int parallel_trials = 1;            // trials run at the same time (threads / parallel_trials each)
};

/// The simple-shear schema plus the calibration keys (section "calibration").
io::Schema calibration_schema();
/// Settings from a configuration of calibration_schema(); fit flags, threads and parallel
/// trials are left at their defaults (command-line choices).
CalibrationSettings calibration_settings(const io::Config& config);
/// Parses "emod,friction,rolling" (any non-empty subset, any order); InputError otherwise.
void parse_fit_list(const std::string& list, CalibrationSettings& settings);
/// The simple-shear keys of `config` (a calibration_schema() configuration) as a
/// simple_shear_schema() configuration with the ball-ball parameters of `fit`: what
/// dem-simple-shear --config reads.
io::Config shear_config_with(const io::Config& config, const ContactFit& fit);

/// One finished trial, as in trials.csv.
struct TrialResult {
  int trial = 0;               // number, also the folder trials/<number>
  int stage = 0;               // 1-4, the stage that first asked for it (0: made outside a search)
  ContactFit fit;
  double stress_rd_max = 0, stress_rd_mean = 0;          // %, shear stress
  double volumetric_rd_max = -1, volumetric_rd_mean = -1; // %, volumetric strain; -1 without one
  double stress_points_used = 0, stress_points_skipped = 0;
  double volumetric_points_used = 0, volumetric_points_skipped = 0;
  double model_slope = 0;      // Pa, initial slope of the model on the lab points
  double model_peak = 0;       // Pa, peak shear stress of the model on the lab points
  double model_dilatancy = 0;  // -, late dilatancy of the model on the lab points (0 without lab volumetric strain)
  double seconds = 0;          // s, wall clock of the trial (with its consolidation, if it needed one)
};

/// The specimen and its shears, without any search: generates (or takes from `from`) the
/// specimen once, has one consolidated specimen per E* (see ModulusSpecimen), and shears copies
/// of it. All files live in
/// `out_dir` (specimen/, trials/<number>/). Tests use it to make a lab curve from known parameters.
class ShearTrials {
 public:
  /// `base`: the simple-shear configuration (its ball-ball values are the starting ones, used
  /// for generation and consolidation; its output.every_strain is the history interval of the
  /// trials). `from`: empty, or a restart after generation or consolidation (InputError otherwise,
  /// for a consolidated one when `fit_modulus` with the Generated rule, or for one whose folder
  /// lacks its history.csv when `fit_modulus`: the other E*'s specimens continue it); a
  /// consolidated one is the specimen of the starting E*.
  /// `farm`: the processes that share the specimens and trials; nullptr for this process alone.
  ShearTrials(SimpleShearConfig base, std::filesystem::path out_dir, std::filesystem::path from, bool fit_modulus,
              std::ostream& log, ModulusSpecimen rule = ModulusSpecimen::Reconsolidated, parallel::TaskFarm* farm = nullptr);
  ~ShearTrials();
  ShearTrials(const ShearTrials&) = delete;
  ShearTrials& operator=(const ShearTrials&) = delete;

  /// Makes sure a consolidated specimen exists for each E* (Pa), `parallel` at a time on each
  /// process with `threads` OpenMP threads each. Returns the wall-clock seconds per E*, 0 for one
  /// that existed. Every process of the farm calls it.
  std::vector<double> prepare(const std::vector<double>& moduli, int parallel, int threads);
  /// Shears the consolidated specimen of fit.effective_modulus (prepared before) with `fit` to
  /// shear strain `strain` in trials/<number>/. Its history.csv has a row for the consolidated
  /// specimen, then one every output.every_strain of the base configuration and one at the end:
  /// time, shear_strain, shear_stress, vertical_stress, height, volumetric_strain, lateral_stress
  /// and balls_outside, as dem-simple-shear measures them. Returns the model curve; the folder
  /// keeps history.csv and log.txt (and the Calibration adds result.csv, the trial's row of
  /// trials.csv). Runs on the process that calls it alone.
  ModelCurve shear(const ContactFit& fit, double strain, int number, int threads) const;
  /// The history of a finished trial, or nullopt if its folder has none.
  std::optional<ModelCurve> stored_curve(int number) const;
  /// Trial `number`'s folder: trials/<number, four digits>.
  std::filesystem::path trial_dir(int number) const;

  const std::filesystem::path& out_dir() const { return out_dir_; }
  parallel::TaskFarm& farm() const { return *farm_; }

 private:
  std::filesystem::path specimen_dir(double modulus) const;
  std::filesystem::path specimen_restart(double modulus) const;  // consolidated restart of this E*
  void generate_once(int threads);
  void consolidate_specimen(double modulus, int threads);  // specimen_dir(modulus), per rule_
  SimpleShearConfig config_for(const ContactFit& fit, int threads) const;

  SimpleShearConfig base_;
  std::filesystem::path out_dir_;
  std::ostream& log_;
  ModulusSpecimen rule_;
  std::unique_ptr<parallel::LocalFarm> own_farm_;  // when given none
  parallel::TaskFarm* farm_;
  std::filesystem::path generated_restart_, generated_files_;  // generated state and its folder
  std::filesystem::path given_consolidated_;                    // --from after consolidation
};

struct CalibrationResult {
  ContactFit best;
  TrialResult best_trial;
  int trials = 0;         // trials the searches asked for
  int new_trials = 0;     // of them run now (the others came from trials.csv)
  double seconds = 0;     // s, wall clock of this run
  std::vector<std::string> stage_notes;  // one line per stage: what it found and why it stopped
};

class Calibration {
 public:
  /// `config`: a calibration_schema() configuration (starting parameters, protocol, search
  /// keys); `settings` from calibration_settings() plus the command line. Checks the lab curve
  /// against the settings and an existing --out against this setup (InputError). `farm`: the
  /// processes that share the trials (each one constructs its Calibration with the same
  /// arguments); nullptr for this process alone.
  Calibration(io::Config config, CalibrationSettings settings, LabCurve lab, std::filesystem::path out_dir,
              std::filesystem::path from, std::ostream& log, parallel::TaskFarm* farm = nullptr);
  ~Calibration();
  Calibration(const Calibration&) = delete;
  Calibration& operator=(const Calibration&) = delete;

  /// The four stages, then calibrated.ini, comparison.csv and summary.json in the output folder.
  CalibrationResult run();

  /// Evaluates a batch (trials.csv first), `parallel_trials` at a time on each process; public so
  /// that other designs of experiments can use the same specimen, cache and outputs.
  std::vector<TrialResult> evaluate(const std::vector<ContactFit>& batch, int stage);
  /// Trials finished so far, by number.
  const std::vector<TrialResult>& trials() const { return trials_; }
  /// The lab-vs-model comparison of a finished trial (its stored history, or the trial again).
  CurveComparison comparison(const TrialResult& trial);

 private:
  struct Progress;
  TrialResult measure(const ContactFit& fit, const ModelCurve& model, int number, int stage, double seconds) const;
  double objective(const TrialResult& t) const;
  void claim_folder(const std::string& setup);  // lock, set-up check, setup.txt (leading process)
  void save_trials() const;
  void load_trials();
  void write_outputs(const CalibrationResult& result, int max_trials);  // calibration_outputs.cpp
  std::string setup_text() const;

  io::Config config_;
  CalibrationSettings settings_;
  LabCurve lab_;
  std::filesystem::path out_dir_;
  std::unique_ptr<io::OutputFolder> folder_;  // locked for the calibration's lifetime (leading process)
  std::ostream& log_;
  std::unique_ptr<parallel::LocalFarm> own_farm_;  // when given none
  parallel::TaskFarm* farm_;
  ContactFit start_;
  std::string modulus_key_ = "effective_modulus";  // the ball-ball law's stiffness parameter
  std::string modulus_symbol_ = "E*";              // its symbol in messages: E* or E
  double lab_slope_ = 0, lab_peak_ = 0, slope_limit_ = 0, target_strain_ = 0;
  bool rolling_by_dilatancy_ = false;  // stage 3 matches the late dilatancy (else the peak)
  double lab_dilatancy_ = 0;           // -, late dilatancy of the lab curve
  std::unique_ptr<ShearTrials> shears_;
  std::vector<TrialResult> trials_;  // sorted by number
  std::unique_ptr<Progress> progress_;
};

namespace detail {
/// The shortest text that reads back as the same double (trials.csv keys, folder names).
std::string exact_text(double v);
/// `digits` significant digits, for progress lines and messages.
std::string short_text(double v, int digits = 4);
/// The key (under ball_ball) of the modulus a calibration fits for the law `keyword`: its stiffness
/// role, effective_modulus (rrlinear, linear) or youngs_modulus (hertz-mindlin, hertz-dmt); and its
/// symbol, E* or E. InputError naming ball_ball.law for a law without one.
std::string modulus_key(const std::string& keyword);
std::string modulus_symbol(const std::string& keyword);
}  // namespace detail

}  // namespace dem::lab
