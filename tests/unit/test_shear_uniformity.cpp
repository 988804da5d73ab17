// Shear uniformity of displacement profiles and stress / strain-rate non-coaxiality
// (dem/measure/shear_uniformity.hpp) on fields with closed-form answers.
#include <dem/core/errors.hpp>
#include <dem/measure/shear_uniformity.hpp>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using dem::InputError;
using dem::Mat3;
using dem::Vec3;
using dem::measure::displacement_profile;
using dem::measure::major_direction_deg;
using dem::measure::non_coaxiality_deg;
using dem::measure::porosity_profile;
using dem::measure::shear_uniformity;

namespace {

constexpr double deg = dem::pi / 180.0;
constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

// Study-like specimen: 20 mm high, bottom plate not at z = 0 so that offsets are exercised.
constexpr double z_bottom = 0.005, height = 0.02, z_top = z_bottom + height;  // m
// 2^-10 m (~1 mm, 5 % strain): sums of a few thousand copies are exact, so a rigid bin's mean is
// exactly U and a rigid third's strain exactly 0 (the ratio's NaN case).
constexpr double U = 0.0009765625;  // m
constexpr int bins = 12;
constexpr double h = height / bins;  // m

std::vector<double> random_heights(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(z_bottom, z_top);
  std::vector<double> z(n);
  for (double& zi : z) zi = uniform(rng);
  return z;
}

// 40 balls per bin in pairs centre +- delta, delta < 0.45 h (clear of the bin edges): every bin's
// mean height is its centre to rounding, so answers can be worked out at the centres.
std::vector<double> paired_heights(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(0.0, 0.45 * h);
  std::vector<double> z;
  for (int i = 0; i < bins; ++i) {
    const double centre = z_bottom + (i + 0.5) * h;
    for (int k = 0; k < 20; ++k) {
      const double delta = offset(rng);
      z.push_back(centre - delta);
      z.push_back(centre + delta);
    }
  }
  return z;
}

// Least-squares slope of y(x) changes by sum (x_i - x_mean) e_i / Sxx for errors e_i; with
// |e_i| <= a that is at most a sum |x_i - x_mean| / Sxx.
double slope_error_bound(const std::vector<double>& x, double a) {
  double mean = 0.0;
  for (const double xi : x) mean += xi;
  mean /= static_cast<double>(x.size());
  double abs_sum = 0.0, sxx = 0.0;
  for (const double xi : x) {
    abs_sum += std::abs(xi - mean);
    sxx += (xi - mean) * (xi - mean);
  }
  return a * abs_sum / sxx;
}

// Rotation turning +z towards +d by angle_rad, about the horizontal axis e_z x d.
Mat3 tilt_towards(const Vec3& d, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Vec3::UnitZ().cross(d).normalized()).toRotationMatrix();
}

// Tensor with principal values major (along z tilted by angle towards d), middle (horizontal,
// normal to d) and minor (in the d-z plane): its d-z major direction is at angle.
Mat3 tilted_tensor(const Vec3& d, double angle_deg, double major, double middle, double minor) {
  const Vec3 n = Vec3::UnitZ().cross(d);
  const Mat3 frame =
      major * Vec3::UnitZ() * Vec3::UnitZ().transpose() + middle * n * n.transpose() + minor * d * d.transpose();
  const Mat3 r = tilt_towards(d, angle_deg * deg);
  return r * frame * r.transpose();
}

}  // namespace

TEST_CASE("displacement profile: binning, end bins, empty bins", "[shear_uniformity]") {
  // 4 bins of 0.25 m on [0, 1]: -0.1 and 1.5 lie outside and join the end bins; 1.0 (z_top)
  // belongs to the top bin; bin 1 stays empty.
  const std::vector<double> z{-0.1, 0.1, 0.6, 0.7, 1.0, 1.5};
  const std::vector<double> u{1.0, 3.0, 5.0, 6.0, 2.0, 4.0};
  const auto p = displacement_profile(z, u, 0.0, 1.0, 4);
  REQUIRE(p.count.size() == 4);
  CHECK(p.count == std::vector<std::size_t>{2, 0, 2, 2});
  CHECK(p.z_centre == std::vector<double>{0.125, 0.375, 0.625, 0.875});  // exact binary fractions
  // Means of two numbers: one rounding each, 1e-15 is ample.
  CHECK(p.z_mean[0] == Approx(0.0).margin(1e-15));
  CHECK(p.z_mean[2] == Approx(0.65).margin(1e-15));
  CHECK(p.z_mean[3] == Approx(1.25).margin(1e-15));
  CHECK(p.mean_displacement[0] == 2.0);
  CHECK(p.mean_displacement[2] == 5.5);
  CHECK(p.mean_displacement[3] == 3.0);
  CHECK(std::isnan(p.mean_displacement[1]));
  CHECK(std::isnan(p.z_mean[1]));

  const auto none = displacement_profile({}, {}, 0.0, 1.0, 3);  // no balls: all bins empty
  CHECK(none.count == std::vector<std::size_t>{0, 0, 0});
  CHECK(std::isnan(none.mean_displacement[2]));
}

TEST_CASE("shear uniformity: uniform simple shear", "[shear_uniformity]") {
  const auto z = random_heights(3000, 7);  // ~250 a bin, none empty
  const double gamma = U / height;         // bottom moves +U, top held

  SECTION("exact field: R^2 = 1, every third U/H, ratio 1") {
    std::vector<double> u;
    for (const double zi : z) u.push_back(U * (1.0 - (zi - z_bottom) / height));
    const auto p = displacement_profile(z, u, z_bottom, z_top, bins);
    for (const auto c : p.count) REQUIRE(c > 0);
    const auto s = shear_uniformity(p, z_bottom, z_top, U, 0.0);
    // A linear field's bin mean is the field at the bin's mean height (z_mean), so only rounding
    // separates the means from the model: ~1e-16 U each, 1 - R^2 ~ 1e-31. Slopes: ~1e-16 relative
    // times z/Delta z ~ 10.
    CHECK(s.r_squared == Approx(1.0).margin(1e-12));
    CHECK(s.bottom_third_strain == Approx(gamma).epsilon(1e-12));
    CHECK(s.middle_third_strain == Approx(gamma).epsilon(1e-12));
    CHECK(s.top_third_strain == Approx(gamma).epsilon(1e-12));
    CHECK(s.top_bottom_strain_ratio == Approx(1.0).epsilon(1e-12));
  }
  SECTION("both plates moving: strain (U_bottom - U_top)/H; top moving alone is negative") {
    const double u_bottom = 0.25 * U, u_top = -0.75 * U;  // relative motion U, as above
    std::vector<double> u;
    for (const double zi : z) u.push_back(u_bottom + (u_top - u_bottom) * (zi - z_bottom) / height);
    const auto s =
        shear_uniformity(displacement_profile(z, u, z_bottom, z_top, bins), z_bottom, z_top, u_bottom, u_top);
    CHECK(s.r_squared == Approx(1.0).margin(1e-12));
    CHECK(s.bottom_third_strain == Approx(gamma).epsilon(1e-12));
    CHECK(s.top_third_strain == Approx(gamma).epsilon(1e-12));

    std::vector<double> top_moving;
    for (const double zi : z) top_moving.push_back(U * (zi - z_bottom) / height);
    const auto t =
        shear_uniformity(displacement_profile(z, top_moving, z_bottom, z_top, bins), z_bottom, z_top, 0.0, U);
    CHECK(t.r_squared == Approx(1.0).margin(1e-12));
    CHECK(t.middle_third_strain == Approx(-gamma).epsilon(1e-12));
    CHECK(t.top_bottom_strain_ratio == Approx(1.0).epsilon(1e-12));
  }
  SECTION("bounded noise stays within its worst-case effect") {
    const double a = 0.01 * U;  // m, noise amplitude: uniform on [-a, a]
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> noise(-a, a);
    std::vector<double> exact, noisy;
    for (const double zi : z) {
      exact.push_back(U * (1.0 - (zi - z_bottom) / height));
      noisy.push_back(exact.back() + noise(rng));
    }
    const auto p0 = displacement_profile(z, exact, z_bottom, z_top, bins);
    const auto p = displacement_profile(z, noisy, z_bottom, z_top, bins);
    const auto s = shear_uniformity(p, z_bottom, z_top, U, 0.0);
    // Each bin mean moves by at most a, so SS_res <= n a^2, and the centred means move by at most
    // sqrt(n) a in norm: sqrt(SS_tot) >= sqrt(SS_tot,exact) - sqrt(n) a. (The expected 1 - R^2 is
    // ~1e-6; the bound, ~1e-3, holds for any draw.)
    double m0 = 0.0, ss_tot0 = 0.0;
    for (const double m : p0.mean_displacement) m0 += m / bins;
    for (const double m : p0.mean_displacement) ss_tot0 += (m - m0) * (m - m0);
    const double root_floor = std::sqrt(ss_tot0) - std::sqrt(double(bins)) * a;
    CHECK(s.r_squared <= 1.0);
    CHECK(1.0 - s.r_squared <= bins * a * a / (root_floor * root_floor));
    // Per third: slope error <= a sum |z - z_mean| / Szz over its 4 bins.
    for (int third = 0; third < 3; ++third) {
      const std::vector<double> zs(p.z_mean.begin() + 4 * third, p.z_mean.begin() + 4 * third + 4);
      const double strain = third == 0   ? s.bottom_third_strain
                            : third == 1 ? s.middle_third_strain
                                         : s.top_third_strain;
      CHECK(std::abs(strain - gamma) <= slope_error_bound(zs, a) * (1.0 + 1e-9));
    }
  }
}

TEST_CASE("shear uniformity: band at the top, rigid below", "[shear_uniformity]") {
  // Bottom 3/4 moves rigidly with the bottom plate (u = U); the top quarter shears from U to 0:
  // u = 4U (1 - x) for x = (z - z_bottom)/H >= 3/4. 3/4 is a bin edge for 12 bins, so each bin is
  // rigid or linear, and with balls paired about the centres the bin means are the field at the
  // centres x_i = (i + 1/2)/12: m_i = U for i <= 8; 5U/6, U/2, U/6 for i = 9, 10, 11.
  // Uniform model U (1 - x_i) = U (11.5 - i)/12, residuals (units U/12): i + 0.5 for i <= 8
  // (sum of squares 242.25), then 7.5, 4.5, 1.5 (78.75): SS_res = 321/144 U^2.
  // Mean of the means 7U/8: deviations U/8 (nine bins), -U/24, -3U/8, -17U/24:
  // SS_tot = (9 * 9 + 1 + 81 + 289)/576 U^2 = 113/144 U^2. R^2 = 1 - 321/113 = -208/113.
  // Top third (bins 8..11, centres -1.5, -0.5, 0.5, 1.5 bin heights h from their middle):
  // slope = (-1.5 - 5/12 + 1/4 + 1/4)/5 U/h = -17/60 U/h, so strain 17/60 * 12 U/H = 17U/(5H);
  // the other thirds are rigid: 0, and the ratio is NaN.
  // Everything is a few roundings from exact: 1e-9 (relative) is far above them.
  const auto z = paired_heights(3);
  std::vector<double> u;
  for (const double zi : z) {
    const double x = (zi - z_bottom) / height;
    u.push_back(x <= 0.75 ? U : 4.0 * U * (1.0 - x));
  }
  const auto s = shear_uniformity(displacement_profile(z, u, z_bottom, z_top, bins), z_bottom, z_top, U, 0.0);
  CHECK(s.r_squared == Approx(-208.0 / 113.0).epsilon(1e-9));
  CHECK(s.top_third_strain == Approx(17.0 * U / (5.0 * height)).epsilon(1e-9));
  CHECK(s.middle_third_strain == 0.0);
  CHECK(s.bottom_third_strain == 0.0);
  CHECK(std::isnan(s.top_bottom_strain_ratio));
}

TEST_CASE("shear uniformity: band at the bottom, rigid above", "[shear_uniformity]") {
  // Mirror of the previous case, u'(z) = U - u(z_top + z_bottom - z): the bottom quarter shears
  // from U to 0 and the rest stays with the top plate. The mirror maps the uniform line onto
  // itself and the residuals to minus those of the mirrored bins, so SS_res, SS_tot and R^2 are
  // unchanged; the bottom third now carries 17U/(5H), the top third 0, and the ratio is 0/that = 0.
  const auto z = paired_heights(5);
  std::vector<double> u;
  for (const double zi : z) {
    const double x = (zi - z_bottom) / height;
    u.push_back(x >= 0.25 ? 0.0 : U * (1.0 - 4.0 * x));
  }
  const auto s = shear_uniformity(displacement_profile(z, u, z_bottom, z_top, bins), z_bottom, z_top, U, 0.0);
  CHECK(s.r_squared == Approx(-208.0 / 113.0).epsilon(1e-9));
  CHECK(s.bottom_third_strain == Approx(17.0 * U / (5.0 * height)).epsilon(1e-9));
  CHECK(s.middle_third_strain == 0.0);
  CHECK(s.top_third_strain == 0.0);
  CHECK(s.top_bottom_strain_ratio == 0.0);
}

TEST_CASE("shear uniformity: sparse or motionless profiles give NaN, not errors", "[shear_uniformity]") {
  // 6 bins of 1 m on [0, 6], thirds of two bins each.
  dem::measure::DisplacementProfile p;
  p.z_centre = {0.5, 1.5, 2.5, 3.5, 4.5, 5.5};
  p.z_mean = p.z_centre;
  p.mean_displacement = {6.0, 5.0, not_a_number, not_a_number, not_a_number, 0.5};
  p.count = {1, 1, 0, 0, 0, 1};
  auto s = shear_uniformity(p, 0.0, 6.0, 6.0, 0.0);
  // Three non-empty bins: R^2 is defined. Residuals 0.5, 0.5, 0 against u = 6 - z; mean of the
  // means 23/6, SS_tot = (13/6)^2 + (7/6)^2 + (10/3)^2 = 618/36. All exact to rounding.
  CHECK(s.r_squared == Approx(1.0 - 0.5 / (618.0 / 36.0)).epsilon(1e-12));
  CHECK(s.bottom_third_strain == Approx(1.0).epsilon(1e-12));  // (6 - 5)/1 m
  CHECK(std::isnan(s.middle_third_strain));                    // no bins
  CHECK(std::isnan(s.top_third_strain));                       // one bin
  CHECK(std::isnan(s.top_bottom_strain_ratio));

  p.count[5] = 0;  // two non-empty bins: no R^2
  p.mean_displacement[5] = not_a_number;
  s = shear_uniformity(p, 0.0, 6.0, 6.0, 0.0);
  CHECK(std::isnan(s.r_squared));
  CHECK(s.bottom_third_strain == Approx(1.0).epsilon(1e-12));

  // No motion at all: every mean 0, SS_tot = 0.
  const auto still =
      shear_uniformity(displacement_profile(random_heights(500, 1), std::vector<double>(500, 0.0), z_bottom, z_top, 6),
                       z_bottom, z_top, 0.0, 0.0);
  CHECK(std::isnan(still.r_squared));
  CHECK(still.bottom_third_strain == 0.0);
  CHECK(std::isnan(still.top_bottom_strain_ratio));
}

TEST_CASE("major direction: angle, range and isotropy", "[shear_uniformity]") {
  // docs/model.md T6: 0.5 atan2(100, 100) = 22.5 deg; rounding only.
  CHECK(major_direction_deg(100.0, 200.0, 50.0) == Approx(22.5).margin(1e-12));
  CHECK(major_direction_deg(100.0, 200.0, -50.0) == Approx(-22.5).margin(1e-12));
  CHECK(major_direction_deg(3.0, 1.0, -0.0) == 90.0);  // horizontal: 90, never -90
  CHECK(std::isnan(major_direction_deg(5.0, 5.0, 0.0)));
  CHECK(std::isnan(major_direction_deg(0.0, 0.0, 0.0)));
  CHECK(std::isnan(major_direction_deg(5.0, 5.0 * (1.0 + 1e-14), 0.0)));  // rounding, not a deviator
  CHECK(std::isnan(major_direction_deg(1.0, not_a_number, 0.0)));
}

TEST_CASE("non-coaxiality: coaxial, constructed and wrapped pairs", "[shear_uniformity]") {
  const Vec3 d(std::cos(30.0 * deg), std::sin(30.0 * deg), 0.0);  // a leg at 30 deg from +x
  // Angles below come from atan2 of entries computed with a few roundings (~1e-16 relative) over
  // deviators of the same order as the entries: errors ~1e-14 deg; 1e-9 deg is generous.
  SECTION("strain rate proportional to the stress deviator: 0 in any orientation") {
    const Mat3 r = Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
    const Mat3 stress = r * Vec3(3e5, 2e5, 1e5).asDiagonal() * r.transpose();  // Pa
    const Mat3 deviator = stress - stress.trace() / 3.0 * Mat3::Identity();
    const Mat3 strain_rate = 2e-8 * deviator + 1e-3 * Mat3::Identity();  // 1/s, plus a volumetric part
    for (const Vec3& dir : {d, Vec3(Vec3::UnitX()), Vec3(-Vec3::UnitY())}) {
      CHECK(non_coaxiality_deg(stress, strain_rate, dir) == Approx(0.0).margin(1e-9));
    }
  }
  SECTION("stress at 40 deg, strain rate at 45 deg: -5") {
    const Mat3 stress = tilted_tensor(d, 40.0, 3e5, 2e5, 1e5);        // Pa
    const Mat3 strain_rate = tilted_tensor(d, 45.0, 2.0, 0.0, -2.0);  // 1/s
    CHECK(non_coaxiality_deg(stress, strain_rate, d) == Approx(-5.0).margin(1e-9));
    CHECK(non_coaxiality_deg(strain_rate, stress, d) == Approx(5.0).margin(1e-9));
  }
  SECTION("directions 89 and -89 are 2 deg apart, not 178") {
    const Mat3 a = tilted_tensor(d, 89.0, 3.0, 2.0, 1.0);
    const Mat3 b = tilted_tensor(d, -89.0, 3.0, 2.0, 1.0);
    CHECK(non_coaxiality_deg(a, b, d) == Approx(-2.0).margin(1e-9));
    CHECK(non_coaxiality_deg(b, a, d) == Approx(2.0).margin(1e-9));
  }
}

TEST_CASE("non-coaxiality: simple-shear sign convention", "[shear_uniformity]") {
  // Bottom moving along +d = +x under a held top: v_x = gamma_dot (H - z) + const, so
  // L_xz = dv_x/dz = -gamma_dot; tension-positive D = (L + L^T)/2 and compression positive e = -D
  // has e_xz = +gamma_dot/2.
  const double gamma_dot = 5.0;  // 1/s
  Mat3 velocity_gradient = Mat3::Zero();
  velocity_gradient(0, 2) = -gamma_dot;
  const auto compression = [](const Mat3& l) { return Mat3(-0.5 * (l + l.transpose())); };
  const Mat3 e = compression(velocity_gradient);
  CHECK(e(0, 2) == 0.5 * gamma_dot);
  CHECK(major_direction_deg(e(0, 0), e(2, 2), e(0, 2)) == Approx(45.0).margin(1e-12));
  // Stress lagging at 30 deg: non-coaxiality 30 - 45.
  const Mat3 stress = tilted_tensor(Vec3::UnitX(), 30.0, 3e5, 2e5, 1e5);
  CHECK(non_coaxiality_deg(stress, e, Vec3::UnitX()) == Approx(-15.0).margin(1e-9));
  // Dilation, D_zz = 0.2 gamma_dot: 0.5 atan2(gamma_dot, -0.2 gamma_dot) = 45 + 0.5 atan(0.2).
  velocity_gradient(2, 2) = 0.2 * gamma_dot;
  const Mat3 dilating = compression(velocity_gradient);
  const double expected = 45.0 + 0.5 * std::atan(0.2) / deg;
  CHECK(major_direction_deg(dilating(0, 0), dilating(2, 2), dilating(0, 2)) == Approx(expected).margin(1e-12));
  CHECK(non_coaxiality_deg(stress, dilating, Vec3::UnitX()) == Approx(30.0 - expected).margin(1e-9));
}

TEST_CASE("non-coaxiality: undefined directions give NaN; a bad d throws", "[shear_uniformity]") {
  const Mat3 stress = tilted_tensor(Vec3::UnitX(), 30.0, 3e5, 2e5, 1e5);  // Pa
  const Mat3 strain_rate = tilted_tensor(Vec3::UnitX(), 45.0, 1.0, 0.0, -1.0);
  // p I rotated carries ~1e-16 p of rounding in its off-diagonals: still isotropic.
  const Mat3 r = Eigen::AngleAxisd(0.9, Vec3(1.0, 2.0, 2.0).normalized()).toRotationMatrix();
  const Mat3 isotropic = r * (2e5 * Mat3::Identity()) * r.transpose();
  CHECK(std::isnan(non_coaxiality_deg(isotropic, strain_rate, Vec3::UnitX())));
  CHECK(std::isnan(non_coaxiality_deg(stress, Mat3::Zero(), Vec3::UnitX())));
  // The measurement sphere's strain rate with too few balls.
  const Mat3 undefined = Mat3::Constant(not_a_number);
  CHECK_NOTHROW(non_coaxiality_deg(stress, undefined, Vec3::UnitX()));
  CHECK(std::isnan(non_coaxiality_deg(stress, undefined, Vec3::UnitX())));
  CHECK(std::isnan(non_coaxiality_deg(stress, strain_rate, Vec3::Constant(not_a_number))));

  CHECK_THROWS_AS(non_coaxiality_deg(stress, strain_rate, Vec3(1.0, 1.0, 0.0)), InputError);
  CHECK_THROWS_WITH(non_coaxiality_deg(stress, strain_rate, Vec3(0.6, 0.0, 0.8)), Catch::Contains("d.z"));
}

TEST_CASE("shear uniformity: bad input throws InputError", "[shear_uniformity]") {
  const std::vector<double> z{0.01, 0.02}, u{0.0, 1e-4};
  CHECK_THROWS_WITH(displacement_profile(z, u, 0.0, 0.03, 0), Catch::Contains("bins = 0"));
  CHECK_THROWS_AS(displacement_profile(z, u, 0.0, 0.03, -3), InputError);
  CHECK_THROWS_WITH(displacement_profile(z, {0.0}, 0.0, 0.03, 3), Catch::Contains("u.size()"));
  CHECK_THROWS_WITH(displacement_profile(z, u, 0.03, 0.03, 3), Catch::Contains("z_top"));
  CHECK_THROWS_AS(displacement_profile(z, u, 0.03, 0.0, 3), InputError);
  CHECK_THROWS_WITH(displacement_profile({0.01, not_a_number}, u, 0.0, 0.03, 3), Catch::Contains("z[1]"));
  CHECK_THROWS_WITH(displacement_profile(z, {0.0, std::numeric_limits<double>::infinity()}, 0.0, 0.03, 3),
                    Catch::Contains("u[1]"));
  CHECK_THROWS_AS(displacement_profile(z, u, not_a_number, 0.03, 3), InputError);

  const auto p = displacement_profile(z, u, 0.0, 0.03, 6);
  CHECK_NOTHROW(shear_uniformity(p, 0.0, 0.03, 1e-4, 0.0));
  CHECK_THROWS_AS(shear_uniformity(p, 0.03, 0.0, 1e-4, 0.0), InputError);
  CHECK_THROWS_AS(shear_uniformity(p, 0.0, 0.03, not_a_number, 0.0), InputError);
  CHECK_THROWS_WITH(shear_uniformity(displacement_profile(z, u, 0.0, 0.03, 2), 0.0, 0.03, 1e-4, 0.0),
                    Catch::Contains(">= 3"));
  auto broken = p;
  broken.count.pop_back();
  CHECK_THROWS_WITH(shear_uniformity(broken, 0.0, 0.03, 1e-4, 0.0), Catch::Contains("profile.count"));
}

TEST_CASE("porosity_profile splits each sphere exactly between the slabs it crosses", "[measure][uniformity]") {
  const double a = 0.001, area = 1e-4;  // m, m^2
  const double ball = 4.0 / 3.0 * dem::pi * a * a * a;
  // Three slabs of 3 mm over [z_bottom, z_bottom + 9 mm]: a ball inside the middle one, a ball
  // centred on the plane between the first two (half each), a ball cut by the plane between the
  // last two at half its radius above the centre (cap of height a/2 above: 5/32 of the ball,
  // the 27/32 below), and a ball half through the bottom plate (all of it in the first slab).
  const double slab = 0.003;
  const std::vector<double> z = {z_bottom + 1.5 * slab, z_bottom + slab, z_bottom + 2 * slab - 0.5 * a, z_bottom};
  const std::vector<double> r(z.size(), a);
  const std::vector<double> n = porosity_profile(z, r, z_bottom, z_bottom + 3 * slab, area, 3);
  REQUIRE(n.size() == 3);
  const double v = area * slab;
  CHECK(n[0] == Approx(1 - (0.5 + 1.0) * ball / v).epsilon(1e-12));
  CHECK(n[1] == Approx(1 - (1.0 + 0.5 + 27.0 / 32.0) * ball / v).epsilon(1e-12));
  CHECK(n[2] == Approx(1 - 5.0 / 32.0 * ball / v).epsilon(1e-12));

  // A simple cubic lattice of spheres fills pi/6 of space: every slab whose bounds fall on
  // lattice mid-planes has the lattice porosity 1 - pi/6.
  std::vector<double> zl, rl;
  const double spacing = 2 * a, side = 10 * spacing;  // 10 x 10 spheres per layer
  for (int k = 0; k < 12; ++k)
    for (int c = 0; c < 100; ++c) zl.push_back(z_bottom + (k + 0.5) * spacing), rl.push_back(a);
  for (const double porosity : porosity_profile(zl, rl, z_bottom, z_bottom + 12 * spacing, side * side, 4))
    CHECK(porosity == Approx(1 - dem::pi / 6).epsilon(1e-12));

  CHECK_THROWS_WITH(porosity_profile(z, r, z_bottom, z_top, area, 0), Catch::Contains("bins"));
  CHECK_THROWS_WITH(porosity_profile(z, {a}, z_bottom, z_top, area, 3), Catch::Contains("r entries"));
  CHECK_THROWS_WITH(porosity_profile(z, r, z_bottom, z_top, 0.0, 3), Catch::Contains("area"));
  CHECK_THROWS_WITH(porosity_profile(z, r, z_top, z_bottom, area, 3), Catch::Contains("z_top"));
  CHECK_THROWS_WITH(porosity_profile({z_bottom, not_a_number}, {a, a}, z_bottom, z_top, area, 3), Catch::Contains("z[1]"));
  CHECK_THROWS_WITH(porosity_profile({z_bottom, z_bottom}, {a, -a}, z_bottom, z_top, area, 3), Catch::Contains("r[1]"));
}
