// Particle-size distributions for specimen generation (docs/model.md 7). The study's ball counts are
// reproduced by diameters uniform *by number* on [0.7, 1.2] mm times the size scale (docs/model.md
// 7.2: 111,122 / 13,890 / 1,736 balls for 1D / 2D / 4D at porosity 0.37, within 1.2 % of the
// study's), while the real sand grading by mass needs 60-80 % more balls. Both are offered.
#pragma once

#include <random>
#include <string>
#include <vector>

namespace dem::lab {

enum class Sampling {
  NumberUniform,  // diameter uniform by number on [d_min, d_max] (PFC `ball distribute` style)
  MassGrading,    // diameters whose mass distribution follows a sieve curve
};

struct Grading {
  Sampling sampling = Sampling::NumberUniform;
  double d_min = 0.7e-3;  // m, before scaling (number-uniform)
  double d_max = 1.2e-3;  // m, before scaling
  std::vector<double> sieve_diameters;   // m, increasing (mass grading)
  std::vector<double> passing_fraction;  // -, mass fraction finer than each sieve, 0 ... 1
  double scale = 1.0;                    // -, size multiplier (1D, 2D, 4D = 1, 2, 4)

  /// Throws InputError naming the key (prefix `where`) for an unusable distribution.
  void validate(const std::string& where = "grading") const;
  /// Smallest and largest diameter that can be drawn, after scaling, m.
  double smallest() const;
  double largest() const;
  bool operator==(const Grading&) const = default;
};

/// Leighton Buzzard sand fraction B by mass: 0.6-1.2 mm, D10 0.65 mm, D50 0.82 mm, D60 0.897 mm
/// (Cu 1.38), log-linear between these sieves.
Grading leighton_buzzard_b_by_mass();

/// Draws diameters (m) until their total volume reaches `solid_volume` (m^3); the last one
/// crosses it. Deterministic for a given generator state.
std::vector<double> sample_diameters(const Grading& grading, double solid_volume, std::mt19937_64& rng);

}  // namespace dem::lab
