// How uniformly a simple-shear specimen shears (docs/model.md 8.1), as a part that adds its
// columns to a protocol's history: the horizontal displacement of the balls along the shear
// direction over each interval between two rows, binned by height, its R^2 against uniform simple
// shear and the strains of the thirds; the plates' horizontal displacements; the stress ratio and
// porosity of three layer spheres; the porosity of the profile's bins.
//
// The probe keeps the positions at the last row (the start of the current interval); a protocol
// that resumes from a restart file saves and restores them (interval(), resume_interval()).
#pragma once

#include <functional>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/measure/shear_uniformity.hpp>

namespace dem::lab {

/// The start of a profile interval: positions by ball id (NaN for pebbles and ids not in use), and
/// the plates' displacements then. Empty positions: no row yet, so the next row has no profile.
struct ProfileInterval {
  std::vector<Vec3> positions;
  Vec3 bottom = Vec3::Zero(), top = Vec3::Zero();
};

class UniformityProbe {
 public:
  /// `bins` height bins between the plates (>= 3).
  UniformityProbe(const World& world, const ShearCell& cell, int bins);

  /// Adds the probe's columns to `log`: profile_r2, strain_bottom_third, strain_middle_third,
  /// strain_top_third, top_bottom_strain_ratio, bottom_dx, bottom_dy, top_dx, top_dy,
  /// layer_{bottom,middle,top}_{stress_ratio,porosity}, layer_stress_spread ((max - min) / mean
  /// of the three layers' vertical stresses: a stress-concentration index), profile_u_1..bins (m),
  /// profile_porosity_1..bins. `direction` gives the shear direction at a row (a unit vector in
  /// x-y). Each row starts the next interval. Values not defined at a row are NaN: the first row
  /// and a row after a pause (the plates did not move apart) have no profile; a layer sphere that
  /// holds no ball has no stress ratio.
  void add_columns(HistoryLog& log, std::function<Vec3()> direction);

  const ProfileInterval& interval() const { return interval_; }
  /// The interval, for a protocol that keeps it in its restart files (lab/toolkit/run.hpp).
  ProfileInterval& interval() { return interval_; }
  void resume_interval(ProfileInterval interval) { interval_ = std::move(interval); }

 private:
  void measure(const Vec3& d, std::vector<double>& row);

  const World& world_;
  const ShearCell& cell_;
  int bins_;
  ProfileInterval interval_;
};

/// The uniformity of the profile summed over the rows of a history from `from` to `to` shear
/// strain (each row's strain within half an `every_strain` of slack), against uniform simple shear
/// with the plates' displacements along `direction` over that span.
struct SpanUniformity {
  bool found = false;                         // the span holds at least one row with a row before it
  double from_strain = 0.0, to_strain = 0.0;  // -, strains at the span's ends as recorded
  measure::ShearUniformity uniformity{};
  bool every_bin_has_balls = true;  // no bin was empty at a row of the span
};
SpanUniformity span_uniformity(const io::CsvTable& history, int bins, double from, double to, double every_strain,
                               const Vec3& direction);

}  // namespace dem::lab
