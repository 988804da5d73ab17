// The cyclic simple-shear test, as its method reads: a consolidated specimen (made here when the
// test makes its own), sigma_v0 noted, an optional static shear ramped in and held for half a
// period, the cyclic path row by row until a stop criterion, an optional monotonic shear, then the
// plates stopped. Each stage goes on where a loaded restart file left it.
#include <dem/lab/protocols/cyclic_shear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/lab/protocols/simple_shear.hpp>
#include <dem/lab/toolkit/broken_bonds.hpp>
#include <dem/lab/toolkit/fabric_log.hpp>
#include <dem/lab/toolkit/snapshots.hpp>

namespace dem::lab {

namespace {

std::string cycle_label(double cycles) {
  std::ostringstream out;
  out << "cycle_" << cycles;
  return out.str();
}

CyclicPath make_path(const CyclicShearConfig& c, double period) {
  return c.path == CyclicShape::Series ? CyclicPath::from_csv(c.series_file, period) : CyclicPath(c.path, c.direction_deg, c.minor_ratio);
}

}  // namespace

void check_cyclic_inputs(const CyclicShearConfig& config) {
  if (config.path == CyclicShape::Series) (void)CyclicPath::from_csv(config.series_file, 1.0);
}

std::vector<std::string> CyclicShearTest::run_files() {
  return {"cyclic_history.csv", "cycles.csv", "cyclic_fabric.csv", "cyclic_snapshots"};
}

CyclicShearTest::CyclicShearTest(SimpleShearConfig specimen_config, CyclicShearConfig config, std::filesystem::path out_dir,
                                 std::ostream& log)
    : own_config_((specimen_config.validate(), std::move(specimen_config))),
      own_run_(std::make_unique<Run>(std::make_unique<World>(world_settings(own_config_)), std::move(out_dir), RunFiles{}, log)),
      own_specimen_(std::make_unique<NgiSpecimen>(*own_run_, own_config_)),
      run_(*own_run_),
      specimen_(*own_specimen_),
      config_(std::move(config)),
      path_(make_path(config_, 1.0)),
      history_(run_.folder() / "cyclic_history.csv"),
      cycles_(horizontal_direction(config_.direction_deg), static_cast<int>(config_.rows_per_cycle)) {
  // The consolidation's row, roses and snapshots, as the simple-shear test writes them.
  const Vec3 d = horizontal_direction(own_config_.shear.legs().front().direction_deg);
  own_outputs_ = std::make_unique<ShearOutputs>(run_, specimen_, [d] { return d; });
  RunFiles files{SimpleShearTest::run_files(), ShearOutputs::files()};
  for (const std::string& f : run_files()) files.results.push_back(f), files.carried.push_back(f);
  run_.set_files(std::move(files));
  run_.set_restart_every(own_config_.output.restart_every_steps);
  run_.set_progress_every(own_config_.output.progress_seconds);
  keep_state();
}

CyclicShearTest::CyclicShearTest(Run& run, NgiSpecimen& specimen, CyclicShearConfig config, std::ostream* log)
    : run_(run),
      specimen_(specimen),
      config_(std::move(config)),
      path_(make_path(config_, 1.0)),
      history_(run_.folder() / "cyclic_history.csv"),
      cycles_(horizontal_direction(config_.direction_deg), static_cast<int>(config_.rows_per_cycle)) {
  if (log) run_.set_log(*log);
  keep_state();
}

CyclicShearTest::~CyclicShearTest() = default;

void CyclicShearTest::load_restart(const std::filesystem::path& file) {
  specimen_.load(file);
  // Checked here, before the output folder is claimed, so that a refused run leaves it as it was.
  if (step_ == Step::Start) require_cyclic_stage();
  run_.log() << "resumed from " << file.string() << " at step " << run_.world().step_count() << " ("
             << (step_ == Step::Start ? to_string(specimen_.progress()) : "cyclic stage " + std::to_string(static_cast<int>(current_phase_))) << ")\n";
}

void CyclicShearTest::open_outputs(const OutputOptions& options) {
  OutputOptions o = options;
  if (!own_run_) o.more_run_files.insert(o.more_run_files.end(), run_files().begin(), run_files().end());
  run_.claim(o);
}

// The drive of the consolidated specimen: its plates, area and height, the servo's gain and cap.
void CyclicShearTest::make_drive() {
  const SimpleShearConfig& c = specimen_.config();
  if (config_.path == CyclicShape::Series) path_ = make_path(config_, outcome_.period);  // "time" in seconds of the stepped period
  outcome_.consolidated_height = specimen_.consolidated_height();
  HorizontalDriveSettings drive;
  drive.top = specimen_.cell().top;
  drive.bottom = specimen_.cell().bottom;
  drive.area = specimen_.cell().area;
  drive.height = outcome_.consolidated_height;
  drive.stiffness_ratio = c.ball_facet.parameters.value_or("stiffness_ratio", 1.0);
  drive.relaxation = config_.servo_relaxation;
  drive.max_speed = config_.servo_max_speed > 0 ? config_.servo_max_speed : 10.0 * shear_rate_ * drive.height;
  drive_ = std::make_shared<HorizontalDrive>(drive);
}

// The stages' settings from the consolidated specimen: the shear rate, the period in whole steps
// per row, sigma_v0; the servo holds the height (constant volume) or the vertical stress.
void CyclicShearTest::require_cyclic_stage() const {
  const ShearStage stage = specimen_.stage();
  const bool makes_its_own = own_run_ && (stage == ShearStage::Empty || stage == ShearStage::Generated);
  require(stage == ShearStage::Consolidated || makes_its_own, "cyclic shear: the specimen's stage", static_cast<int>(stage),
          "2 (consolidated: consolidate it or load a consolidated restart)");
}

void CyclicShearTest::begin() {
  require_cyclic_stage();
  ServoWall* servo = specimen_.servo();
  require(servo != nullptr, "cyclic shear: the top plate's servo", "missing", "a consolidated specimen");
  const World& w = run_.world();
  shear_rate_ = specimen_.shear_rate();
  const double period = config_.period > 0 ? config_.period : 4.0 * 0.01 / shear_rate_;
  steps_per_row_ = std::max<std::int64_t>(1, std::llround(period / (static_cast<double>(config_.rows_per_cycle) * w.time_step())));
  outcome_.period = static_cast<double>(steps_per_row_ * config_.rows_per_cycle) * w.time_step();
  make_drive();
  outcome_.vertical_stress_initial = specimen_.measure(Vec3::UnitX()).vertical_stress;
  const double sigma_v0 = outcome_.vertical_stress_initial;
  servo->set_target(specimen_.config().consolidation.vertical_stress);
  servo->hold_position(config_.drainage == CyclicDrainage::ConstantVolume);
  static_stress_ = config_.static_csr * sigma_v0 * horizontal_direction(config_.static_direction_deg);
  run_.log() << "cyclic shear: " << (config_.control == CyclicControl::Stress ? "stress" : "strain") << "-controlled "
             << to_string(config_.path) << ", "
             << (config_.control == CyclicControl::Stress ? "CSR " + std::to_string(config_.csr)
                                                          : "strain amplitude " + std::to_string(config_.strain_amplitude))
             << ", " << (config_.drainage == CyclicDrainage::ConstantVolume ? "constant volume" : "drained") << ", sigma_v0 "
             << sigma_v0 / 1e3 << " kPa, period " << outcome_.period << " s (" << steps_per_row_ * config_.rows_per_cycle
             << " steps), H_c " << outcome_.consolidated_height * 1e3 << " mm\n";
}

Vec3 CyclicShearTest::stress_target(double cycles) const {
  const Vec3 p = path_.at(cycles);
  return static_stress_ + outcome_.vertical_stress_initial * (path_.absolute() ? p : Vec3(config_.csr * p));
}

Vec3 CyclicShearTest::strain_target(double cycles) const {
  const Vec3 p = path_.at(cycles);
  return cyclic_start_strain_ + (path_.absolute() ? p : Vec3(config_.strain_amplitude * p));
}

void CyclicShearTest::start_phase(CyclicPhase phase, std::int64_t start_step) {
  current_phase_ = phase;
  phase_start_step_ = start_step;
  HorizontalDrive& d = *drive_;
  const double steps_per_cycle = static_cast<double>(steps_per_row_ * config_.rows_per_cycle);
  if (phase == CyclicPhase::Static) {
    const Vec3 target = static_stress_;
    d.servo_stress([target](double n) { return target * std::min(1.0, n / 0.25); }, start_step, steps_per_cycle);
  } else if (phase == CyclicPhase::Cyclic) {
    if (config_.control == CyclicControl::Stress)
      d.servo_stress([this](double n) { return stress_target(n); }, start_step, steps_per_cycle);
    else
      d.follow_strain([this](double n) { return strain_target(n); }, start_step, steps_per_cycle);
  } else {
    d.move_bottom(shear_rate_ * outcome_.consolidated_height * horizontal_direction(config_.post_direction_deg));
  }
}

void CyclicShearTest::run() {
  run_.claim_if_needed();
  if (own_run_) {  // its own specimen: made and consolidated as the simple-shear test makes it
    if (specimen_.stage() == ShearStage::Empty) specimen_.generate();
    if (specimen_.stage() == ShearStage::Generated) {
      specimen_.consolidate();
      own_outputs_->next_row_at(0.0);
      own_outputs_->record(0.0, true);
      run_.save(run_.folder() / "consolidated.restart");
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  World& w = run_.world();
  if (step_ == Step::Start) {
    specimen_.cement(CementAfter::Consolidation);  // consolidated.restart, written before, is the plain specimen
    begin();
    current_phase_ = CyclicPhase::Static;
    record_row();
    step_ = Step::StaticRows;
    rows_done_ = 0;
    if (config_.static_csr > 0) start_phase(CyclicPhase::Static, w.step_count());
  }
  if (step_ == Step::StaticRows) {
    const std::int64_t rows = config_.static_csr > 0 ? std::max<std::int64_t>(2, config_.rows_per_cycle / 2) : 0;  // ramp, then hold
    for (; rows_done_ < rows; ++rows_done_, record_row()) {
      run_.save_if_due();
      w.step(steps_per_row_);
    }
    if (rows > 0)
      run_.log() << "static shear stress " << last_sample_.stress.norm() / 1e3 << " kPa (target " << static_stress_.norm() / 1e3 << " kPa)\n";
    step_ = Step::CyclicStart;
  }
  if (step_ == Step::CyclicStart) {
    cyclic_start_strain_ = plate_offset(w, specimen_.cell()) / outcome_.consolidated_height;
    drive_->reset_work();
    start_phase(CyclicPhase::Cyclic, w.step_count());
    record_row();  // N = 0
    step_ = Step::CyclicRows;
    rows_done_ = 0;
  }
  if (step_ == Step::CyclicRows) {
    while (true) {
      run_.save_if_due();
      w.step(steps_per_row_);
      ++rows_done_;
      record_row();
      const double n = static_cast<double>(rows_done_) / static_cast<double>(config_.rows_per_cycle);
      outcome_.cycles = n;
      if (config_.ru_limit > 0 && last_sample_.pore_pressure_ratio >= config_.ru_limit && std::isnan(outcome_.cycles_to_ru))
        outcome_.cycles_to_ru = n;
      if (config_.da_strain_limit > 0 && last_double_amplitude_ >= config_.da_strain_limit && std::isnan(outcome_.cycles_to_da_strain))
        outcome_.cycles_to_da_strain = n;
      while (next_snapshot_ < config_.snapshot_cycles.size() && n >= config_.snapshot_cycles[next_snapshot_] - 1e-12) {
        const std::string label = cycle_label(config_.snapshot_cycles[next_snapshot_++]);
        snapshots_->write(w, label, w.time(), last_sample_.strain.norm(), broken_bonds_.get());
        run_.record_outputs(snapshots_->files());
      }
      while (next_fabric_ < config_.fabric_cycles.size() && n >= config_.fabric_cycles[next_fabric_] - 1e-12)
        fabric_->record(w, cycle_label(config_.fabric_cycles[next_fabric_++]), last_sample_.strain.norm());
      write_outputs();
      specimen_.require_no_escape(last_sample_.strain.norm());
      if (!std::isnan(outcome_.cycles_to_ru)) outcome_.stop = "pore pressure ratio";
      else if (!std::isnan(outcome_.cycles_to_da_strain)) outcome_.stop = "double-amplitude strain";
      else if (n >= static_cast<double>(config_.max_cycles) - 1e-12) outcome_.stop = "cycles";
      else if (n >= path_.length_cycles() - 1e-12) outcome_.stop = "series end";
      if (!outcome_.stop.empty()) break;
      progress(n);
    }
    run_.log() << "cyclic stage ended at N = " << outcome_.cycles << " (" << outcome_.stop << "): r_u "
               << last_sample_.pore_pressure_ratio << ", double-amplitude strain " << last_double_amplitude_ << "\n";
    step_ = Step::PostRows;
    rows_done_ = -1;  // the post-cyclic stage's steps left, once it starts
  }
  if (step_ == Step::PostRows && config_.post_strain > 0) {
    // The bottom plate moves shear_rate x H_c x dt a step: the strain is a whole number of steps,
    // in rows of output.every_strain.
    const double per_step = shear_rate_ * w.time_step();
    if (rows_done_ < 0) {
      start_phase(CyclicPhase::Post, w.step_count());
      rows_done_ = std::max<std::int64_t>(1, std::llround(config_.post_strain / per_step));
      post_every_ = std::max<std::int64_t>(1, std::llround(specimen_.config().output.every_strain / per_step));
    }
    while (rows_done_ > 0) {
      run_.save_if_due();
      const std::int64_t steps = std::min(post_every_, rows_done_);
      w.step(steps);
      rows_done_ -= steps;
      record_row();
      write_outputs();
      specimen_.require_no_escape(last_sample_.strain.norm());
    }
    run_.log() << "post-cyclic shear to " << config_.post_strain << ": tau " << last_sample_.stress.norm() / 1e3 << " kPa, sigma_v "
               << last_sample_.vertical_stress / 1e3 << " kPa\n";
  }
  if (step_ != Step::Done) {
    step_ = Step::Done;
    drive_->hold();
    stop_shear(w, specimen_.cell());
    write_outputs();
    outcome_.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run_.save(run_.folder() / "final.restart");
    run_.log() << "cyclic shear done in " << outcome_.wall_seconds << " s\n";
  }
}

void CyclicShearTest::progress(double cycles) {
  std::ostringstream detail;
  detail << "N " << cycles << " of " << config_.max_cycles << ", tau " << last_sample_.stress.norm() / 1e3 << " kPa, sigma_v "
         << last_sample_.vertical_stress / 1e3 << " kPa, r_u " << last_sample_.pore_pressure_ratio << ", double-amplitude strain "
         << last_double_amplitude_;
  run_.progress("cyclic", detail.str(), cycles, static_cast<double>(config_.max_cycles));
}

}  // namespace dem::lab
