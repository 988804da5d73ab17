// The loading path of a cyclic simple-shear test in the horizontal plane: where the shear stress
// (stress control) or the shear strain (strain control) should be at a given number of cycles,
// in units of the amplitude. The shapes are the ones bi-directional devices run (docs/cyclic-shear.md):
//
//   sine     a (sin 2 pi N) along d                        one-directional
//   circle   a (sin 2 pi N d + cos 2 pi N e)               |value| = a while it turns 360 deg per cycle
//   ellipse  a (sin 2 pi N d + q cos 2 pi N e)             axes a along d, q a across
//   figure8  a (sin 2 pi N d + q sin 4 pi N e)             two lobes across d per cycle
//   series   (x, y)(N) from a CSV file, linear in between  any path, in amplitude units or absolute
//
// with N the cycles since the start of the cyclic stage, d the unit vector at direction_deg from
// +x towards +y and e = d turned +90 deg. The circle and the ellipse turn from e towards d:
// clockwise seen from above (+z). The circle and the ellipse start off the origin; their
// value grows linearly from zero over the first quarter cycle (ramp) so the plate is not asked to
// jump. A series file has a header line and three columns: "cycle" (N, -) or "time" (s), then
// "x" and "y"; its values are used as they are (CSR or strain), N beyond its last row holds the
// last value and ends the path (finished()).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <dem/core/math.hpp>

namespace dem::lab {

enum class CyclicShape { Sine, Circle, Ellipse, Figure8, Series };

/// "sine", "circle", "ellipse", "figure8", "series"; InputError naming `key` for another name.
CyclicShape cyclic_shape_from(const std::string& name, const std::string& key);
std::string to_string(CyclicShape shape);

class CyclicPath {
 public:
  /// A drawn shape (not Series). `minor_ratio` is q of the ellipse and figure-8 (>= 0).
  CyclicPath(CyclicShape shape, double direction_deg, double minor_ratio);
  /// A series read from `file`; `period` (s, > 0) converts a "time" column into cycles. InputError
  /// names the file for a missing column, fewer than two rows, or cycles that do not increase.
  static CyclicPath from_csv(const std::filesystem::path& file, double period);

  /// The target at N cycles (N >= 0), horizontal (z = 0): unit amplitude for a drawn shape.
  Vec3 at(double cycles) const;
  /// The cycles the path lasts: infinite for a drawn shape, the last row's for a series.
  double length_cycles() const;
  /// true for a series: its values are CSR or strains themselves, not multiples of an amplitude.
  bool absolute() const { return shape_ == CyclicShape::Series; }
  CyclicShape shape() const { return shape_; }

 private:
  CyclicShape shape_ = CyclicShape::Sine;
  Vec3 d_ = Vec3::UnitX(), e_ = Vec3::UnitY();
  double q_ = 0.0;
  std::vector<double> cycles_, x_, y_;  // series
};

}  // namespace dem::lab
