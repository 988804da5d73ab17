#include <dem/lab/toolkit/periodic_profile.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/core/errors.hpp>
#include <dem/measure/shear_uniformity.hpp>

namespace dem::lab {

namespace {

const PeriodicCell& cell_of(const World& world) {
  const PeriodicCell* cell = world.periodic_cell();
  require(cell != nullptr, "periodic profile", "a World without a periodic cell", "a periodic cell");
  return *cell;
}

}  // namespace

PeriodicInterval periodic_interval(const World& world) {
  const PeriodicCell& cell = cell_of(world);
  const ParticleStore& p = world.particles();
  PeriodicInterval start;
  start.cell = cell.matrix();
  const std::size_t ids = p.id.empty() ? 0 : static_cast<std::size_t>(*std::max_element(p.id.begin(), p.id.end())) + 1;
  start.reduced.assign(ids, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) start.reduced[static_cast<std::size_t>(p.id[i])] = cell.reduced(p.x[i]);
  return start;
}

double periodic_profile_r2(const World& world, const PeriodicInterval& start, int bins) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const PeriodicCell& cell = cell_of(world);
  const Mat3 h0 = start.cell, h1 = cell.matrix();
  const double shear = h1(0, 2) - h0(0, 2);  // m, the affine x-displacement from s_z = 0 to 1
  if (start.reduced.empty() || shear == 0.0) return nan;
  const ParticleStore& p = world.particles();
  std::vector<double> z, u, departure;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i) || static_cast<std::size_t>(p.id[i]) >= start.reduced.size()) continue;
    const Vec3& s0 = start.reduced[static_cast<std::size_t>(p.id[i])];
    if (!s0.allFinite()) continue;
    Vec3 ds = cell.reduced(p.x[i]) - s0;
    for (int a = 0; a < 3; ++a) ds[a] -= std::round(ds[a]);  // the nearest image of the ball's motion
    const Vec3 x0 = h0 * s0, x1 = h1 * (s0 + ds);
    z.push_back(x0.z());
    u.push_back(x1.x() - x0.x());
    departure.push_back(u.back() - ((h1 - h0) * s0).x());
  }
  if (z.size() < 3) return nan;
  double offset = 0.0;  // the rigid translation of the packing, which nothing in a periodic cell fixes
  for (const double d : departure) offset += d;
  offset /= static_cast<double>(departure.size());
  for (double& v : u) v -= offset;
  const double height = h0(2, 2);
  const measure::DisplacementProfile profile = measure::displacement_profile(z, u, 0.0, height, bins);
  // The affine displacement of a point at s: (h1 - h0) s; along x at the bottom (s_z = 0) and top.
  return measure::shear_uniformity(profile, 0.0, height, 0.0, shear).r_squared;
}

}  // namespace dem::lab
