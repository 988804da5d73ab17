// Relative difference between a laboratory curve and a model curve, the study's Table 2/3 metric
// (docs/model.md 8): RD_k = |y_lab(x_k) - y_model(x_k)| / |y_lab(x_k)| on the lab's x points.
//
// The model is interpolated onto the lab points, not the reverse, because the study defines RD
// at the experimental strains. Points the metric cannot judge are skipped and counted rather
// than guessed: lab values near zero (RD explodes there, as the study's 160-260 % volumetric
// values show) and lab points outside the model's x-range (extrapolating a stress-strain curve
// is not a model prediction). The units of x and y are the caller's; RD is dimensionless.
#pragma once

#include <cstddef>
#include <vector>

namespace dem::measure {

/// A sampled curve y(x). x must be strictly increasing, x and y finite and of equal length.
struct Curve {
  std::vector<double> x, y;
};

/// Linear interpolation of `curve` at x. Returns NaN outside [x.front(), x.back()]: clamping
/// would invent a plateau the data do not show. A single-point curve is defined only at its x.
/// Throws InputError for an invalid curve (empty, size mismatch, non-finite, x not strictly
/// increasing) or a non-finite x.
double interpolate(const Curve& curve, double x);

/// Result of relative_difference(). Percentages are 100 * RD.
struct RelativeDifference {
  double max_percent;          ///< max_k RD_k, %
  double mean_percent;         ///< mean_k RD_k over the used points, %
  std::size_t points_used;     ///< lab points that entered the statistics
  std::size_t points_skipped;  ///< lab points with |y_lab| < eps_abs (or y_lab = 0) or outside the model's x-range
};

/// Max and mean relative difference of `model` against `lab` on the lab's x points, the model
/// being linearly interpolated onto them. Lab points with |y_lab| < eps_abs (always when
/// y_lab = 0), or outside the model's x-range, are skipped. eps_abs is in the units of y.
/// Throws InputError for an invalid curve (see interpolate), eps_abs negative or not finite,
/// or when no lab point is usable.
RelativeDifference relative_difference(const Curve& lab, const Curve& model, double eps_abs);

}  // namespace dem::measure
