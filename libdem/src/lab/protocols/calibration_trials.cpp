// The specimen of a calibration and its trial shears (ShearTrials, see calibration.hpp), and the
// small helpers the calibration shares with it.
#include <dem/lab/protocols/calibration.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/core/law_registry.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/shear_legs.hpp>
#include <dem/lab/protocols/simple_shear.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>
#include <dem/lab/toolkit/specimen_file.hpp>
#include <dem/lab/toolkit/specimen_guards.hpp>

namespace fs = std::filesystem;

namespace dem::lab {
namespace detail {

std::string short_text(double v, int digits) {
  std::ostringstream out;
  out.precision(digits);
  out << v;
  return out.str();
}

std::string exact_text(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return {buffer, result.ptr};
}

std::string modulus_key(const std::string& keyword) {
  const LawEntry& law = contact_law(keyword, "ball_ball.law");
  require(!law.roles.stiffness.empty(), "ball_ball.law", keyword, "a law with a modulus to fit");
  return law.roles.stiffness;
}

std::string modulus_symbol(const std::string& keyword) { return modulus_key(keyword) == "effective_modulus" ? "E*" : "E"; }

}  // namespace detail

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A world of the configuration `c`: its shear cell and contact laws, no balls yet.
struct TrialWorld {
  World world;
  ShearCell cell;
  explicit TrialWorld(const SimpleShearConfig& c) : world(world_settings(c)), cell(build_shear_cell(world, shear_cell_spec(c))) {
    set_contact_laws(world, c, c.ball_ball.friction(), c.ball_ball.rolling_friction(), false);
  }
};

// A trial from the toolkit's parts: the consolidated specimen of `restart` sheared along the legs of
// `c` (one, to the lab's largest strain) as SimpleShearTest::shear() shears it, with a history row
// at every output.every_strain and at the end. The columns model_curve_from_history reads are
// measured as SimpleShearTest measures them; the first row is this specimen's own consolidated
// state.
void shear_specimen(const SimpleShearConfig& c, const fs::path& restart, const fs::path& history_file, std::ostream& log) {
  c.validate();
  require(c.shear.total_strain() > 0.0, "trial shear strain", c.shear.total_strain(), "> 0");
  const auto t0 = std::chrono::steady_clock::now();
  TrialWorld trial(c);
  World& world = trial.world;
  const ShearCell& cell = trial.cell;
  const ConsolidatedSpecimen specimen = load_consolidated_specimen(restart, world, cell, c, log);
  ServoWall servo(cell.top, specimen.servo);
  servo.resume_steps_on_target(specimen.servo_steps_on_target);
  world.add_controller([&](World& w) {
    servo(w);
    move_rings(w, cell, true);
    w.set_damping_frame(shear_damping_frame(c, w, cell));  // docs/model.md 3.1
  });
  const double height = specimen.height;  // m, H_c
  const double sign = c.output.volumetric_strain_sign == VolumeSign::DilationPositive ? 1.0 : -1.0;
  HistoryLog history(history_file);
  history.add("time", [&] { return world.time(); });
  history.add("shear_strain", [&] { return plate_offset(world, cell).norm() / height; });
  history.add("shear_stress", [&] {
    return std::hypot(world.wall(cell.top).force.x() / cell.area, world.wall(cell.top).force.y() / cell.area);
  });
  history.add("vertical_stress", [&] { return world.wall(cell.top).normal_stress(); });
  history.add("height", [&] { return cell.plate_gap(world); });
  history.add("volumetric_strain", [&] { return sign * ((cell.plate_gap(world) - height) / height); });
  history.add("lateral_stress", [&] { return ring_lateral_stress(world, cell); });
  history.add("balls_outside", [&] { return static_cast<double>(balls_outside(world, cell)); });
  history.record();

  ShearLegs legs(c.shear.legs());
  const double rate = shear_strain_rate(c, world);  // 1/s
  log << "resumed from " << restart.string() << " at step " << world.step_count() << "; shear: rate " << rate << " 1/s, "
      << (c.shear.mode == ShearMode::ConstantVolume ? "constant volume" : "drained") << ", to " << legs.total_strain() << "\n";
  const auto start_leg = [&](const ShearLeg& leg) {
    start_shear_leg(world, cell, servo, shear_leg_motion(c, leg.direction_deg, rate, height));
  };
  const std::int64_t first_step = world.step_count();
  double next_row = c.output.every_strain;
  legs.start(world, cell, height);
  start_leg(legs.current());
  legs.run(world, cell, SimpleShearTest::chunk_steps, start_leg, [&](double strain, bool done) {
    if (!done && strain < next_row - 1e-12) return;
    world.gather_state();  // after a step that left only the walls whole
    history.record();
    require_no_escape(world, cell, strain);  // after the row: it shows the state the ball was lost in
    while (next_row <= strain + 1e-12) next_row += c.output.every_strain;
  });
  stop_shear(world, cell);
  log << "shear done in " << seconds_since(t0) << " s, " << world.step_count() - first_step << " steps, shear stress "
      << history.last("shear_stress") / 1e3 << " kPa at strain " << legs.strain() << "\n";
}

// Refuses, before any work, a --from specimen that this configuration cannot go on from: its balls
// against the grading, its engine and specimen keys against the configuration.
void check_specimen_file(const SimpleShearConfig& c, const fs::path& file) {
  TrialWorld trial(c);
  std::ostringstream applied;  // the keys a trial applies again: logged by each trial
  load_specimen(file, trial.world, trial.cell, c, applied);
}

}  // namespace

ShearTrials::ShearTrials(SimpleShearConfig base, fs::path out_dir, fs::path from, bool fit_modulus, std::ostream& log,
                         ModulusSpecimen rule, parallel::TaskFarm* farm)
    : base_(std::move(base)), out_dir_(std::move(out_dir)), log_(log), rule_(rule),
      own_farm_(farm ? nullptr : std::make_unique<parallel::LocalFarm>()), farm_(farm ? farm : own_farm_.get()) {
  // Trials need neither roses nor snapshots nor periodic restarts: only the history.
  base_.output.fabric_strains.clear();
  base_.output.snapshot_strains.clear();
  base_.output.restart_every_steps = std::numeric_limits<long>::max() / 4;
  base_.output.progress_seconds = 60.0;
  // Every trial's specimen is made with the starting generation friction, not the trial's.
  base_.generation.friction = base_.generation_friction();
  base_.generation.rolling_friction = base_.generation_rolling_friction();
  fs::create_directories(out_dir_ / "specimen");
  generated_files_ = out_dir_ / "specimen" / "generated";
  generated_restart_ = generated_files_ / "generated.restart";
  if (from.empty()) return;

  // Which stage does the restart hold? The leading process reads it for all.
  const std::string stage_text = farm_->on_leader([&] {
    ShearStage held = ShearStage::Empty;
    try {
      held = restart_stage(from);
      check_specimen_file(base_, from);
    } catch (const InputError& e) {
      throw InputError("--from " + from.string() + ": " + e.what());
    }
    // Specimens of other E* are consolidated again from a consolidated one, continuing its history.
    if (held == ShearStage::Consolidated && fit_modulus)
      require(fs::exists(from.parent_path() / "history.csv"), "--from " + from.string() + ": history.csv beside it",
              "(missing)", "the folder the restart was written in, with the history.csv written with it");
    return std::to_string(static_cast<int>(held));
  });
  const auto stage = static_cast<ShearStage>(std::stoi(stage_text));
  if (stage == ShearStage::Generated) {
    generated_restart_ = from;
    generated_files_ = from.parent_path();
  } else if (stage == ShearStage::Consolidated) {
    require(!fit_modulus || rule_ == ModulusSpecimen::Reconsolidated, "--from", from.string() + " (a consolidated specimen)",
            "a restart right after generation when E* is fitted with calibration.modulus_specimen = generated (every E* "
            "is then consolidated from the generated state); use modulus_specimen = reconsolidated, fit without emod, or drop --from");
    given_consolidated_ = from;
  } else {
    throw InputError("--from " + from.string() + ": stage " + std::to_string(static_cast<int>(stage)) +
                     ": must be a restart after generation (1) or consolidation (2), e.g. dem-consolidate's consolidated.restart");
  }
}

ShearTrials::~ShearTrials() = default;

SimpleShearConfig ShearTrials::config_for(const ContactFit& fit, int threads) const {
  SimpleShearConfig c = base_;
  c.ball_ball.set_stiffness(fit.modulus);
  c.ball_ball.set_friction(fit.friction);
  if (!c.ball_ball.entry().roles.rolling_friction.empty()) c.ball_ball.set_rolling_friction(fit.rolling_friction);
  c.engine.threads = std::max(1, threads);
  return c;
}

fs::path ShearTrials::specimen_dir(double modulus) const { return out_dir_ / "specimen" / ("E_" + detail::exact_text(modulus)); }

fs::path ShearTrials::trial_dir(int number) const {
  std::ostringstream name;
  name << std::setw(4) << std::setfill('0') << number;
  return out_dir_ / "trials" / name.str();
}

fs::path ShearTrials::specimen_restart(double modulus) const {
  if (!given_consolidated_.empty() && modulus == base_.ball_ball.stiffness()) return given_consolidated_;
  return specimen_dir(modulus) / "consolidated.restart";
}

std::vector<double> ShearTrials::prepare(const std::vector<double>& moduli, int parallel, int threads) {
  std::vector<double> seconds(moduli.size(), 0.0);
  const double start_modulus = base_.ball_ball.stiffness();
  if (!given_consolidated_.empty() && rule_ == ModulusSpecimen::Generated) {
    for (double m : moduli)
      require(m == start_modulus, "trial E*", m, "the E* of the --from specimen, " + detail::exact_text(start_modulus));
    return seconds;
  }
  // What is missing is seen by the leading process and handed to the others, so that all take
  // the same steps even if a file system's caches show them an older folder.
  const bool from_reference = rule_ == ModulusSpecimen::Reconsolidated;
  std::istringstream plan(farm_->on_leader([&] {
    std::ostringstream missing;
    missing << (from_reference && !fs::exists(specimen_restart(start_modulus)));  // the starting E*'s specimen
    for (std::size_t i = 0; i < moduli.size(); ++i) {
      const bool first = std::find(moduli.begin(), moduli.begin() + static_cast<std::ptrdiff_t>(i), moduli[i]) == moduli.begin() + static_cast<std::ptrdiff_t>(i);
      if (first && !fs::exists(specimen_restart(moduli[i]))) missing << ' ' << i;
    }
    return missing.str();
  }));
  bool reference_missing = false;
  plan >> reference_missing;
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; plan >> i;) todo.push_back(i);
  if (todo.empty()) return seconds;

  // Reconsolidated specimens start from the one of the starting E*: make that first. Each specimen
  // is made by one process; the farm hands its seconds to every process.
  auto timed = [](const std::function<void()>& make) {
    const auto t0 = std::chrono::steady_clock::now();
    make();
    return detail::exact_text(seconds_since(t0));
  };
  double reference_seconds = 0.0;
  if (reference_missing)
    reference_seconds = std::stod(farm_->on_leader([&] {
      return timed([&] {
        generate_once(parallel * threads);
        consolidate_specimen(start_modulus, parallel * threads);
      });
    }));
  if (!from_reference) farm_->on_leader([&] { return timed([&] { generate_once(parallel * threads); }); });
  farm_->run(
      todo.size(), parallel,
      [&](std::size_t k) {
        const std::size_t i = todo[k];
        return timed([&] {
          if (!from_reference || moduli[i] != start_modulus) consolidate_specimen(moduli[i], threads);
        });
      },
      [&](std::size_t k, const std::string& result) { seconds[todo[k]] = std::stod(result); });
  if (from_reference) seconds[todo.front()] += reference_seconds;
  return seconds;
}

void ShearTrials::generate_once(int threads) {
  if (!fs::exists(generated_restart_)) {
    const auto t0 = std::chrono::steady_clock::now();
    fs::remove_all(generated_files_);
    fs::create_directories(generated_files_);
    std::ofstream log(generated_files_ / "log.txt");
    SimpleShearTest test(config_for({base_.ball_ball.stiffness(), base_.ball_ball.friction(), base_.ball_ball.rolling_friction()},
                                    threads),
                         generated_files_, log);
    test.generate();
    test.save_restart(generated_restart_);
    std::ostringstream line;
    line.precision(3);
    line << "specimen generated in " << seconds_since(t0) << " s: " << test.ball_count() << " balls (" << generated_restart_.string()
         << ")\n";
    log_ << line.str() << std::flush;
  }
}

void ShearTrials::consolidate_specimen(double modulus, int threads) {
  // From the generated state, or again from the starting E*'s consolidated specimen; with the
  // starting mu and mu_r either way, so that a specimen depends on E* only.
  const bool again = rule_ == ModulusSpecimen::Reconsolidated && modulus != base_.ball_ball.stiffness();
  const fs::path from = again ? specimen_restart(base_.ball_ball.stiffness()) : generated_restart_;
  const fs::path dir = specimen_dir(modulus);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream log(dir / "log.txt");
  SimpleShearTest test(config_for({modulus, base_.ball_ball.friction(), base_.ball_ball.rolling_friction()}, threads), dir, log);
  test.load_restart(from);
  // Both write dir/consolidated.restart last: its presence marks a finished specimen.
  if (again) test.reconsolidate();
  else test.consolidate();
}

ModelCurve ShearTrials::shear(const ContactFit& fit, double strain, int number, int threads) const {
  const fs::path restart = specimen_restart(fit.modulus);
  require(fs::exists(restart), "consolidated specimen", restart.string(), "prepared before the trial (ShearTrials::prepare)");
  const fs::path dir = trial_dir(number);
  fs::remove_all(dir);
  SimpleShearConfig c = config_for(fit, threads);
  c.shear.directions_deg = {base_.shear.legs().front().direction_deg};
  c.shear.leg_strains = {strain};
  fs::create_directories(dir);
  {
    std::ofstream log(dir / "log.txt");
    shear_specimen(c, restart, dir / "history.csv", log);
  }
  const ModelCurve model = model_curve_from_history(io::read_csv(dir / "history.csv", io::Missing::Allowed));
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename() != "history.csv" && entry.path().filename() != "log.txt") fs::remove_all(entry.path());
  return model;
}

std::optional<ModelCurve> ShearTrials::stored_curve(int number) const {
  const fs::path file = trial_dir(number) / "history.csv";
  if (!fs::exists(file)) return std::nullopt;
  return model_curve_from_history(io::read_csv(file, io::Missing::Allowed));
}

}  // namespace dem::lab
