// The cyclic test's outputs: the columns of cyclic_history.csv, a row of it (and the cycle log's
// sample), cycles.csv, summary.json.
#include <dem/lab/protocols/cyclic_shear.hpp>

#include <cmath>

#include <dem/lab/toolkit/broken_bonds.hpp>
#include <dem/measure/shear_uniformity.hpp>

#include "../../io/json_file.hpp"
#include "../toolkit/run_summary.hpp"

namespace dem::lab {

namespace {

Vec3 horizontal(Vec3 v) {
  v.z() = 0.0;
  return v;
}

}  // namespace

void CyclicShearTest::add_history_columns() {
  const ShearState& s = row_.state;
  HistoryLog& h = history_;
  const double& sigma_v0 = outcome_.vertical_stress_initial;
  const double& height_c = outcome_.consolidated_height;
  h.add("time", [&s] { return s.time; });
  h.add("step", [this] { return static_cast<double>(run_.world().step_count()); });
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
  if (specimen_.config().cementation.after != CementAfter::None) add_bond_columns(h, run_.world());  // only when cemented
}

void CyclicShearTest::record_row() {
  const World& w = run_.world();
  row_.state = specimen_.measure(horizontal_direction(specimen_.config().shear.legs().front().direction_deg));
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
  if (broken_bonds_) broken_bonds_->update(w, s.shear_strain);  // the bonds broken in the last row
  history_.record();
  last_sample_ = sample;
  last_double_amplitude_ = row_.double_amplitude;
}

void CyclicShearTest::write_outputs() const {
  io::CsvTable table(CycleLog::columns(), io::Missing::Allowed);  // cyclic_history.csv: saved by every row
  for (const CycleRow& r : cycles_.cycles()) table.add_row(CycleLog::values(r));
  table.save(run_.folder() / "cycles.csv");
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
  save_summary(run_, j, resolved_config_json, outcome_.wall_seconds);
}

}  // namespace dem::lab
