// How uniformly a periodic cell shears: the displacement profile of a simple shear (L_xz) over the
// interval between two history rows, binned by height, and its R^2 against the uniform shear of
// the cell (measure/shear_uniformity.hpp), the measure the NGI cell's history reports as
// profile_r2. Without plates the profile is fixed only up to a rigid translation of the packing,
// so the balls' mean departure from the affine displacement is taken out first.
//
// Positions are kept in reduced coordinates s = h^-1 (x - origin), by ball id: a ball that left
// through a face between the rows comes back by whole cells (the nearest image of its motion), so
// its displacement is the real one, not the wrap's jump.
#pragma once

#include <vector>

#include <dem/core/math.hpp>
#include <dem/core/world.hpp>

namespace dem::lab {

/// The start of an interval: each ball's reduced position by id (NaN for ids not in use) and the
/// cell matrix h (m). Empty positions: no row yet.
struct PeriodicInterval {
  std::vector<Vec3> reduced;
  Mat3 cell = Mat3::Identity();
};

/// The interval that starts now. InputError without a periodic cell.
PeriodicInterval periodic_interval(const World& world);

/// R^2 of the x-displacement profile since `start` (`bins` height bins over the cell) against the
/// cell's affine shear, as measure::shear_uniformity defines it; NaN without a start, with fewer
/// than three non-empty bins, or when the cell did not shear (no change of h_xz).
double periodic_profile_r2(const World& world, const PeriodicInterval& start, int bins);

}  // namespace dem::lab
