// The pieces of the cyclic simple-shear test that need no simulation: the loading paths, the
// per-cycle table and its double-amplitude strain, and the [cyclic] keys' one declaration.
#include <catch2/catch.hpp>

#include <cmath>

#include <dem/core/errors.hpp>
#include <dem/io/config.hpp>
#include <dem/lab/toolkit/cycle_log.hpp>
#include <dem/lab/toolkit/cyclic_path.hpp>
#include <dem/lab/protocols/cyclic_shear_config.hpp>

#include "support/temp_dir.hpp"

using namespace dem;
using namespace dem::lab;
using Catch::Matchers::Contains;

TEST_CASE("cyclic path: the drawn shapes at known cycle fractions", "[cyclic]") {
  const Vec3 d(std::cos(pi / 6), std::sin(pi / 6), 0.0), e(-std::sin(pi / 6), std::cos(pi / 6), 0.0);  // 30 deg
  const CyclicPath sine(CyclicShape::Sine, 30.0, 0.5);
  CHECK((sine.at(0.25) - d).norm() < 1e-15);
  CHECK((sine.at(0.75) + d).norm() < 1e-15);
  CHECK(sine.at(0.5).norm() < 1e-15);
  const CyclicPath circle(CyclicShape::Circle, 30.0, 0.5);
  // The ramp: half the radius at an eighth of a cycle, the full radius from a quarter on.
  CHECK(circle.at(0.125).norm() == Approx(0.5).margin(1e-15));
  double turned = 0.0;
  Vec3 previous = circle.at(1.0);
  for (int k = 1; k <= 400; ++k) {
    const Vec3 v = circle.at(1.0 + k / 400.0);
    CHECK(v.norm() == Approx(1.0).margin(1e-14));
    turned += std::atan2(previous.cross(v).z(), previous.dot(v));
    previous = v;
  }
  CHECK(turned == Approx(-2 * pi).margin(1e-12));  // one turn per cycle, clockwise seen from above
  const CyclicPath ellipse(CyclicShape::Ellipse, 30.0, 0.5);
  CHECK((ellipse.at(1.25) - d).norm() < 1e-14);
  CHECK((ellipse.at(1.0) - 0.5 * e).norm() < 1e-14);
  const CyclicPath eight(CyclicShape::Figure8, 30.0, 0.5);
  CHECK((eight.at(0.125) - (std::sqrt(0.5) * d + 0.5 * e)).norm() < 1e-14);
  CHECK((eight.at(0.375) - (std::sqrt(0.5) * d - 0.5 * e)).norm() < 1e-14);
  CHECK(std::isinf(eight.length_cycles()));
  CHECK_THROWS_WITH(cyclic_shape_from("square", "cyclic.path"), Contains("cyclic.path") && Contains("figure8"));
}

TEST_CASE("cyclic path: a series interpolates its rows and ends with the last", "[cyclic]") {
  dem::testing::TempDir dir("cyclic_series");
  const CyclicPath by_cycle = CyclicPath::from_csv(dir.write("s.csv", "cycle,x,y\n0,0,0\n0.5,0.2,-0.1\n2,0.2,0.3\n"), 1.0);
  CHECK(by_cycle.absolute());
  CHECK(by_cycle.length_cycles() == 2.0);
  CHECK((by_cycle.at(0.25) - Vec3(0.1, -0.05, 0)).norm() < 1e-15);
  CHECK((by_cycle.at(1.25) - Vec3(0.2, 0.1, 0)).norm() < 1e-15);
  CHECK((by_cycle.at(5.0) - Vec3(0.2, 0.3, 0)).norm() < 1e-15);
  // A time column in seconds, over a period of 0.01 s.
  const CyclicPath by_time = CyclicPath::from_csv(dir.write("t.csv", "time,x,y\n0,0,0\n0.02,0.4,0\n"), 0.01);
  CHECK(by_time.length_cycles() == Approx(2.0));
  CHECK(by_time.at(1.0).x() == Approx(0.2));
  CHECK_THROWS_WITH(CyclicPath::from_csv(dir.write("bad.csv", "cycle,x,y\n0,0,0\n0,1,0\n"), 1.0),
                    Contains("bad.csv") && Contains("increasing"));
  CHECK_THROWS_WITH(CyclicPath::from_csv(dir.write("cols.csv", "n,x,y\n0,0,0\n1,1,0\n"), 1.0), Contains("'cycle'"));
}

TEST_CASE("cycle log: peaks, double amplitude, pore pressure and work of sampled loops", "[cyclic]") {
  // gamma = g sin(2 pi N) along d, tau = t sin(2 pi N + delta): the loop's area is pi g t sin(delta)
  // (the work fed in below is that integral, exact), and 40 rows a cycle hit the peaks exactly.
  const double g = 0.004, t = 2e4, delta = 0.3;
  const int rows = 40;
  CycleLog log(Vec3::UnitX(), rows);
  for (int k = 0; k <= 2 * rows + 10; ++k) {
    const double n = static_cast<double>(k) / rows, w = 2 * pi * n;
    CyclicSample s;
    s.cycles = n;
    s.strain = Vec3(g * std::sin(w), 0, 0);
    s.stress = Vec3(t * std::sin(w + delta), 0, 0);
    s.pore_pressure_ratio = 0.1 * n;
    // integral of t sin(w + delta) g cos(w) dw from 0 to 2 pi n
    s.work = g * t * (0.5 * std::sin(delta) * w + 0.25 * (std::cos(delta) - std::cos(2 * w + delta)));
    s.non_coaxiality_deg = k % 2 == 0 ? -4.0 : 6.0;
    log.add(s);
  }
  const auto& cycles = log.cycles();
  REQUIRE(cycles.size() == 3);
  for (int c = 0; c < 2; ++c) {
    const CycleRow& r = cycles[static_cast<std::size_t>(c)];
    CHECK(r.cycle == c + 1);
    CHECK(r.complete);
    CHECK(r.strain_max == Approx(g).epsilon(1e-12));
    CHECK(r.strain_min == Approx(-g).epsilon(1e-12));
    CHECK(r.double_amplitude_strain == Approx(2 * g).epsilon(1e-12));
    CHECK(r.stress_max <= t);
    CHECK(r.stress_max == Approx(t).epsilon(1 - std::cos(pi / rows)));  // within half a row of the peak
    CHECK(r.energy == Approx(pi * g * t * std::sin(delta)).epsilon(1e-12));
    CHECK(r.pore_pressure_ratio_end == Approx(0.1 * (c + 1)));
    CHECK(r.non_coaxiality_deg == Approx(5.0));
  }
  CHECK_FALSE(cycles[2].complete);
  CHECK(log.double_amplitude_strain() == Approx(2 * g).epsilon(1e-12));
  CHECK_THROWS_AS(log.add(CyclicSample{}), InputError);  // N went back
}

TEST_CASE("cyclic keys: one declaration, the schema's defaults are the struct's", "[cyclic][config]") {
  io::Schema schema;
  add_cyclic_shear_keys(schema);
  const io::Config defaults(schema);
  CHECK(cyclic_shear_config(defaults) == CyclicShearConfig{});
  // Key = field name: a value set by key lands in the field of that name.
  io::Config c(schema);
  c.set("cyclic.csr", "0.15");
  c.set("cyclic.path", "figure8");
  c.set("cyclic.fabric_cycles", "1,5");
  const CyclicShearConfig set = cyclic_shear_config(c);
  CHECK(set.csr == 0.15);
  CHECK(set.path == CyclicShape::Figure8);
  CHECK(set.fabric_cycles == std::vector<double>{1, 5});
  CHECK_THROWS_WITH(c.set("cyclic.path", "square"), Contains("cyclic.path") && Contains("square"));
  CHECK_THROWS_WITH(c.set("cyclic.csr", "-0.1"), Contains("cyclic.csr"));
  c.set("cyclic.path", "series");
  CHECK_THROWS_WITH(cyclic_shear_config(c), Contains("cyclic.series_file"));
}
