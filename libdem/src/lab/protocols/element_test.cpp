// Element tests in a periodic cell, as their method reads: the specimen made in the cell (a gas
// compressed by the cell servo to the confining stress), then the material's law and the loading
// path by the cell's velocity gradient, a history row every element.every_strain. Each stage goes
// on where a loaded restart file left it.
#include <dem/lab/protocols/element_test.hpp>

#include <chrono>
#include <cmath>
#include <ostream>
#include <sstream>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/core/errors.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>
#include <dem/measure/cell_state.hpp>
#include <dem/measure/cell_stress.hpp>

#include "../../io/json_file.hpp"
#include "../toolkit/run_summary.hpp"

namespace dem::lab {

namespace {

constexpr std::int64_t loading_chunk_steps = 10;  // steps between tests of the row and end strains
constexpr int profile_bins = 12;    // height bins of the simple shears' displacement profile (as the NGI cell's)
constexpr double span_from = 0.2;  // the simple shears' uniformity over the NGI cell's span, from 20 % to the end

PeriodicSpecimenSettings specimen_settings(const ElementTestConfig& c) {
  const ElementConfig& e = c.element;
  return {.grading = c.grading, .ball_ball = c.ball_ball, .density = e.density, .balls = e.balls, .seed = e.seed,
          .initial_solid_fraction = e.initial_solid_fraction, .stress = e.confining_stress, .compaction_friction = e.compaction_friction,
          .tolerance = e.tolerance, .equilibrium_ratio = e.equilibrium_ratio, .max_rate = e.servo_max_rate,
          .max_steps = e.max_compaction_steps, .section = "element"};
}

bool simple_shear(ElementTestKind kind) {
  return kind == ElementTestKind::SimpleShear || kind == ElementTestKind::SimpleShearUndrained || kind == ElementTestKind::CyclicSimpleShear;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::string to_string(ElementTestKind kind) {
  switch (kind) {
    case ElementTestKind::Isotropic: return "isotropic";
    case ElementTestKind::TriaxialDrained: return "triaxial-drained";
    case ElementTestKind::TriaxialUndrained: return "triaxial-undrained";
    case ElementTestKind::SimpleShear: return "simple-shear";
    case ElementTestKind::SimpleShearUndrained: return "simple-shear-undrained";
    case ElementTestKind::CyclicSimpleShear: return "cyclic-simple-shear";
  }
  return "?";
}

std::vector<std::string> ElementTest::run_files() {
  return {"history.csv", "summary.json", "restart.restart", "consolidated.restart", "final.restart", "broken_bonds.vtp"};
}

ElementTest::ElementTest(ElementTestConfig config, std::filesystem::path out_dir, std::ostream& log)
    : config_(std::move(config)),
      run_(std::make_unique<World>(world_settings(config_.engine)), std::move(out_dir), {run_files(), {"history.csv"}}, log),
      history_(run_.folder() / "history.csv"),
      specimen_(run_, specimen_settings(config_)) {
  run_.set_restart_every(config_.output.restart_every_steps);
  run_.set_progress_every(config_.output.progress_seconds);
  const ElementConfig& e = config_.element;
  cyclic_path_ = e.cyclic_path == CyclicShape::Series ? CyclicPath::from_csv(e.cyclic_series_file, cyclic_period())
                                                      : CyclicPath(e.cyclic_path, e.cyclic_direction_deg, e.cyclic_minor_ratio);
  add_columns();
  if (config_.cementation.after != CementAfter::None)
    broken_bonds_ = std::make_unique<BrokenBondLog>(run_, "element_broken_bond_strains",
                                                    e.test == ElementTestKind::CyclicSimpleShear ? "cycles" : "test_strain");
  run_.keep("stage", [this] { return static_cast<double>(stage_); }, [this](double v) {
    require(v >= 0 && v <= 2 && v == std::floor(v), "restart file: stage", v, "0, 1 or 2");
    stage_ = static_cast<Stage>(static_cast<int>(v));
  });
  for (std::size_t k = 0; k < reference_.size(); ++k) run_.keep("reference_cell_" + std::to_string(k), reference_[k]);
  run_.keep("next_row_strain", next_row_strain_);
  run_.keep("loading_start_time", loading_start_time_);
  run_.keep("peak_ratio", peak_ratio_);
  run_.keep("peak_strain", peak_strain_);
  run_.keep("history_rows", [this] { return static_cast<double>(history_.rows()); },
            [this](double rows) { history_.resume(run_.loaded_folder() / "history.csv", static_cast<std::size_t>(rows)); });
}

double ElementTest::strain_rate() const {
  const ElementConfig& e = config_.element;
  if (e.strain_rate > 0.0) return e.strain_rate;
  // I = rate d sqrt(rho / p): the mean diameter of the grading, the confining stress.
  const double diameter = 0.5 * (config_.grading.smallest() + config_.grading.largest());
  return e.inertial_number / diameter * std::sqrt(e.confining_stress / e.density);
}

double ElementTest::cyclic_period() const {
  const double period = config_.element.cyclic_period;
  return period > 0.0 ? period : 4.0 * 0.01 / strain_rate();
}

Vec3 ElementTest::cyclic_target(double time) const {
  const ElementConfig& e = config_.element;
  const bool strain = e.cyclic_control == CyclicControl::Strain;
  // A series holds the strains or the stress ratios themselves; a drawn shape is in amplitudes.
  const double amplitude = cyclic_path_.absolute() ? (strain ? 1.0 : e.confining_stress)
                                                   : (strain ? e.strain_amplitude : e.csr * e.confining_stress);
  return amplitude * cyclic_path_.at(std::max(0.0, (time - loading_start_time_) / cyclic_period()));
}

Mat3 ElementTest::reference() const {
  Mat3 h;
  for (int k = 0; k < 9; ++k) h(k / 3, k % 3) = reference_[static_cast<std::size_t>(k)];
  return h;
}

double ElementTest::test_strain() const {
  const Mat3 h = run_.world().periodic_cell()->matrix(), h0 = reference();
  if (config_.element.test == ElementTestKind::Isotropic) return 1.0 - h.determinant() / h0.determinant();
  if (config_.element.test == ElementTestKind::CyclicSimpleShear) return (run_.world().time() - loading_start_time_) / cyclic_period();
  if (simple_shear(config_.element.test)) return measure::cell_strain(h0, h).deformation_gradient(0, 2);
  return axial_sign() * (1.0 - h(2, 2) / h0(2, 2));
}

double ElementTest::row_spacing() const {
  const ElementConfig& e = config_.element;
  return e.test == ElementTestKind::CyclicSimpleShear ? 1.0 / static_cast<double>(e.rows_per_cycle) : e.every_strain;
}

double ElementTest::test_end() const {
  const ElementConfig& e = config_.element;
  if (e.test != ElementTestKind::CyclicSimpleShear) return e.target_strain;
  return std::min(e.cycles, cyclic_path_.length_cycles());  // a series ends at its last row
}

double ElementTest::axial_sign() const {
  return config_.element.direction == TriaxialDirection::Extension ? -1.0 : 1.0;
}

// The path of element.test on the servo: rates where prescribed, stresses where held.
void ElementTest::set_path() {
  CellServo& servo = specimen_.servo();
  const double stress = config_.element.confining_stress;
  const double rate = strain_rate(), axial_rate = axial_sign() * rate;  // zz shortened at +rate in compression
  for (CellComponent shear : {CellComponent::yz, CellComponent::xz, CellComponent::xy}) servo.set_rate(shear, 0.0);
  switch (config_.element.test) {
    case ElementTestKind::Isotropic: break;
    case ElementTestKind::TriaxialDrained:
      if (config_.element.drained_path == DrainedPath::ConstantP) {
        // The lateral target from the last measured sigma_zz (compression positive): p stays put.
        const auto lateral = [&servo, stress](double) { return 0.5 * (3.0 * stress + servo.stress().stress(2, 2)); };
        servo.set_stress_path(CellComponent::xx, lateral);
        servo.set_stress_path(CellComponent::yy, lateral);
      } else {
        servo.set_stress(CellComponent::xx, stress);
        servo.set_stress(CellComponent::yy, stress);
      }
      servo.set_rate(CellComponent::zz, -axial_rate);
      break;
    case ElementTestKind::TriaxialUndrained:
      servo.set_rate(CellComponent::zz, -axial_rate);
      servo.set_rate(CellComponent::xx, 0.5 * axial_rate);
      servo.hold_volume(CellComponent::yy);
      break;
    case ElementTestKind::SimpleShear:
    case ElementTestKind::SimpleShearUndrained:
      servo.set_rate(CellComponent::xx, 0.0);
      servo.set_rate(CellComponent::yy, 0.0);
      if (config_.element.test == ElementTestKind::SimpleShear) servo.set_stress(CellComponent::zz, stress);
      else servo.set_rate(CellComponent::zz, 0.0);
      servo.set_rate(CellComponent::xz, rate);
      break;
    case ElementTestKind::CyclicSimpleShear: {
      for (CellComponent normal : {CellComponent::xx, CellComponent::yy, CellComponent::zz}) servo.set_rate(normal, 0.0);
      const double dt = run_.world().time_step();
      const bool drained = config_.element.cyclic_drainage == CyclicDrainage::Drained;
      if (drained) servo.set_stress(CellComponent::zz, stress);
      if (drained && config_.element.cyclic_control == CyclicControl::Strain) {
        // sigma_zz held, so L_zz != 0 and dF_xz = dt L_xz F_zz: the rate that lands F_xz (F_yz) on
        // the path at t + dt from where it is, so the height's change does not drift it off.
        // The reference cell is fixed once loading starts (set_path runs after it is set or restored).
        const Mat3 from_reference = reference().inverse();
        const auto rate_to = [this, dt, from_reference](int column) {
          return [this, dt, column, from_reference](double t) {
            const Mat3 f = run_.world().periodic_cell()->matrix() * from_reference;
            return (cyclic_target(t + dt)[column] - f(column, 2)) / (dt * f(2, 2));
          };
        };
        servo.set_rate_path(CellComponent::xz, rate_to(0));
        servo.set_rate_path(CellComponent::yz, rate_to(1));
      } else if (config_.element.cyclic_control == CyclicControl::Strain) {
        // With every normal rate and L_xy zero, a step of L_xz (L_yz) adds dt L_xz (dt L_yz) to
        // F_xz (F_yz) exactly (L h is then nilpotent): the rate of the step from t to t + dt that
        // lands the strain on the path at t + dt, so it follows the path with no drift.
        servo.set_rate_path(CellComponent::xz, [this, dt](double t) { return (cyclic_target(t + dt).x() - cyclic_target(t).x()) / dt; });
        servo.set_rate_path(CellComponent::yz, [this, dt](double t) { return (cyclic_target(t + dt).y() - cyclic_target(t).y()) / dt; });
      } else {
        // tau = -sigma_xz (compression positive), the shear stress that resists a positive strain.
        servo.set_stress_path(CellComponent::xz, [this](double t) { return -cyclic_target(t).x(); });
        servo.set_stress_path(CellComponent::yz, [this](double t) { return -cyclic_target(t).y(); });
      }
      break;
    }
  }
}

void ElementTest::load_restart(const std::filesystem::path& file) {
  const ProtocolRecord& record = run_.load(file);
  const RunProgress progress = stage_ == Stage::Done      ? RunProgress::Done
                               : stage_ == Stage::Loading ? RunProgress::Shearing
                               : specimen_.made()         ? RunProgress::Consolidated
                               : specimen_.placed()       ? RunProgress::Consolidating
                                                          : RunProgress::Generating;
  if (!record.configuration.empty() && !run_.configuration().empty())
    for (const ResumeChange& c : check_resume(run_.schema(), record.configuration, run_.configuration(), progress, false, "restart file " + file.string())) {
      // Only the isotropic test records rows while compressing: mid-compression it cannot change.
      require(!(c.key == "element.test" && progress == RunProgress::Consolidating && (c.file_value == "isotropic" || c.new_value == "isotropic")),
              "element.test", c.new_value + " here, " + c.file_value + " in the file", "the file's while the compression runs (its rows are the isotropic test's)");
      run_.note_change(c.key, c.file_value, c.new_value);
    }
  if (stage_ >= Stage::Loading) {
    specimen_.use_material_law(true);  // the contact lists and their history as the file has them
    set_path();
  }
  run_.log() << "resumed from " << file.string() << " at step " << run_.world().step_count() << " (" << to_string(progress) << ")\n";
}

void ElementTest::record_row() {
  const ElementTestKind kind = config_.element.test;
  if (kind == ElementTestKind::SimpleShear || kind == ElementTestKind::SimpleShearUndrained) {
    // R^2 of the displacement profile since the last row against uniform shear; each row starts
    // the next interval (kept in the restart files, so a resumed run measures the same).
    const World& w = run_.world();
    profile_r2_ = stage_ == Stage::Loading ? periodic_profile_r2(w, profile_start_, profile_bins) : std::nan("");
    profile_start_ = periodic_interval(w);
    if (stage_ == Stage::Loading && span_start_.reduced.empty() && test_strain() >= span_from - 1e-12)
      span_start_ = profile_start_, span_from_strain_ = test_strain();
  }
  history_.record();
  const double strain = test_strain();
  if (broken_bonds_) broken_bonds_->update(run_.world(), strain);  // the bonds broken since the last row
  while (next_row_strain_ <= strain + 1e-12) next_row_strain_ += row_spacing();
  if (stage_ != Stage::Loading) return;  // the peak of the loading path (a gas has none worth quoting)
  // The peak of |q|/p in extension, where q < 0.
  const double ratio = simple_shear(config_.element.test) ? history_.last("shear_stress_ratio")
                                                          : axial_sign() * history_.last("stress_ratio");
  if (ratio > peak_ratio_) peak_ratio_ = ratio, peak_strain_ = strain;
}

void ElementTest::start_loading() {
  const Mat3 h = run_.world().periodic_cell()->matrix();
  for (int k = 0; k < 9; ++k) reference_[static_cast<std::size_t>(k)] = h(k / 3, k % 3);
  next_row_strain_ = 0.0;
  peak_ratio_ = peak_strain_ = 0.0;
  loading_start_time_ = run_.world().time();
  record_row();  // the test's strain 0
  run_.save(run_.folder() / "consolidated.restart");  // the plain specimen: cemented or not from it
  specimen_.use_material_law(true);
  if (config_.cementation.after == CementAfter::Consolidation) cement_now();
  set_path();
  stage_ = Stage::Loading;
}

void ElementTest::run() {
  run_.claim_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  World& w = run_.world();
  const bool isotropic = config_.element.test == ElementTestKind::Isotropic;
  if (stage_ == Stage::Specimen) {
    if (!specimen_.placed()) {
      specimen_.place();
      if (config_.cementation.after == CementAfter::Generation) cement_now();
      const Mat3 h = w.periodic_cell()->matrix();
      for (int k = 0; k < 9; ++k) reference_[static_cast<std::size_t>(k)] = h(k / 3, k % 3);
      next_row_strain_ = 0.0;
    }
    specimen_.run([&] {
      if (isotropic && test_strain() >= next_row_strain_ - 1e-12) record_row();
    });
    if (isotropic) {
      record_row();  // the end state
      stage_ = Stage::Done;
    } else {
      start_loading();
    }
  }
  if (stage_ == Stage::Loading) {
    const double target = test_end();
    double strain = test_strain();
    while (strain < target) {
      w.step(loading_chunk_steps);
      strain = test_strain();
      if (strain >= next_row_strain_ - 1e-12 || strain >= target) {
        record_row();
        std::ostringstream detail;
        detail << to_string(config_.element.test) << " strain " << strain << " of " << target << ", q "
               << history_.last("deviator_stress") / 1e3 << " kPa, p " << history_.last("mean_stress") / 1e3 << " kPa";
        run_.progress("loading", detail.str(), strain, target);
      }
      run_.save_if_due();  // after the chunk's row: a resume goes on with the next chunk
    }
    stage_ = Stage::Done;
  }
  run_.add_wall_seconds(seconds_since(t0));
  if (broken_bonds_) broken_bonds_->write_vtp(w, run_.folder() / "broken_bonds.vtp");
  run_.save(run_.folder() / "final.restart");
  run_.log() << to_string(config_.element.test) << " done at step " << w.step_count() << ": peak stress ratio " << peak_ratio_
             << " at strain " << peak_strain_ << "\n";
}

void ElementTest::cement_now() {
  World& w = run_.world();
  const std::size_t made = cement(w, bond_material(config_.cementation, config_.element.seed), config_.cementation.gap_ratio,
                                  config_.cementation.fraction);
  run_.log() << "cemented at step " << w.step_count() << ": " << made << " bonds ("
             << 2.0 * static_cast<double>(made) / static_cast<double>(w.particles().size()) << " per ball)\n";
}

void ElementTest::add_columns() {
  const World& w = run_.world();
  HistoryLog& h = history_;
  // One measurement a row: the stress (compression positive), the strain and the packing.
  struct RowState {
    Mat3 sigma = Mat3::Zero();
    measure::CellStrain strain;
    measure::CellPacking packing;
  };
  auto row = std::make_shared<RowState>();
  h.before_row([this, row, &w] {
    row->sigma = -measure::cell_stress(w).stress;
    row->strain = measure::cell_strain(reference(), w.periodic_cell()->matrix());
    row->packing = measure::cell_packing(w);
  });
  const auto p = [row] { return row->sigma.trace() / 3; };
  const auto q = [row] { return row->sigma(2, 2) - 0.5 * (row->sigma(0, 0) + row->sigma(1, 1)); };
  h.add("step", [&w] { return static_cast<double>(w.step_count()); });
  h.add("time_s", [&w] { return w.time(); });
  h.add("stage", [this] { return static_cast<double>(stage_); });
  h.add("axial_strain", [row] { return -row->strain.small_strain(2, 2); });
  h.add("volumetric_strain", [row] { return 1.0 - row->strain.deformation_gradient.determinant(); });
  h.add("shear_strain", [row] { return row->strain.deformation_gradient(0, 2); });
  if (config_.element.test == ElementTestKind::CyclicSimpleShear) {  // the other paths' columns stay as they were
    h.add("cycles", [this] { return stage_ == Stage::Specimen ? 0.0 : test_strain(); });
    h.add("shear_strain_yz", [row] { return row->strain.deformation_gradient(1, 2); });
  }
  h.add("mean_stress", p);
  h.add("deviator_stress", q);
  h.add("stress_ratio", [p, q] { return p() > 0.0 ? q() / p() : 0.0; });
  // tau = -sigma_xz (compression positive): the shear stress that resists a positive shear strain.
  h.add("shear_stress", [row] { return -row->sigma(0, 2); });
  h.add("shear_stress_ratio", [row] { return row->sigma(2, 2) > 0.0 ? -row->sigma(0, 2) / row->sigma(2, 2) : 0.0; });
  h.add("void_ratio", [row] { return row->packing.void_ratio; });
  h.add("porosity", [row] { return row->packing.porosity; });
  h.add("coordination", [row] { return row->packing.mechanical_coordination_number; });
  const char* names[6] = {"cell_stress_xx", "cell_stress_yy", "cell_stress_zz", "cell_stress_xy", "cell_stress_xz", "cell_stress_yz"};
  const int index[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 6; ++k) h.add(names[k], [row, a = index[k][0], b = index[k][1]] { return row->sigma(a, b); });
  h.add("unbalanced_force_ratio", [&w] { return w.unbalanced_force_ratio(); });
  const ElementTestKind kind = config_.element.test;
  if (kind == ElementTestKind::SimpleShear || kind == ElementTestKind::SimpleShearUndrained) {  // the others' columns stay
    h.add("profile_r2", [this] { return profile_r2_; });  // measured by record_row()
    for (auto [name, interval] : {std::pair{"profile", &profile_start_}, std::pair{"span", &span_start_}}) {
      run_.keep_points(std::string(name) + "_reference", interval->reduced);
      for (int k = 0; k < 9; ++k) run_.keep(std::string(name) + "_cell_" + std::to_string(k), interval->cell(k / 3, k % 3));
    }
    run_.keep("span_from_strain", span_from_strain_);
  }
  if (config_.cementation.after == CementAfter::None) return;  // a plain run's columns stay as they were
  add_bond_columns(h, w);
}

void ElementTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  j["test"] = to_string(config_.element.test);
  j["balls"] = run_.world().particles().size();
  j["strain_rate_per_s"] = config_.element.test == ElementTestKind::Isotropic ? 0.0 : strain_rate();
  j["peak"] = {{simple_shear(config_.element.test) ? "shear_stress_ratio" : "stress_ratio", peak_ratio_},
               {config_.element.test == ElementTestKind::CyclicSimpleShear ? "cycles" : "strain", peak_strain_}};
  if (config_.element.test == ElementTestKind::CyclicSimpleShear) j["cyclic_period_s"] = cyclic_period();
  if (history_.rows() > 0) {
    io::Json f;
    for (const char* name : {"axial_strain", "volumetric_strain", "shear_strain", "mean_stress", "deviator_stress", "stress_ratio",
                             "shear_stress", "void_ratio", "porosity", "coordination"})
      f[name] = history_.last(name);
    j["final"] = f;
  }
  // The profile of the whole span from 20 % to the end against uniform shear: the NGI cell's
  // "R^2 20-40 %" (summary.json's uniformity there) when the test ends at 40 %.
  if (!span_start_.reduced.empty())
    j["uniformity"] = {{"from_strain", span_from_strain_}, {"to_strain", history_.last("shear_strain")},
                       {"profile_r2", periodic_profile_r2(run_.world(), span_start_, profile_bins)}};
  save_summary(run_, j, resolved_config_json, run_.wall_seconds());
}

}  // namespace dem::lab
