// Principal stresses (docs/model.md 6.3). Eigen returns eigenvalues in ascending order, so the
// largest eigenvalue of s = -sigma is sigma_1.
#include <dem/measure/principal_stress.hpp>

#include <dem/core/errors.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

namespace dem::measure {
namespace {

constexpr double rad_to_deg = 180.0 / pi;

// Below this fraction of the tensor's largest entry a component counts as zero: rounding in a
// measured tensor is ~1e-16 relative, so 1e-12 separates noise from a real deviator.
constexpr double relative_zero = 1e-12;

// Deterministic sign for an eigenvector (which Eigen returns with an arbitrary sign).
Vec3 canonical_sign(Vec3 e) {
  const double z = e.z(), x = e.x(), y = e.y();
  const bool flip = std::abs(z) > relative_zero ? z < 0.0
                    : std::abs(x) > relative_zero ? x < 0.0
                                                  : y < 0.0;
  return flip ? Vec3(-e) : e;
}

// Major-direction angle from vertical in the (a, z) plane, compression positive:
// psi = 0.5 atan2(2 s_az, s_zz - s_aa), docs/model.md 6.3. An isotropic sub-tensor has no major
// direction; report 0 there instead of the angle of rounding noise.
double in_plane_rotation_deg(double s_aa, double s_zz, double s_az, double scale) {
  const double radius = std::hypot(0.5 * (s_zz - s_aa), s_az);
  if (radius <= relative_zero * scale) return 0.0;
  const double psi = 0.5 * std::atan2(2.0 * s_az, s_zz - s_aa) * rad_to_deg;
  return psi <= -90.0 ? psi + 180.0 : psi;  // s_az = -0.0 would give -90; the range is (-90, 90]
}

}  // namespace

PrincipalStresses principal_stresses(const Mat3& stress_tension_positive) {
  const Mat3& sigma = stress_tension_positive;
  double scale = 0.0;  // Pa, largest entry
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const std::string name = "stress[" + std::to_string(i) + "][" + std::to_string(j) + "]";
      require(std::isfinite(sigma(i, j)), name, sigma(i, j), "finite (Pa)");
      scale = std::max(scale, std::abs(sigma(i, j)));
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double asym = std::abs(sigma(i, j) - sigma(j, i));
      require(asym <= 1e-8 * scale,
              "|stress[" + std::to_string(i) + "][" + std::to_string(j) + "] - stress[" +
                  std::to_string(j) + "][" + std::to_string(i) + "]|",
              asym, "<= 1e-8 * max |entry| (symmetric tensor)");
    }
  }

  const Mat3 s = -0.5 * (sigma + sigma.transpose());  // compression positive
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(s);
  const Vec3 values = solver.eigenvalues();  // ascending
  const Mat3 vectors = solver.eigenvectors();

  PrincipalStresses out{};
  out.sigma_1 = values(2);
  out.sigma_2 = values(1);
  out.sigma_3 = values(0);
  out.direction_1 = canonical_sign(vectors.col(2));
  out.direction_2 = canonical_sign(vectors.col(1));
  out.direction_3 = canonical_sign(vectors.col(0));
  out.rotation_xz_deg = in_plane_rotation_deg(s(0, 0), s(2, 2), s(0, 2), scale);
  out.rotation_yz_deg = in_plane_rotation_deg(s(1, 1), s(2, 2), s(1, 2), scale);
  out.tilt_deg = std::acos(std::min(1.0, std::abs(out.direction_1.z()))) * rad_to_deg;
  return out;
}

}  // namespace dem::measure
