#include <dem/lab/toolkit/cycle_log.hpp>

#include <algorithm>
#include <cmath>

#include <dem/core/errors.hpp>

namespace dem::lab {

double largest_distance(const std::vector<Vec3>& points) {
  double largest = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j) largest = std::max(largest, (points[i] - points[j]).norm());
  return largest;
}

CycleLog::CycleLog(const Vec3& direction, int rows_per_cycle) : d_(direction), rows_per_cycle_(rows_per_cycle) {
  require(std::abs(direction.norm() - 1.0) < 1e-9 && direction.z() == 0.0, "cycle log direction", direction.norm(),
          "a horizontal unit vector");
  require(rows_per_cycle >= 2, "cyclic.rows_per_cycle", rows_per_cycle, ">= 2");
}

void CycleLog::add(const CyclicSample& s) {
  require(window_.empty() || s.cycles >= window_.back().cycles, "cyclic sample N", s.cycles,
          ">= the previous sample's " + (window_.empty() ? std::string() : std::to_string(window_.back().cycles)));
  window_.push_back(s);
  if (window_.size() > static_cast<std::size_t>(rows_per_cycle_) + 1) window_.erase(window_.begin());
  // Cycle k holds N in (k - 1, k]; a tolerance keeps N = k - 1e-13 (rounding) in cycle k.
  const int cycle = std::max(1, static_cast<int>(std::ceil(s.cycles - 1e-9)));
  if (s.cycles <= 1e-9 && rows_.empty()) {  // the start: the first cycle's first sample
    current_ = {s};
    return;
  }
  if (rows_.empty() || cycle > rows_.back().cycle) {
    if (!rows_.empty()) rows_.back().complete = true;
    const CyclicSample start = current_.empty() ? s : current_.back();
    current_ = {start};
    rows_.push_back(CycleRow{});
    rows_.back().cycle = cycle;
  }
  current_.push_back(s);
  finish_row();
  if (std::abs(s.cycles - cycle) <= 1e-9) rows_.back().complete = true;
}

void CycleLog::finish_row() {
  CycleRow& r = rows_.back();
  const CyclicSample& first = current_.front();
  const CyclicSample& last = current_.back();
  r.stress_max = r.strain_max = r.pore_pressure_ratio_max = -INFINITY;
  r.stress_min = r.strain_min = INFINITY;
  r.stress_magnitude_max = 0.0;
  std::vector<Vec3> strains;
  double coaxiality_sum = 0.0;
  int coaxiality_count = 0;
  for (const CyclicSample& s : current_) {
    r.stress_max = std::max(r.stress_max, s.stress.dot(d_));
    r.stress_min = std::min(r.stress_min, s.stress.dot(d_));
    r.stress_magnitude_max = std::max(r.stress_magnitude_max, s.stress.norm());
    r.strain_max = std::max(r.strain_max, s.strain.dot(d_));
    r.strain_min = std::min(r.strain_min, s.strain.dot(d_));
    r.pore_pressure_ratio_max = std::max(r.pore_pressure_ratio_max, s.pore_pressure_ratio);
    strains.push_back(s.strain);
    if (&s != &first && std::isfinite(s.non_coaxiality_deg)) coaxiality_sum += std::abs(s.non_coaxiality_deg), ++coaxiality_count;
  }
  r.double_amplitude_strain = largest_distance(strains);
  r.pore_pressure_ratio_end = last.pore_pressure_ratio;
  r.energy = last.work - first.work;
  r.coordination_number = last.coordination_number;
  r.mechanical_coordination_number = last.mechanical_coordination_number;
  r.vertical_stress = last.vertical_stress;
  r.non_coaxiality_deg = coaxiality_count > 0 ? coaxiality_sum / coaxiality_count : NAN;
}

double CycleLog::double_amplitude_strain() const {
  std::vector<Vec3> strains;
  for (const CyclicSample& s : window_) strains.push_back(s.strain);
  return largest_distance(strains);
}

std::vector<std::string> CycleLog::columns() {
  return {"cycle", "stress_max", "stress_min", "stress_magnitude_max", "strain_max", "strain_min", "double_amplitude_strain",
          "pore_pressure_ratio_max", "pore_pressure_ratio_end", "energy", "coordination_number",
          "mechanical_coordination_number", "vertical_stress", "non_coaxiality_deg", "complete"};
}

std::vector<double> CycleLog::values(const CycleRow& r) {
  return {static_cast<double>(r.cycle), r.stress_max, r.stress_min, r.stress_magnitude_max, r.strain_max, r.strain_min,
          r.double_amplitude_strain, r.pore_pressure_ratio_max, r.pore_pressure_ratio_end, r.energy, r.coordination_number,
          r.mechanical_coordination_number, r.vertical_stress, r.non_coaxiality_deg, r.complete ? 1.0 : 0.0};
}

}  // namespace dem::lab
