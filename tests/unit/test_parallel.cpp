// The threads' shares of a loop: what speed_fractions gives for measured speeds. The expected
// fractions are ratios of small integers, so the tolerance only absorbs a few double roundings.
#include <dem/core/parallel.hpp>

#include <catch2/catch.hpp>
#include <vector>

using dem::speed_fractions;

namespace {
Approx exactly(double value) { return Approx(value).epsilon(0).margin(1e-12); }
}  // namespace

TEST_CASE("speed_fractions: shares in proportion to measured speed, floored at half an equal share", "[parallel]") {
  SECTION("equal speeds give equal shares, whatever the work and time") {
    const auto f = speed_fractions({300, 100}, {3.0, 1.0});
    CHECK(f[0] == exactly(0.5));
    CHECK(f[1] == exactly(0.5));
  }
  SECTION("a thread twice as fast gets two thirds") {
    // 100 units in 1 s against 100 units in 2 s
    const auto f = speed_fractions({100, 100}, {1.0, 2.0});
    CHECK(f[0] == exactly(2.0 / 3.0));
    CHECK(f[1] == exactly(1.0 / 3.0));
  }
  SECTION("a thread ten times slower keeps half an equal share; the rest goes to the others by speed") {
    const auto f = speed_fractions({100, 100, 100}, {1.0, 2.0, 10.0});
    const double floor = 0.5 / 3.0;
    CHECK(f[2] == exactly(floor));
    // the other two share 1 - floor as 100 : 50
    CHECK(f[0] == exactly((1.0 - floor) * 2.0 / 3.0));
    CHECK(f[1] == exactly((1.0 - floor) / 3.0));
    CHECK(f[0] + f[1] + f[2] == exactly(1.0));
  }
  SECTION("without a measurement the shares are equal") {
    CHECK(speed_fractions({100, 100}, {0.0, 1.0}) == std::vector<double>{0.5, 0.5});
    CHECK(speed_fractions({0, 100}, {1.0, 1.0}) == std::vector<double>{0.5, 0.5});
    CHECK(speed_fractions({100, 100}, {1.0}) == std::vector<double>{0.5, 0.5});
    CHECK(speed_fractions({100}, {1.0}) == std::vector<double>{1.0});
  }
}
