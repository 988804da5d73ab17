// Rose histograms, Fourier fits (docs/model.md 9.2, test T8) and the fabric tensor (docs/model.md 9.3).
#include <dem/core/errors.hpp>
#include <dem/measure/fabric.hpp>

#include <catch2/catch.hpp>
#include <cmath>
#include <numeric>
#include <random>

using dem::Vec3;
using dem::measure::ContactSample;
using dem::measure::RosePlane;

namespace {

constexpr double deg = dem::pi / 180.0;

// N contacts with x-z normals drawn from E(theta) = (1/pi)(1 + a cos 2(theta - theta_a)) by
// rejection, random sign (n and -n are the same contact), and normal force
// f0 (1 + a_n cos 2(theta - theta_n)) times a uniform factor in [0.5, 1.5] (mean 1).
std::vector<ContactSample> anisotropic_sample(std::size_t n_contacts, std::uint64_t seed) {
  const double a = 0.4, theta_a = 30.0 * deg, f0 = 2.0, a_n = 0.3, theta_n = 60.0 * deg;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<ContactSample> contacts;
  contacts.reserve(n_contacts);
  while (contacts.size() < n_contacts) {
    const double theta = dem::pi * uniform(rng);
    if (uniform(rng) * (1.0 + a) > 1.0 + a * std::cos(2.0 * (theta - theta_a))) continue;
    const double sign = uniform(rng) < 0.5 ? -1.0 : 1.0;
    const double force = f0 * (1.0 + a_n * std::cos(2.0 * (theta - theta_n))) * (0.5 + uniform(rng));
    contacts.push_back({sign * Vec3(std::cos(theta), 0.0, std::sin(theta)), force});
  }
  return contacts;
}

}  // namespace

TEST_CASE("fabric: T8 Fourier fits recover a known anisotropy", "[measure][fabric]") {
  const std::size_t n_contacts = 1000000;
  const auto contacts = anisotropic_sample(n_contacts, 1);
  const auto r = dem::measure::rose(contacts, RosePlane::ShearXZ, 10.0);

  REQUIRE(r.count.size() == 18);
  CHECK(std::accumulate(r.count.begin(), r.count.end(), 0L) == static_cast<long>(n_contacts));
  CHECK(r.contacts_used == static_cast<long>(n_contacts));
  CHECK(r.contacts_skipped == 0);
  CHECK(std::accumulate(r.fraction.begin(), r.fraction.end(), 0.0) == Approx(1.0).epsilon(1e-12));

  // Sampling noise: each of (2/N) sum cos 2theta, (2/N) sum sin 2theta has std ~ sqrt(2/N) =
  // 1.4e-3, so a is off by ~1.4e-3 and theta_a by ~1.4e-3/(2a) rad = 0.1 deg. docs/model.md's T8
  // bounds (0.003, 0.3 deg) are 2-3 sigma; the seed is fixed, so the test is deterministic.
  // The sinc correction removes the binning bias of the cos 2theta mode exactly.
  CHECK(r.a == Approx(0.400).margin(0.003));
  CHECK(r.theta_a_deg == Approx(30.0).margin(0.3));
  CHECK(r.a_direct == Approx(0.400).margin(0.003));
  CHECK(r.theta_a_direct_deg == Approx(30.0).margin(0.3));
  // Binned and bin-free fits see the same angles; binning only adds sub-bin position noise.
  CHECK(r.a == Approx(r.a_direct).margin(1e-3));

  // Forces. Each bin holds ~55,000 contacts and the force factor has relative std 0.29, so
  // f_m has relative noise ~1.3e-3 and the fitted a_n ~ sqrt(2/M) * 1.3e-3 = 4e-4 (theta_n:
  // 4e-4/(2 a_n) rad = 0.04 deg). Averaging f over a bin weighted by E(theta) instead of
  // uniformly biases f_m by ~ (D^2/12) (E'/E) f' <= 2e-3 f0, mostly outside the 2theta mode.
  // Tolerances: a_n 0.003, theta_n 0.3 deg, f0 0.2 %.
  CHECK(r.a_n == Approx(0.3).margin(0.003));
  CHECK(r.theta_n_deg == Approx(60.0).margin(0.3));
  CHECK(r.f0 == Approx(2.0).epsilon(2e-3));
  // Rothenburg-Bathurst f0 = integral E f_n = f0 (1 + a a_n / 2 cos 2(theta_a - theta_n))
  // = 2 (1 + 0.06 cos(-60 deg)) = 2.06 N. Noise: std(F_n) ~ 0.75 N over 1e6 contacts -> 7.5e-4 N.
  CHECK(r.mean_force_all == Approx(2.06).margin(4e-3));

  // 2-D fabric: phi_xx = 1/2 + (a/4) cos 2theta_a = 0.55, phi_zz = 0.45,
  // phi_xz = (a/4) sin 2theta_a = 0.1 sin 60 deg; noise ~ sqrt(0.5/N)/2 = 3.5e-4.
  const dem::Mat3 phi = dem::measure::fabric_tensor(contacts);
  CHECK(phi.trace() == Approx(1.0).epsilon(1e-12));
  CHECK(phi(1, 1) == 0.0);
  CHECK(phi(0, 0) == Approx(0.55).margin(1.5e-3));
  CHECK(phi(2, 2) == Approx(0.45).margin(1.5e-3));
  CHECK(phi(0, 2) == Approx(0.1 * std::sin(60.0 * deg)).margin(1.5e-3));
  CHECK(phi(0, 2) == phi(2, 0));
}

TEST_CASE("fabric: isotropic normals give no anisotropy", "[measure][fabric]") {
  // Uniform on the sphere (normalised Gaussian vectors): the x-z projection is uniform in angle
  // by symmetry about y, and the fabric tensor is I/3.
  const std::size_t n_contacts = 1000000;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<ContactSample> contacts;
  contacts.reserve(n_contacts);
  for (std::size_t i = 0; i < n_contacts; ++i) {
    const Vec3 v(gauss(rng), gauss(rng), gauss(rng));
    contacts.push_back({v.normalized(), 1.0});
  }
  const auto r = dem::measure::rose(contacts, RosePlane::ShearXZ);
  // With a = 0 the fitted a is Rayleigh-distributed with sigma = sqrt(2/N) = 1.4e-3;
  // P(a > 5 sigma) = exp(-12.5) = 4e-6.
  const double bound = 5.0 * std::sqrt(2.0 / static_cast<double>(n_contacts));
  CHECK(r.a_direct < bound);
  CHECK(r.a < bound / 0.99);  // the sinc correction scales the noise by 1/0.995
  CHECK(std::accumulate(r.count.begin(), r.count.end(), 0L) + r.contacts_skipped ==
        static_cast<long>(n_contacts));
  CHECK(r.a_n == Approx(0.0).margin(1e-12));  // equal forces: every bin mean is exactly 1
  CHECK(r.f0 == Approx(1.0).epsilon(1e-12));

  // phi = I/3; each entry has std <= sqrt(var(n_i n_j)/N) <= sqrt(0.09/N) = 3e-4.
  const dem::Mat3 phi = dem::measure::fabric_tensor(contacts);
  CHECK(phi.trace() == Approx(1.0).epsilon(1e-12));
  CHECK((phi - dem::Mat3::Identity() / 3.0).cwiseAbs().maxCoeff() < 1.5e-3);
}

TEST_CASE("fabric: projection planes, folding and bins by hand", "[measure][fabric]") {
  const double s = 1.0 / std::sqrt(2.0);
  const std::vector<ContactSample> contacts = {
      {Vec3(s, s, 0.0), 1.0},     // xy 45; xz (s, 0) -> 0;   yz (s, 0) -> 0
      {Vec3(-s, 0.0, -s), 3.0},   // xy (-s, 0) -> 180 -> 0; xz atan2(-s, -s) = -135 -> 45; yz -90 -> 90
      {Vec3(-s, 0.0, s), 5.0},    // xy 180 -> 0; xz 135; yz (0, s) -> 90
      {Vec3(0.0, 0.0, 1.0), 7.0}, // xy: perpendicular, skipped; xz 90; yz 90
  };
  SECTION("ShearXZ") {
    const auto r = dem::measure::rose(contacts, RosePlane::ShearXZ, 45.0);  // bins 0,45,90,135
    CHECK(r.bin_lo_deg == std::vector<double>{0.0, 45.0, 90.0, 135.0});
    CHECK(r.count == std::vector<long>{1, 1, 1, 1});
    CHECK(r.mean_normal_force == std::vector<double>{1.0, 3.0, 7.0, 5.0});
    CHECK(r.mean_force_all == Approx(4.0));  // (1 + 3 + 5 + 7)/4
    CHECK(r.contacts_skipped == 0);
    // cos 2theta: 1, 0, -1, 0 and sin 2theta: 0, 1, 0, -1 -> both sums 0.
    CHECK(r.a_direct == Approx(0.0).margin(1e-15));
  }
  SECTION("HorizontalXY") {
    const auto r = dem::measure::rose(contacts, RosePlane::HorizontalXY, 45.0);
    CHECK(r.count == std::vector<long>{2, 1, 0, 0});
    CHECK(r.mean_normal_force == std::vector<double>{4.0, 1.0, 0.0, 0.0});  // (3 + 5)/2
    CHECK(r.contacts_used == 3);
    CHECK(r.contacts_skipped == 1);
    CHECK(r.fraction[0] == Approx(2.0 / 3.0));
    // Angles 0, 0, 45: sum cos 2theta = 2, sum sin 2theta = 1 -> a = (2/3) sqrt(5),
    // theta_a = 0.5 atan2(1, 2) = 13.2825 deg.
    CHECK(r.a_direct == Approx(2.0 / 3.0 * std::sqrt(5.0)).epsilon(1e-12));
    CHECK(r.theta_a_direct_deg == Approx(0.5 * std::atan2(1.0, 2.0) / deg).epsilon(1e-12));
  }
  SECTION("SideYZ") {
    const auto r = dem::measure::rose(contacts, RosePlane::SideYZ, 45.0);
    CHECK(r.count == std::vector<long>{1, 0, 3, 0});
    CHECK(r.mean_normal_force == std::vector<double>{1.0, 0.0, 5.0, 0.0});  // (3 + 5 + 7)/3
    CHECK(r.contacts_skipped == 0);
  }
}

TEST_CASE("fabric: binned fit of an exactly binned cos 2theta density", "[measure][fabric]") {
  // Bin fractions h_m = integral over the bin of (1/pi)(1 + a cos 2(theta - theta_a)), i.e.
  // D/pi + (a/(2 pi)) [sin 2(hi - theta_a) - sin 2(lo - theta_a)]. Place one contact per
  // 1e-6 of probability at its bin centre, so the binned fit sees these fractions to 5e-7.
  const double a = 0.25, theta_a = 100.0 * deg, width = 15.0 * deg;
  std::vector<ContactSample> contacts;
  for (int m = 0; m < 12; ++m) {
    const double lo = m * width, hi = lo + width, mid = lo + width / 2.0;
    const double h = width / dem::pi +
                     a / (2.0 * dem::pi) * (std::sin(2.0 * (hi - theta_a)) - std::sin(2.0 * (lo - theta_a)));
    const long n = std::lround(h * 1e6);
    for (long k = 0; k < n; ++k) contacts.push_back({Vec3(std::cos(mid), 0.0, std::sin(mid)), 1.0});
  }
  const auto r = dem::measure::rose(contacts, RosePlane::ShearXZ, 15.0);
  // Without the sinc correction a would be 0.25 * sin(15 deg)/(15 deg) = 0.2471; with it, the
  // only error is rounding the counts: |dH_1| <= 12 * 5e-7, so |da| <= 2 * 6e-6 / 0.989 = 1.2e-5
  // and |dtheta_a| <= 6e-6 / (2 * 0.124) rad = 0.0014 deg.
  CHECK(r.a == Approx(a).margin(5e-5));
  CHECK(r.theta_a_deg == Approx(100.0).margin(0.01));
}

TEST_CASE("fabric: bad input", "[measure][fabric]") {
  const std::vector<ContactSample> ok = {{Vec3::UnitX(), 1.0}};
  using dem::InputError;
  for (const double width : {7.0, 0.0, -10.0, 90.0, 180.0, std::nan("")}) {
    CAPTURE(width);
    CHECK_THROWS_AS(dem::measure::rose(ok, RosePlane::ShearXZ, width), InputError);
  }
  CHECK_THROWS_WITH(dem::measure::rose(ok, RosePlane::ShearXZ, 7.0), Catch::Contains("bin_width_deg"));
  CHECK_NOTHROW(dem::measure::rose(ok, RosePlane::ShearXZ, 7.5));  // 24 bins

  const std::vector<ContactSample> not_unit = {{Vec3::UnitX(), 1.0}, {Vec3(0.0, 0.0, 2.0), 1.0}};
  CHECK_THROWS_WITH(dem::measure::rose(not_unit, RosePlane::ShearXZ), Catch::Contains("contacts[1]"));
  CHECK_THROWS_AS(dem::measure::fabric_tensor(not_unit), InputError);
  const std::vector<ContactSample> bad_force = {{Vec3::UnitX(), std::nan("")}};
  CHECK_THROWS_WITH(dem::measure::rose(bad_force, RosePlane::ShearXZ), Catch::Contains("normal_force"));
  CHECK_THROWS_AS(dem::measure::fabric_tensor({}), InputError);

  // No usable contact is not an error: empty rose, NaN fits.
  const auto r = dem::measure::rose({{Vec3::UnitY(), 1.0}}, RosePlane::ShearXZ);
  CHECK(r.contacts_skipped == 1);
  CHECK(std::accumulate(r.count.begin(), r.count.end(), 0L) == 0);
  CHECK(std::isnan(r.a));
  CHECK(std::isnan(r.a_direct));
  CHECK(std::isnan(r.mean_force_all));
}

TEST_CASE("fabric: the left-right asymmetry of a rose about the vertical, and its tilt", "[measure][fabric]") {
  // Normals in the x-z plane at angle theta from +x (the rose's angle), force f.
  const auto at = [](double theta_deg, double force) {
    const double t = theta_deg * M_PI / 180.0;
    return ContactSample{Vec3(std::cos(t), 0.0, std::sin(t)), force};
  };
  // Mirror pairs about 90 deg (75/105, 45/135) with equal forces: symmetric.
  const std::vector<ContactSample> mirrored = {at(75, 1.0), at(105, 1.0), at(45, 2.0), at(135, 2.0), at(90.5, 3.0), at(89.5, 3.0)};
  const auto symmetric = dem::measure::rose_asymmetry(dem::measure::rose(mirrored, RosePlane::ShearXZ));
  CHECK(symmetric.count == 0.0);
  CHECK(symmetric.force == 0.0);
  // Every normal on one side of the vertical: each pair differs by its whole count.
  const std::vector<ContactSample> one_side = {at(75, 1.0), at(45, 2.0), at(15, 3.0)};
  const auto lopsided = dem::measure::rose_asymmetry(dem::measure::rose(one_side, RosePlane::ShearXZ));
  CHECK(lopsided.count == Approx(1.0).epsilon(1e-12));
  CHECK(lopsided.force == Approx(1.0).epsilon(1e-12));
  // Two normals in [60, 70), one in its mirror bin [110, 120) with twice the force: counts 2
  // against 1 (|2 - 1| / 3), mean forces 1 against 2 (|1 - 2| / 3).
  const std::vector<ContactSample> uneven = {at(62, 1.0), at(63, 1.0), at(115, 2.0)};
  const auto a = dem::measure::rose_asymmetry(dem::measure::rose(uneven, RosePlane::ShearXZ));
  CHECK(a.count == Approx(1.0 / 3.0).epsilon(1e-12));
  CHECK(a.force == Approx(1.0 / 3.0).epsilon(1e-12));
  // The tilt: a fabric in the one bin [60, 70) leans 25 deg (its centre's) from the vertical
  // towards +x, by the binned Fourier fit.
  std::vector<ContactSample> leaning;
  for (int k = -4; k <= 4; ++k) leaning.push_back(at(65.0 + k, 1.0));
  const auto tilt = dem::measure::rose_asymmetry(dem::measure::rose(leaning, RosePlane::ShearXZ));
  CHECK(tilt.count_tilt_deg == Approx(25.0).margin(1e-9));
  CHECK(std::isnan(dem::measure::rose_asymmetry(dem::measure::rose({}, RosePlane::ShearXZ)).count));
}
