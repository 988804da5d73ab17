// What the cyclic test keeps in restart files (lab/toolkit/run.hpp), and how a loaded one puts the
// stage under way back: the cycle table from the history rows, the drive as it was.
#include <dem/lab/protocols/cyclic_shear.hpp>

#include <algorithm>
#include <cmath>

#include <dem/core/errors.hpp>
#include <dem/lab/toolkit/broken_bonds.hpp>
#include <dem/lab/toolkit/fabric_log.hpp>
#include <dem/lab/toolkit/snapshots.hpp>

namespace dem::lab {

void CyclicShearTest::keep_state() {
  add_history_columns();
  fabric_ = std::make_unique<FabricLog>(run_.folder() / "cyclic_fabric.csv");
  snapshots_ = std::make_unique<SnapshotWriter>(run_.folder() / "cyclic_snapshots");
  if (specimen_.config().cementation.after != CementAfter::None)
    broken_bonds_ = std::make_unique<BrokenBondLog>(run_, "cyclic_broken_bond_strains");
  std::sort(config_.snapshot_cycles.begin(), config_.snapshot_cycles.end());
  std::sort(config_.fabric_cycles.begin(), config_.fabric_cycles.end());
  // The drive acts from the cyclic test's start on, after the cell's own controller.
  run_.world().add_controller([this](World& w) {
    if (drive_) (*drive_)(w);
  });
  specimen_.set_beyond_consolidation([this] { return step_ != Step::Start; });
  Run& r = run_;
  r.keep("cyclic_step", [this] { return static_cast<double>(step_); }, [this](double v) {
    require(v >= 0 && v <= 5 && v == std::floor(v), "restart file: cyclic_step", v, "0 to 5");
    step_ = static_cast<Step>(static_cast<int>(v));
  });
  r.keep("cyclic_rows_done", rows_done_);
  r.keep("cyclic_phase", [this] { return static_cast<double>(current_phase_); },
         [this](double v) { current_phase_ = static_cast<CyclicPhase>(std::clamp(static_cast<int>(v), 0, 2)); });
  r.keep("cyclic_phase_start_step", phase_start_step_);
  r.keep("cyclic_steps_per_row", steps_per_row_);
  r.keep("cyclic_shear_rate", shear_rate_);
  r.keep("cyclic_sigma_v0", outcome_.vertical_stress_initial);
  r.keep("cyclic_period", outcome_.period);
  r.keep("cyclic_cycles", outcome_.cycles);
  r.keep("cyclic_cycles_to_ru", outcome_.cycles_to_ru);
  r.keep("cyclic_cycles_to_da_strain", outcome_.cycles_to_da_strain);
  r.keep("cyclic_wall_seconds", outcome_.wall_seconds);
  r.keep("cyclic_work", [this] { return drive_ ? drive_->work() : 0.0; }, [this](double v) { loaded_work_ = v; });
  for (int k = 0; k < 2; ++k) {
    r.keep("cyclic_static_stress_" + std::string(1, "xy"[k]), static_stress_[k]);
    r.keep("cyclic_start_strain_" + std::string(1, "xy"[k]), cyclic_start_strain_[k]);
  }
  r.keep("cyclic_post_every", post_every_);
  r.keep("cyclic_next_fabric", next_fabric_);
  r.keep("cyclic_next_snapshot", next_snapshot_);
  r.keep("cyclic_history_rows", [this] { return static_cast<double>(history_.rows()); }, [this](double rows) {
    history_.resume(run_.loaded_folder() / "cyclic_history.csv", static_cast<std::size_t>(rows));
  });
  r.on_load([this] {
    if (step_ == Step::Start) return;
    // The cycle table from the cyclic rows the history keeps (their values are the samples'), the
    // drive as the stage under way left it.
    const io::CsvTable& t = history_.table();
    const auto col = [&](const char* name) { return t.column_index(name); };
    for (const auto& row : t.rows()) {
      if (static_cast<int>(row[col("phase")]) != static_cast<int>(CyclicPhase::Cyclic)) continue;
      CyclicSample s;
      s.cycles = row[col("cycles")];
      s.strain = Vec3(row[col("shear_strain_x")], row[col("shear_strain_y")], 0.0);
      s.stress = Vec3(row[col("shear_stress_x")], row[col("shear_stress_y")], 0.0);
      s.pore_pressure_ratio = row[col("pore_pressure_ratio")];
      s.work = row[col("work")];
      s.coordination_number = row[col("coordination_number")];
      s.mechanical_coordination_number = row[col("mechanical_coordination_number")];
      s.non_coaxiality_deg = row[col("non_coaxiality_deg")];
      s.vertical_stress = row[col("vertical_stress")];
      cycles_.add(s);
    }
    make_drive();
    start_phase(current_phase_, phase_start_step_);
    drive_->resume_work(loaded_work_);
    if (step_ == Step::Done) drive_->hold();
  });
  r.on_claim([this] {
    if (!run_.loaded()) return;
    fabric_->resume(next_fabric_);
    snapshots_->resume(next_snapshot_);
    run_.record_outputs(snapshots_->files());
  });
}

}  // namespace dem::lab
