// The cyclic simple-shear protocol: the stages, the rows and the stop
// criteria. Outputs are written after every row, so the files are complete if the run stops.
#include <dem/lab/cyclic_shear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/lab/fabric_log.hpp>
#include <dem/lab/snapshots.hpp>
#include <dem/measure/shear_uniformity.hpp>

#include "../io/json_file.hpp"

namespace dem::lab {

namespace {

Vec3 horizontal(Vec3 v) {
  v.z() = 0.0;
  return v;
}

std::string cycle_label(double cycles) {
  std::ostringstream out;
  out << "cycle_" << cycles;
  return out.str();
}

}  // namespace

void check_cyclic_inputs(const CyclicShearConfig& config) {
  if (config.path == CyclicShape::Series) (void)CyclicPath::from_csv(config.series_file, 1.0);
}

std::vector<std::string> CyclicShearTest::run_files() {
  return {"cyclic_history.csv", "cycles.csv", "cyclic_fabric.csv", "cyclic_snapshots"};
}

CyclicShearTest::CyclicShearTest(SimpleShearTest& specimen, CyclicShearConfig config, std::ostream& log)
    : specimen_(specimen),
      config_(std::move(config)),
      log_(log),
      path_(config_.path == CyclicShape::Series ? CyclicPath::from_csv(config_.series_file, 1.0)
                                                : CyclicPath(config_.path, config_.direction_deg, config_.minor_ratio)),
      history_(specimen.output_folder() / "cyclic_history.csv"),
      cycles_(horizontal_direction(config_.direction_deg), static_cast<int>(config_.rows_per_cycle)) {
  require(specimen_.stage() == ShearStage::Consolidated, "cyclic shear: the specimen's stage", static_cast<int>(specimen_.stage()),
          "2 (consolidated: run consolidate() or load a consolidated restart)");
  add_history_columns();
  World& w = specimen_.world();
  const double height = specimen_.consolidated_height();
  shear_rate_ = specimen_.shear_rate();
  const double period = config_.period > 0 ? config_.period : 4.0 * 0.01 / shear_rate_;
  steps_per_row_ = std::max<std::int64_t>(1, std::llround(period / (static_cast<double>(config_.rows_per_cycle) * w.time_step())));
  outcome_.period = static_cast<double>(steps_per_row_ * config_.rows_per_cycle) * w.time_step();
  outcome_.consolidated_height = height;
  if (config_.path == CyclicShape::Series) {
    // A "time" column is in seconds of the stepped period: read again with it.
    path_ = CyclicPath::from_csv(config_.series_file, outcome_.period);
  }
  fabric_ = std::make_unique<FabricLog>(specimen_.output_folder() / "cyclic_fabric.csv");
  snapshots_ = std::make_unique<SnapshotWriter>(specimen_.output_folder() / "cyclic_snapshots");
  std::sort(config_.snapshot_cycles.begin(), config_.snapshot_cycles.end());
  std::sort(config_.fabric_cycles.begin(), config_.fabric_cycles.end());

  HorizontalDriveSettings drive;
  drive.top = specimen_.top_plate();
  drive.bottom = specimen_.bottom_plate();
  drive.area = specimen_.area();
  drive.height = height;
  drive.stiffness_ratio = specimen_.config().ball_facet.parameters.value_or("stiffness_ratio", 1.0);
  drive.relaxation = config_.servo_relaxation;
  drive.max_speed = config_.servo_max_speed > 0 ? config_.servo_max_speed : 10.0 * shear_rate_ * height;
  drive_ = std::make_shared<HorizontalDrive>(drive);
  std::weak_ptr<HorizontalDrive> weak = drive_;
  w.add_controller([weak](World& world) {
    if (const auto d = weak.lock()) (*d)(world);
  });
}

CyclicShearTest::~CyclicShearTest() = default;

Vec3 CyclicShearTest::stress_target(double cycles) const {
  const Vec3 p = path_.at(cycles);
  return static_stress_ + outcome_.vertical_stress_initial * (path_.absolute() ? p : Vec3(config_.csr * p));
}

Vec3 CyclicShearTest::strain_target(double cycles) const {
  const Vec3 p = path_.at(cycles);
  return cyclic_start_strain_ + (path_.absolute() ? p : Vec3(config_.strain_amplitude * p));
}

void CyclicShearTest::start_phase(CyclicPhase phase) {
  World& w = specimen_.world();
  HorizontalDrive& d = *drive_;
  const double steps_per_cycle = static_cast<double>(steps_per_row_ * config_.rows_per_cycle);
  if (phase == CyclicPhase::Static) {
    const Vec3 target = static_stress_;
    d.servo_stress([target](double n) { return target * std::min(1.0, n / 0.25); }, w.step_count(), steps_per_cycle);
  } else if (phase == CyclicPhase::Cyclic) {
    cyclic_start_strain_ = plate_offset(w, specimen_.cell()) / outcome_.consolidated_height;
    d.reset_work();
    if (config_.control == CyclicControl::Stress)
      d.servo_stress([this](double n) { return stress_target(n); }, w.step_count(), steps_per_cycle);
    else
      d.follow_strain([this](double n) { return strain_target(n); }, w.step_count(), steps_per_cycle);
  } else {
    d.move_bottom(shear_rate_ * outcome_.consolidated_height * horizontal_direction(config_.post_direction_deg));
  }
}

void CyclicShearTest::add_history_columns() {
  const ShearState& s = row_.state;
  HistoryLog& h = history_;
  const double& sigma_v0 = outcome_.vertical_stress_initial;
  const double& height_c = outcome_.consolidated_height;
  h.add("time", [&s] { return s.time; });
  h.add("step", [this] { return static_cast<double>(specimen_.world().step_count()); });
  h.add("phase", [this] { return static_cast<double>(static_cast<int>(current_phase_)); });
  h.add("cycles", [this] { return row_.cycles; });
  h.add("shear_strain_x", [&s] { return s.shear_strain_x; });
  h.add("shear_strain_y", [&s] { return s.shear_strain_y; });
  h.add("shear_strain", [&s] { return s.shear_strain; });
  h.add("shear_stress_x", [&s] { return s.shear_stress_x; });
  h.add("shear_stress_y", [&s] { return s.shear_stress_y; });
  h.add("shear_stress", [&s] { return s.shear_stress; });
  h.add("target_x", [this] { return row_.target.x(); });
  h.add("target_y", [this] { return row_.target.y(); });
  h.add("vertical_stress", [&s] { return s.vertical_stress; });
  h.add("vertical_stress_bottom", [&s] { return s.vertical_stress_bottom; });
  h.add("excess_pore_pressure", [this] { return row_.excess_pore_pressure; });
  h.add("pore_pressure_ratio", [this, &sigma_v0] { return row_.excess_pore_pressure / sigma_v0; });
  h.add("height", [&s] { return s.height; });
  h.add("height_change", [&s, &height_c] { return (s.height - height_c) / height_c; });
  h.add("stress_ratio", [&s] { return s.vertical_stress > 0 ? s.shear_stress / s.vertical_stress : NAN; });
  h.add("work", [this] { return drive_->work(); });
  h.add("double_amplitude_strain", [this] { return row_.double_amplitude; });
  h.add("lateral_stress", [&s] { return s.lateral_stress; });
  h.add("sigma_1", [&s] { return s.sphere.principal.sigma_1; });
  h.add("sigma_2", [&s] { return s.sphere.principal.sigma_2; });
  h.add("sigma_3", [&s] { return s.sphere.principal.sigma_3; });
  h.add("coordination_number", [&s] { return s.sphere.coordination_number; });
  h.add("mechanical_coordination_number", [&s] { return s.sphere.mechanical_coordination_number; });
  h.add("porosity", [&s] { return s.sphere.porosity; });
  h.add("specimen_porosity", [&s] { return s.specimen_porosity; });
  h.add("non_coaxiality_deg", [this] { return row_.non_coaxiality_deg; });
  h.add("kinetic_energy", [&s] { return s.kinetic_energy; });
  h.add("balls_outside", [&s] { return static_cast<double>(s.balls_outside); });
}

void CyclicShearTest::record_row() {
  const World& w = specimen_.world();
  row_.state = specimen_.measure();
  const ShearState& s = row_.state;
  const HorizontalDrive& d = *drive_;
  const Wall& top = w.wall(d.settings().top);
  const Wall& bottom = w.wall(d.settings().bottom);
  const double sigma_v0 = outcome_.vertical_stress_initial;
  const double excess = sigma_v0 - s.vertical_stress;
  const Vec3 rate = horizontal(bottom.velocity - top.velocity);
  const Mat3 stress = -s.sphere.stress, strain_rate = -s.sphere.strain_rate;
  const double coaxiality = rate.norm() > 0 ? measure::non_coaxiality_deg(stress, strain_rate, rate.normalized()) : NAN;
  const double phase_cycles = d.cycles_at(w.step_count());
  const double cycles = current_phase_ == CyclicPhase::Cyclic ? phase_cycles
                        : current_phase_ == CyclicPhase::Static ? 0.0 : outcome_.cycles;
  CyclicSample sample;
  sample.cycles = cycles;
  sample.strain = Vec3(s.shear_strain_x, s.shear_strain_y, 0.0);
  sample.stress = Vec3(s.shear_stress_x, s.shear_stress_y, 0.0);
  sample.pore_pressure_ratio = excess / sigma_v0;
  sample.work = d.work();
  sample.coordination_number = s.sphere.coordination_number;
  sample.mechanical_coordination_number = s.sphere.mechanical_coordination_number;
  sample.non_coaxiality_deg = coaxiality;
  sample.vertical_stress = s.vertical_stress;
  if (current_phase_ == CyclicPhase::Cyclic) cycles_.add(sample);
  row_.cycles = cycles;
  row_.target = d.target(phase_cycles);
  row_.excess_pore_pressure = excess;
  row_.double_amplitude = current_phase_ == CyclicPhase::Cyclic ? cycles_.double_amplitude_strain() : NAN;
  row_.non_coaxiality_deg = coaxiality;
  history_.record();
  last_sample_ = sample;
  last_double_amplitude_ = row_.double_amplitude;
}

void CyclicShearTest::write_outputs() const {
  const std::filesystem::path& out = specimen_.output_folder();  // cyclic_history.csv: saved by every row
  io::CsvTable table(CycleLog::columns(), io::Missing::Allowed);
  for (const CycleRow& r : cycles_.cycles()) table.add_row(CycleLog::values(r));
  table.save(out / "cycles.csv");
}

void CyclicShearTest::run() {
  const auto t0 = std::chrono::steady_clock::now();
  World& w = specimen_.world();
  ServoWall* servo = specimen_.vertical_servo();
  require(servo != nullptr, "cyclic shear: the top plate's servo", "missing", "a consolidated specimen");
  if (!specimen_.outputs_open()) specimen_.open_outputs({.more_run_files = run_files()});
  outcome_.vertical_stress_initial = specimen_.measure().vertical_stress;
  const double sigma_v0 = outcome_.vertical_stress_initial;
  servo->set_target(specimen_.config().consolidation.vertical_stress);
  servo->hold_position(config_.drainage == CyclicDrainage::ConstantVolume);
  static_stress_ = config_.static_csr * sigma_v0 * horizontal_direction(config_.static_direction_deg);
  log_ << "cyclic shear: " << (config_.control == CyclicControl::Stress ? "stress" : "strain") << "-controlled "
       << to_string(config_.path) << ", "
       << (config_.control == CyclicControl::Stress ? "CSR " + std::to_string(config_.csr) : "strain amplitude " + std::to_string(config_.strain_amplitude))
       << ", " << (config_.drainage == CyclicDrainage::ConstantVolume ? "constant volume" : "drained") << ", sigma_v0 "
       << sigma_v0 / 1e3 << " kPa, period " << outcome_.period << " s (" << steps_per_row_ * config_.rows_per_cycle
       << " steps), H_c " << outcome_.consolidated_height * 1e3 << " mm\n";

  current_phase_ = CyclicPhase::Static;
  record_row();
  if (config_.static_csr > 0) {
    start_phase(CyclicPhase::Static);
    const std::int64_t rows = std::max<std::int64_t>(2, config_.rows_per_cycle / 2);  // half a period: ramp, then hold
    for (std::int64_t r = 0; r < rows; ++r) {
      w.step(steps_per_row_);
      record_row();
    }
    log_ << "static shear stress " << last_sample_.stress.norm() / 1e3 << " kPa (target " << static_stress_.norm() / 1e3 << " kPa)\n";
  }

  current_phase_ = CyclicPhase::Cyclic;
  start_phase(CyclicPhase::Cyclic);
  record_row();  // N = 0
  auto first = [](double& at, double cycles) {
    if (std::isnan(at)) at = cycles;
  };
  std::int64_t row = 0;
  while (true) {
    w.step(steps_per_row_);
    ++row;
    record_row();
    const double n = static_cast<double>(row) / static_cast<double>(config_.rows_per_cycle);
    outcome_.cycles = n;
    if (config_.ru_limit > 0 && last_sample_.pore_pressure_ratio >= config_.ru_limit) first(outcome_.cycles_to_ru, n);
    if (config_.da_strain_limit > 0 && last_double_amplitude_ >= config_.da_strain_limit) first(outcome_.cycles_to_da_strain, n);
    while (next_snapshot_ < config_.snapshot_cycles.size() && n >= config_.snapshot_cycles[next_snapshot_] - 1e-12)
      snapshots_->write(w, cycle_label(config_.snapshot_cycles[next_snapshot_++]), w.time(), last_sample_.strain.norm());
    while (next_fabric_ < config_.fabric_cycles.size() && n >= config_.fabric_cycles[next_fabric_] - 1e-12)
      fabric_->record(w, cycle_label(config_.fabric_cycles[next_fabric_++]), last_sample_.strain.norm());
    write_outputs();
    specimen_.require_no_escape();
    if (!std::isnan(outcome_.cycles_to_ru)) outcome_.stop = "pore pressure ratio";
    else if (!std::isnan(outcome_.cycles_to_da_strain)) outcome_.stop = "double-amplitude strain";
    else if (n >= static_cast<double>(config_.max_cycles) - 1e-12) outcome_.stop = "cycles";
    else if (n >= path_.length_cycles() - 1e-12) outcome_.stop = "series end";
    if (!outcome_.stop.empty()) break;
    progress(n);
  }
  log_ << "cyclic stage ended at N = " << outcome_.cycles << " (" << outcome_.stop << "): r_u "
       << last_sample_.pore_pressure_ratio << ", double-amplitude strain " << last_double_amplitude_ << "\n";

  if (config_.post_strain > 0) {
    current_phase_ = CyclicPhase::Post;
    start_phase(CyclicPhase::Post);
    // The bottom plate moves shear_rate x H_c x dt a step: the strain is a whole number of steps,
    // in rows of output.every_strain.
    const double per_step = shear_rate_ * w.time_step();
    const auto every = std::max<std::int64_t>(1, std::llround(specimen_.config().output.every_strain / per_step));
    for (std::int64_t left = std::max<std::int64_t>(1, std::llround(config_.post_strain / per_step)); left > 0;) {
      const std::int64_t steps = std::min(every, left);
      w.step(steps);
      left -= steps;
      record_row();
      write_outputs();
      specimen_.require_no_escape();
    }
    log_ << "post-cyclic shear to " << config_.post_strain << ": tau " << last_sample_.stress.norm() / 1e3 << " kPa, sigma_v "
         << last_sample_.vertical_stress / 1e3 << " kPa\n";
  }
  drive_->hold();
  stop_shear(w, specimen_.cell());
  write_outputs();
  specimen_.save_restart(specimen_.output_folder() / "final.restart");
  outcome_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log_ << "cyclic shear done in " << outcome_.wall_seconds << " s\n";
}

void CyclicShearTest::progress(double cycles) const {
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (now - last_progress_ < specimen_.config().output.progress_seconds) return;
  last_progress_ = now;
  log_ << "[cyclic] N " << cycles << " of " << config_.max_cycles << ", tau " << last_sample_.stress.norm() / 1e3 << " kPa, sigma_v "
       << last_sample_.vertical_stress / 1e3 << " kPa, r_u " << last_sample_.pore_pressure_ratio << ", double-amplitude strain "
       << last_double_amplitude_ << std::endl;
}

void CyclicShearTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  const SpecimenState& c = specimen_.consolidated_state();
  j["balls"] = specimen_.ball_count();
  j["consolidated_height_m"] = outcome_.consolidated_height;
  io::Json sc;
  sc["porosity"] = c.porosity;
  sc["coordination_number"] = c.coordination_number;
  sc["mechanical_coordination_number"] = c.mechanical_coordination_number;
  sc["vertical_stress_Pa"] = c.vertical_stress;
  sc["k0"] = c.k0;
  j["specimen_consolidated"] = sc;
  j["vertical_stress_initial_Pa"] = outcome_.vertical_stress_initial;
  j["period_s"] = outcome_.period;
  j["steps_per_cycle"] = steps_per_row_ * config_.rows_per_cycle;
  j["cycles"] = outcome_.cycles;
  j["stop"] = outcome_.stop;
  io::Json l;
  l["pore_pressure_ratio"] = config_.ru_limit > 0 ? io::Json(outcome_.cycles_to_ru) : io::Json();
  l["double_amplitude_strain"] = config_.da_strain_limit > 0 ? io::Json(outcome_.cycles_to_da_strain) : io::Json();
  j["cycles_to_liquefaction"] = l;
  if (history_.rows() > 0) {
    io::Json f;
    for (const char* name : {"shear_strain", "shear_stress", "vertical_stress", "pore_pressure_ratio", "double_amplitude_strain",
                             "coordination_number", "mechanical_coordination_number"})
      f[name] = history_.last(name);
    j["final"] = f;
  }
  j["wall_clock_s"] = outcome_.wall_seconds;
  j["threads"] = specimen_.world().threads();
  j["time_step_s"] = specimen_.world().time_step();
  j["configuration"] = io::Json::parse(resolved_config_json);
  io::save_json(specimen_.output_folder() / "summary.json", j);
}

}  // namespace dem::lab
