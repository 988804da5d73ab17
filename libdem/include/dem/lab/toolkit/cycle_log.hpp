// The per-cycle table of a cyclic shear test (cycles.csv) and the double-amplitude strain its stop
// criterion reads, from the history rows in order. A sample at N cycles belongs to cycle
// ceil(N) (N = 0: the start); each cycle also holds the sample that ended the previous one, so
// its peak-to-peak values and its work span the whole cycle.
//
// Columns (SI; stresses and strains are components along the path's direction d, except the
// magnitudes):
//   cycle, stress_max, stress_min (Pa), stress_magnitude_max (Pa, |tau|), strain_max, strain_min,
//   double_amplitude_strain (-: the largest distance between two strain vectors of the cycle, the
//   peak-to-peak strain of a one-directional cycle, the diameter of a circular one),
//   pore_pressure_ratio_max, pore_pressure_ratio_end (-), energy (J/m^3: the work tau . d gamma
//   the plates did on the specimen per unit volume over the cycle, the loop's area), and at the
//   cycle's last sample coordination_number, mechanical_coordination_number, vertical_stress (Pa);
//   non_coaxiality_deg (the mean of |non-coaxiality| over the cycle's samples that have one),
//   complete (1, or 0 for the cycle the run stopped in).
#pragma once

#include <string>
#include <vector>

#include <dem/core/math.hpp>

namespace dem::lab {

/// One history row's values, as CycleLog reads them.
struct CyclicSample {
  double cycles = 0.0;                 // -, N since the cyclic stage began
  Vec3 strain = Vec3::Zero();          // -, shear strain vector (horizontal)
  Vec3 stress = Vec3::Zero();          // Pa, shear stress vector on the top plate
  double pore_pressure_ratio = 0.0;    // -, r_u
  double work = 0.0;                   // J/m^3, cumulative tau . d gamma since the stage began
  double coordination_number = 0.0;    // -
  double mechanical_coordination_number = 0.0;  // -
  double non_coaxiality_deg = 0.0;     // deg, NaN where undefined
  double vertical_stress = 0.0;        // Pa
};

struct CycleRow {
  int cycle = 0;
  double stress_max = 0, stress_min = 0, stress_magnitude_max = 0;
  double strain_max = 0, strain_min = 0, double_amplitude_strain = 0;
  double pore_pressure_ratio_max = 0, pore_pressure_ratio_end = 0;
  double energy = 0;
  double coordination_number = 0, mechanical_coordination_number = 0, vertical_stress = 0;
  double non_coaxiality_deg = 0;
  bool complete = false;
};

class CycleLog {
 public:
  /// `direction` (unit, horizontal) is the one the components are taken along; a window of
  /// `rows_per_cycle` (>= 2) samples is one period for double_amplitude_strain().
  CycleLog(const Vec3& direction, int rows_per_cycle);

  /// Adds the next sample (N not decreasing, else InputError).
  void add(const CyclicSample& sample);
  /// Every cycle begun so far; the last one is incomplete until a sample reaches its end.
  const std::vector<CycleRow>& cycles() const { return rows_; }
  /// The largest distance between two strain vectors over the last period of samples (-).
  double double_amplitude_strain() const;

  static std::vector<std::string> columns();
  static std::vector<double> values(const CycleRow& row);

 private:
  void finish_row();

  Vec3 d_;
  int rows_per_cycle_;
  std::vector<CyclicSample> window_;   // the last rows_per_cycle + 1 samples
  std::vector<CyclicSample> current_;  // the samples of the current cycle, its start included
  std::vector<CycleRow> rows_;
};

/// The largest distance between two of the points (0 for fewer than two).
double largest_distance(const std::vector<Vec3>& points);

}  // namespace dem::lab
