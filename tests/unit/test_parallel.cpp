// The threads' shares of a loop: what speed_fractions gives for measured speeds, where
// share_begin and split_work put the borders, and how ChunkQueue hands out a share's chunks. The
// expected values are ratios of small integers, so the tolerance only absorbs a few double
// roundings.
#include <dem/core/parallel.hpp>

#include <catch2/catch.hpp>
#include <cstdint>
#include <thread>
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

TEST_CASE("share_begin: a loop's items split by the threads' fractions", "[parallel]") {
  using dem::share_begin;
  SECTION("without fractions, or with the wrong number of them, the shares are equal") {
    CHECK(share_begin(1000, nullptr, 2, 1) == 500);
    const std::vector<double> three{0.2, 0.3, 0.5};
    CHECK(share_begin(1000, &three, 2, 1) == 500);
    CHECK(share_begin(7, nullptr, 3, 1) == 2);  // 7 * 1 / 3, rounded down as the loops did
  }
  SECTION("shares follow the fractions and cover every item once") {
    const std::vector<double> f{0.25, 0.75};
    CHECK(share_begin(1000, &f, 2, 0) == 0);
    CHECK(share_begin(1000, &f, 2, 1) == 250);
    CHECK(share_begin(1000, &f, 2, 2) == 1000);
  }
  SECTION("fractions summing to a little over 1 never reach past the last item") {
    const std::vector<double> f{0.6, 0.6};
    CHECK(share_begin(10, &f, 2, 1) == 6);
    CHECK(share_begin(10, &f, 2, 2) == 10);
  }
}

TEST_CASE("split_work: contiguous shares of equal work, and of measured fractions", "[parallel]") {
  using dem::split_work;
  // items of work 1, 1, 1, 1, 4, 4 (total 12)
  const std::vector<std::int64_t> units{1, 1, 1, 1, 4, 4};
  const auto work = [&units](std::int64_t k) { return units[static_cast<std::size_t>(k)]; };
  SECTION("two equal shares: the first ends where the work reaches 6") {
    std::vector<std::int64_t> share_work;
    const auto border = split_work(6, {0.5, 0.5}, work, &share_work);
    CHECK(border == std::vector<std::int64_t>{0, 5, 6});  // 1+1+1+1+4 = 8 >= 6 at item 4
    CHECK(share_work == std::vector<std::int64_t>{8, 4});
  }
  SECTION("a quarter and three quarters") {
    std::vector<std::int64_t> share_work;
    const auto border = split_work(6, {0.25, 0.75}, work, &share_work);
    CHECK(border == std::vector<std::int64_t>{0, 3, 6});  // 3 >= 12 / 4 at item 2
    CHECK(share_work == std::vector<std::int64_t>{3, 9});
  }
  SECTION("more shares than work: the last ones are empty and end at the count") {
    const auto border = split_work(2, {0.25, 0.25, 0.25, 0.25}, [](std::int64_t) { return std::int64_t{1}; });
    CHECK(border == std::vector<std::int64_t>{0, 1, 2, 2, 2});
  }
}

TEST_CASE("ChunkQueue: the owner takes from the front, others from the back, each chunk once", "[parallel]") {
  SECTION("alone, in order") {
    dem::ChunkQueue q;
    q.reset(5);
    CHECK(q.left() == 5);
    CHECK(q.take_front() == 0);
    CHECK(q.take_back() == 4);
    CHECK(q.take_front() == 1);
    CHECK(q.take_back() == 3);
    CHECK(q.left() == 1);
    CHECK(q.take_back() == 2);
    CHECK(q.left() == 0);
    CHECK(q.take_front() == -1);
    CHECK(q.take_back() == -1);
    q.reset(0);
    CHECK(q.take_front() == -1);
  }
  SECTION("two threads racing from both ends: every chunk taken exactly once") {
    constexpr std::int64_t chunks = 200000;
    dem::ChunkQueue q;
    q.reset(chunks);
    std::vector<std::int64_t> front, back;
    std::thread owner([&] {
      for (std::int64_t c; (c = q.take_front()) >= 0;) front.push_back(c);
    });
    for (std::int64_t c; (c = q.take_back()) >= 0;) back.push_back(c);
    owner.join();
    REQUIRE(static_cast<std::int64_t>(front.size() + back.size()) == chunks);
    // The owner's chunks are 0, 1, 2, ... and the other's count down from the end: they meet once.
    std::int64_t out_of_place = 0;
    for (std::size_t k = 0; k < front.size(); ++k) out_of_place += front[k] != static_cast<std::int64_t>(k);
    for (std::size_t k = 0; k < back.size(); ++k) out_of_place += back[k] != chunks - 1 - static_cast<std::int64_t>(k);
    CHECK(out_of_place == 0);
  }
}
