// Interpolation and the relative-difference metric (docs/model.md 8) on curves small enough to
// compute by hand. Expected values are exact decimals, so the tolerance only absorbs rounding
// of a few double operations (1e-12).
#include <dem/core/errors.hpp>
#include <dem/measure/relative_difference.hpp>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

using dem::InputError;
using dem::measure::Curve;
using dem::measure::interpolate;
using dem::measure::relative_difference;

namespace {
constexpr double tol = 1e-12;
const Curve lab{{0.0, 1.0, 2.0, 3.0, 4.0}, {0.0, 10.0, 20.0, 40.0, 50.0}};
}  // namespace

TEST_CASE("interpolate: linear between nodes, exact at nodes, NaN outside", "[measure]") {
  CHECK(interpolate(lab, 0.0) == 0.0);
  CHECK(interpolate(lab, 3.0) == 40.0);
  CHECK(interpolate(lab, 4.0) == 50.0);
  CHECK(interpolate(lab, 2.25) == Approx(25.0).margin(tol));  // 20 + 0.25 * (40 - 20)
  CHECK(interpolate(lab, 0.1) == Approx(1.0).margin(tol));    // 0 + 0.1 * 10
  CHECK(std::isnan(interpolate(lab, -0.001)));
  CHECK(std::isnan(interpolate(lab, 4.5)));
  const Curve single{{2.0}, {7.0}};
  CHECK(interpolate(single, 2.0) == 7.0);
  CHECK(std::isnan(interpolate(single, 2.1)));
}

TEST_CASE("relative difference: model covering the lab range", "[measure]") {
  // model: y = 11 x on [0, 2], then 22 + 9 (x - 2) on [2, 4].
  const Curve model{{0.0, 2.0, 4.0}, {0.0, 22.0, 40.0}};
  // x = 0: y_lab = 0 -> skipped.
  // x = 1: model 11 -> |10 - 11| / 10 = 0.1
  // x = 2: model 22 -> |20 - 22| / 20 = 0.1
  // x = 3: model 31 -> |40 - 31| / 40 = 0.225
  // x = 4: model 40 -> |50 - 40| / 50 = 0.2
  // max = 22.5 %, mean = (0.1 + 0.1 + 0.225 + 0.2) / 4 = 0.15625 -> 15.625 %
  const auto rd = relative_difference(lab, model, 1e-9);
  CHECK(rd.max_percent == Approx(22.5).margin(tol));
  CHECK(rd.mean_percent == Approx(15.625).margin(tol));
  CHECK(rd.points_used == 4);
  CHECK(rd.points_skipped == 1);
}

TEST_CASE("relative difference: lab points outside the model range are skipped", "[measure]") {
  // model: y = 6 + 10 (x - 0.5) on [0.5, 2.5].
  const Curve model{{0.5, 2.5}, {6.0, 26.0}};
  // x = 0, 3, 4: outside [0.5, 2.5] -> skipped (x = 0 also has y_lab = 0).
  // x = 1: model 6 + 5 = 11 -> |10 - 11| / 10 = 0.1
  // x = 2: model 6 + 15 = 21 -> |20 - 21| / 20 = 0.05
  // max = 10 %, mean = 0.075 -> 7.5 %
  const auto rd = relative_difference(lab, model, 1e-9);
  CHECK(rd.max_percent == Approx(10.0).margin(tol));
  CHECK(rd.mean_percent == Approx(7.5).margin(tol));
  CHECK(rd.points_used == 2);
  CHECK(rd.points_skipped == 3);
}

TEST_CASE("relative difference: small and negative lab values", "[measure]") {
  const Curve lab_small{{1.0, 2.0, 3.0}, {0.001, -0.5, 2.0}};
  const Curve model{{0.0, 4.0}, {0.0, 4.0}};  // y = x
  // eps_abs = 0.01:
  // x = 1: |0.001| < 0.01 -> skipped
  // x = 2: |-0.5 - 2| / |-0.5| = 5 -> 500 %
  // x = 3: |2 - 3| / 2 = 0.5 -> 50 %
  // max = 500 %, mean = (5 + 0.5) / 2 = 2.75 -> 275 %
  const auto rd = relative_difference(lab_small, model, 0.01);
  CHECK(rd.max_percent == Approx(500.0).margin(1e-10));
  CHECK(rd.mean_percent == Approx(275.0).margin(1e-10));
  CHECK(rd.points_used == 2);
  CHECK(rd.points_skipped == 1);
  // eps_abs = 0 keeps x = 1: |0.001 - 1| / 0.001 = 999 -> 99900 %; mean (999 + 5 + 0.5)/3 = 334.8333...
  const auto all = relative_difference(lab_small, model, 0.0);
  CHECK(all.points_used == 3);
  CHECK(all.max_percent == Approx(99900.0).epsilon(1e-12));
  CHECK(all.mean_percent == Approx(100.0 * 1004.5 / 3.0).epsilon(1e-12));
}

TEST_CASE("relative difference: identical curves give zero", "[measure]") {
  const auto rd = relative_difference(lab, lab, 0.0);  // y_lab = 0 at x = 0 is still skipped
  CHECK(rd.max_percent == 0.0);
  CHECK(rd.mean_percent == 0.0);
  CHECK(rd.points_used == 4);
  CHECK(rd.points_skipped == 1);
}

TEST_CASE("relative difference and interpolate: bad input", "[measure]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Curve model{{0.0, 4.0}, {0.0, 4.0}};
  SECTION("x not strictly increasing names the index and both values") {
    const Curve repeated{{0.0, 1.0, 1.0}, {1.0, 2.0, 3.0}};
    CHECK_THROWS_AS(relative_difference(repeated, model, 0.0), InputError);
    CHECK_THROWS_WITH(relative_difference(repeated, model, 0.0),
                      Catch::Contains("lab.x[2] = 1") && Catch::Contains("lab.x[1] = 1"));
    const Curve decreasing{{0.0, 3.0, 2.0}, {1.0, 2.0, 3.0}};
    CHECK_THROWS_WITH(relative_difference(lab, decreasing, 0.0), Catch::Contains("model.x[2] = 2"));
    CHECK_THROWS_AS(interpolate(decreasing, 1.0), InputError);
  }
  SECTION("NaN in a curve, in x or in eps_abs") {
    const Curve nan_y{{0.0, 1.0}, {1.0, nan}};
    CHECK_THROWS_WITH(relative_difference(nan_y, model, 0.0), Catch::Contains("lab.y[1]"));
    CHECK_THROWS_AS(interpolate(model, nan), InputError);
    CHECK_THROWS_WITH(relative_difference(lab, model, nan), Catch::Contains("eps_abs"));
    CHECK_THROWS_AS(relative_difference(lab, model, -1.0), InputError);
  }
  SECTION("size mismatch and empty curve") {
    const Curve mismatch{{0.0, 1.0, 2.0}, {1.0, 2.0}};
    CHECK_THROWS_WITH(relative_difference(lab, mismatch, 0.0), Catch::Contains("model.y.size() = 2"));
    CHECK_THROWS_AS(interpolate(Curve{}, 0.0), InputError);
  }
  SECTION("no usable point") {
    const Curve far{{10.0, 20.0}, {1.0, 2.0}};  // no lab x inside [10, 20]
    CHECK_THROWS_WITH(relative_difference(lab, far, 0.0), Catch::Contains("no usable lab point"));
    CHECK_THROWS_AS(relative_difference(lab, model, 100.0), InputError);  // every |y_lab| < 100
  }
}
