// Principal stresses against closed-form values (docs/model.md 6.3, test T6).
#include <dem/core/errors.hpp>
#include <dem/measure/principal_stress.hpp>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

using dem::Mat3;
using dem::Vec3;
using dem::measure::principal_stresses;

namespace {

// Compression-positive components -> the tension-positive tensor the function takes.
Mat3 tension_positive(const Mat3& compression_positive) { return -compression_positive; }

Mat3 rotation(double angle_rad, const Vec3& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

}  // namespace

TEST_CASE("principal stresses: T6 in-plane values and rotation", "[measure]") {
  Mat3 s = Mat3::Zero();  // Pa, compression positive; s_yy between the in-plane values
  s(0, 0) = 100.0;
  s(2, 2) = 200.0;
  s(0, 2) = s(2, 0) = 50.0;
  s(1, 1) = 150.0;
  const auto p = principal_stresses(tension_positive(s));

  // Exact: (100 + 200)/2 +- sqrt(50^2 + 50^2) = 150 +- 50 sqrt(2). The eigen-solver is backward
  // stable, so errors are ~1e-16 * |s| = 2e-14 Pa; 1e-9 Pa leaves room for any platform.
  const double r = 50.0 * std::sqrt(2.0);
  CHECK(p.sigma_1 == Approx(150.0 + r).margin(1e-9));
  CHECK(p.sigma_2 == Approx(150.0).margin(1e-9));
  CHECK(p.sigma_3 == Approx(150.0 - r).margin(1e-9));
  // docs/model.md quotes three decimals: half a unit of the last digit.
  CHECK(p.sigma_1 == Approx(220.711).margin(5e-4));
  CHECK(p.sigma_3 == Approx(79.289).margin(5e-4));

  // psi = 0.5 atan2(100, 100) = 22.5 deg towards +x; same tolerance argument (rounding only).
  CHECK(p.rotation_xz_deg == Approx(22.5).margin(1e-10));
  CHECK(p.rotation_yz_deg == Approx(0.0).margin(1e-10));  // s_yz = 0, s_zz > s_yy
  CHECK(p.tilt_deg == Approx(22.5).margin(1e-6));         // e1 lies in x-z: tilt = psi
  const double psi = 22.5 * dem::pi / 180.0;
  CHECK((p.direction_1 - Vec3(std::sin(psi), 0.0, std::cos(psi))).norm() < 1e-12);
  CHECK((p.direction_2 - Vec3(0.0, 1.0, 0.0)).norm() < 1e-12);
  CHECK((p.direction_3 - Vec3(-std::cos(psi), 0.0, std::sin(psi))).norm() < 1e-12);
}

TEST_CASE("principal stresses: rotated diagonal tensor is recovered", "[measure]") {
  // s = R diag(3, 2, 1) R^T has eigenvalues 3, 2, 1 with eigenvectors the columns of R.
  const Mat3 rot = rotation(0.7, Vec3(1.0, 2.0, 3.0));
  const Mat3 s = rot * Vec3(3e5, 2e5, 1e5).asDiagonal() * rot.transpose();  // Pa
  const auto p = principal_stresses(tension_positive(s));

  // Rounding only: ~1e-16 relative to 3e5 Pa. 1e-12 relative is generous.
  CHECK(p.sigma_1 == Approx(3e5).epsilon(1e-12));
  CHECK(p.sigma_2 == Approx(2e5).epsilon(1e-12));
  CHECK(p.sigma_3 == Approx(1e5).epsilon(1e-12));
  // Eigenvalue gaps are 1e5 Pa, so the eigenvector error is ~1e-16 * 3e5 / 1e5; sign-free check.
  CHECK(std::abs(p.direction_1.dot(rot.col(0))) == Approx(1.0).margin(1e-12));
  CHECK(std::abs(p.direction_2.dot(rot.col(1))) == Approx(1.0).margin(1e-12));
  CHECK(std::abs(p.direction_3.dot(rot.col(2))) == Approx(1.0).margin(1e-12));
  CHECK(p.direction_1.z() >= 0.0);  // documented sign choice: pointing upwards
  CHECK(p.direction_2.z() >= 0.0);
  CHECK(p.direction_3.z() >= 0.0);
  const double tilt = std::acos(std::abs(rot.col(0).z())) * 180.0 / dem::pi;
  CHECK(p.tilt_deg == Approx(tilt).margin(1e-6));
}

TEST_CASE("principal stresses: sign conventions of values and angles", "[measure]") {
  SECTION("vertical compression is a positive sigma_1 along +z, psi = 0") {
    Mat3 sigma = Mat3::Zero();  // Pa, tension positive
    sigma(2, 2) = -2e5;
    sigma(0, 0) = sigma(1, 1) = -1e5;
    const auto p = principal_stresses(sigma);
    CHECK(p.sigma_1 == Approx(2e5));
    CHECK(p.sigma_3 == Approx(1e5));
    CHECK((p.direction_1 - Vec3::UnitZ()).norm() < 1e-12);
    CHECK(p.rotation_xz_deg == 0.0);
    CHECK(p.tilt_deg == Approx(0.0).margin(1e-6));
  }
  SECTION("tension comes out negative") {
    Mat3 sigma = Mat3::Zero();
    sigma(0, 0) = 50.0;  // Pa, tension along x
    const auto p = principal_stresses(sigma);
    CHECK(p.sigma_1 == Approx(0.0).margin(1e-12));
    CHECK(p.sigma_3 == Approx(-50.0));
    CHECK((p.direction_3 - Vec3::UnitX()).norm() < 1e-12);
    // s_zz - s_xx = 50 > 0 with no shear: the in-plane major direction is vertical.
    CHECK(p.rotation_xz_deg == 0.0);
  }
  SECTION("major direction rotated towards +x gives positive psi") {
    // Major compression along z rotated by +30 deg about y: R_y(30) z = (sin 30, 0, cos 30).
    const double beta = 30.0 * dem::pi / 180.0;
    const Mat3 rot = rotation(beta, Vec3::UnitY());
    const Mat3 s = rot * Vec3(1e5, 1.5e5, 3e5).asDiagonal() * rot.transpose();
    const auto p = principal_stresses(tension_positive(s));
    CHECK(p.rotation_xz_deg == Approx(30.0).margin(1e-9));  // rounding only
    CHECK(p.rotation_yz_deg == Approx(0.0).margin(1e-9));
    CHECK(p.tilt_deg == Approx(30.0).margin(1e-6));
    CHECK(p.direction_1.x() > 0.0);
  }
  SECTION("major direction rotated towards +y gives positive yz angle") {
    // R_x(-beta) z = (0, sin beta, cos beta).
    const double beta = 40.0 * dem::pi / 180.0;
    const Mat3 rot = rotation(-beta, Vec3::UnitX());
    const Mat3 s = rot * Vec3(1.5e5, 1e5, 3e5).asDiagonal() * rot.transpose();
    const auto p = principal_stresses(tension_positive(s));
    CHECK(p.rotation_yz_deg == Approx(40.0).margin(1e-9));
    CHECK(p.rotation_xz_deg == Approx(0.0).margin(1e-9));
    CHECK(p.tilt_deg == Approx(40.0).margin(1e-6));
  }
  SECTION("in-plane major direction horizontal gives psi = 90, not -90") {
    Mat3 s = Mat3::Zero();
    s(0, 0) = 3.0;  // Pa; s_xz = -0.0 after the sign flip must not give -90
    s(2, 2) = 1.0;
    const auto p = principal_stresses(tension_positive(s));
    CHECK(p.rotation_xz_deg == 90.0);
  }
}

TEST_CASE("principal stresses: hydrostatic state", "[measure]") {
  // p I is invariant under rotation; the rotated copy carries rounding noise ~1e-16 * p in the
  // off-diagonals, which must not be read as a principal direction.
  const double pressure = 2e5;  // Pa
  const Mat3 rot = rotation(1.1, Vec3(0.3, -0.5, 0.8));
  const Mat3 s = rot * (pressure * Mat3::Identity()) * rot.transpose();
  const auto p = principal_stresses(tension_positive(s));
  CHECK(p.sigma_1 == Approx(pressure).epsilon(1e-12));
  CHECK(p.sigma_2 == Approx(pressure).epsilon(1e-12));
  CHECK(p.sigma_3 == Approx(pressure).epsilon(1e-12));
  CHECK(p.rotation_xz_deg == 0.0);
  CHECK(p.rotation_yz_deg == 0.0);
  // Any orthonormal basis is allowed; check that it is one.
  CHECK(std::abs(p.direction_1.dot(p.direction_2)) < 1e-12);
  CHECK(std::abs(p.direction_1.dot(p.direction_3)) < 1e-12);
  CHECK(p.direction_1.norm() == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("principal stresses: bad input throws InputError", "[measure]") {
  Mat3 sigma = -1e5 * Mat3::Identity();
  SECTION("NaN") {
    sigma(1, 2) = sigma(2, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(principal_stresses(sigma), dem::InputError);
    CHECK_THROWS_WITH(principal_stresses(sigma), Catch::Contains("stress[1][2]"));
  }
  SECTION("infinity") {
    sigma(0, 0) = std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS(principal_stresses(sigma), dem::InputError);
  }
  SECTION("not symmetric") {
    sigma(0, 1) = 1e3;  // Pa; 1 % of the largest entry
    CHECK_THROWS_AS(principal_stresses(sigma), dem::InputError);
    CHECK_THROWS_WITH(principal_stresses(sigma), Catch::Contains("symmetric"));
  }
}
