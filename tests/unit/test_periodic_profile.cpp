// The periodic cell's displacement profile (lab/toolkit/periodic_profile.hpp): R^2 against the
// cell's uniform shear is 1 for an affine motion whatever wraps and rigid translations it holds,
// and falls to the value of the bin means for a banded one.
#include <catch2/catch.hpp>

#include <cmath>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/lab/toolkit/periodic_profile.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using namespace dem::lab;

namespace {

constexpr double side = 0.02;  // m, a cubic cell
constexpr int columns = 6;     // balls on a 6 x 6 x 12 grid, one per profile bin in height

// A World of balls at reduced positions s in the cell h (no contacts: far apart, no law needed).
World world_at(const Mat3& h, const std::vector<Vec3>& reduced) {
  World world;
  for (const Vec3& s : reduced) world.add_ball(ball_at(h * s, Vec3::Zero(), 1e-4));
  world.set_periodic_cell(PeriodicCell(h, Vec3::Zero()));
  return world;
}

std::vector<Vec3> grid() {
  std::vector<Vec3> s;
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < columns; ++j)
      for (int i = 0; i < columns; ++i) s.emplace_back((i + 0.5) / columns, (j + 0.5) / columns, (k + 0.5) / 12);
  return s;
}

}  // namespace

TEST_CASE("periodic profile: an affine shear with wraps and a rigid shift is uniform; a band is not", "[lab][periodic]") {
  const Mat3 h0 = side * Mat3::Identity();
  const std::vector<Vec3> s0 = grid();
  const PeriodicInterval start = periodic_interval(world_at(h0, s0));
  Mat3 h1 = h0;
  h1(0, 2) = 0.1 * side;  // 10 % shear: x moves by 0.1 s_z side

  // The same reduced positions in the sheared cell are the affine motion; shift every ball by a
  // rigid 3 mm along x (no plate fixes the packing) and wrap the ones that leave through x = side.
  std::vector<Vec3> s1 = s0;
  for (Vec3& s : s1) s.x() = std::fmod(s.x() + 0.003 / side, 1.0);
  CHECK(periodic_profile_r2(world_at(h1, s1), start, 12) == Approx(1.0).margin(1e-12));
  // A ball that leaves through the top face comes back at the bottom: the nearest image of its motion.
  s1.back().z() -= 1.0;
  CHECK(periodic_profile_r2(world_at(h1, s1), start, 12) == Approx(1.0).margin(1e-12));

  // A band: the upper half slides a further 1 mm along x. The bin means are the affine line plus
  // 1 mm above mid-height; after the mean departure (0.5 mm) is removed they are off the line by
  // +-0.5 mm, so R^2 = 1 - 12 (0.5 mm)^2 / SS_tot with SS_tot the spread of the bin means.
  std::vector<Vec3> banded = s0;
  for (Vec3& s : banded)
    if (s.z() > 0.5) s.x() += 0.001 / side;
  const double r2 = periodic_profile_r2(world_at(h1, banded), start, 12);
  double mean = 0.0, ss = 0.0;
  std::vector<double> bin(12);
  for (int k = 0; k < 12; ++k) bin[static_cast<std::size_t>(k)] = 0.1 * side * (k + 0.5) / 12 + (k >= 6 ? 0.0005 : -0.0005);
  for (const double b : bin) mean += b / 12;
  for (const double b : bin) ss += (b - mean) * (b - mean);
  CHECK(r2 == Approx(1.0 - 12 * 0.0005 * 0.0005 / ss).epsilon(1e-9));
  CHECK(r2 < 0.99);
  // No shear between the rows: nothing to compare with.
  CHECK(std::isnan(periodic_profile_r2(world_at(h0, s0), start, 12)));
}
