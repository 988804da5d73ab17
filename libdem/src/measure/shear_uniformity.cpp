// Shear uniformity and non-coaxiality (docs/model.md 8, 6.3). Sums of deviations are taken from
// the first value rather than from a computed mean, so that equal values give exactly zero
// (a rigid third has strain 0, not rounding noise that would make the strain ratio huge).
#include <dem/measure/shear_uniformity.hpp>

#include <dem/core/errors.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace dem::measure {
namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();
constexpr double rad_to_deg = 180.0 / pi;
constexpr double relative_zero = 1e-12;  // rounding is ~1e-16 relative; see principal_stress.cpp

// "name[i]", built with a stream (see relative_difference.cpp on GCC 12 and string concatenation).
std::string element(const std::string& name, std::size_t i) {
  std::ostringstream out;
  out << name << '[' << i << ']';
  return out.str();
}

void require_plates(double z_bottom, double z_top) {
  require(std::isfinite(z_bottom), "z_bottom", z_bottom, "finite (m)");
  require(std::isfinite(z_top), "z_top", z_top, "finite (m)");
  std::ostringstream allowed;
  allowed.precision(10);
  allowed << "> z_bottom = " << z_bottom << " (m)";
  require(z_top > z_bottom, "z_top", z_top, allowed.str());
}

// Least-squares slope of y against x; NaN for fewer than 2 points.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2) return not_a_number;
  double x_mean = 0.0;
  for (const double xi : x) x_mean += xi;
  x_mean /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - x_mean) * (x[i] - x_mean);
    sxy += (x[i] - x_mean) * (y[i] - y[0]);  // sum (x - x_mean) = 0, so any y offset will do
  }
  return sxx > 0.0 ? sxy / sxx : not_a_number;
}

// Major direction of the d-z sub-tensor of S's symmetric part.
double major_direction_dz_deg(const Mat3& s, const Vec3& d) {
  if (!s.allFinite()) return not_a_number;
  const Vec3 ez = Vec3::UnitZ();
  return major_direction_deg(d.dot(s * d), s(2, 2), 0.5 * (d.dot(s * ez) + ez.dot(s * d)));
}

}  // namespace

DisplacementProfile displacement_profile(const std::vector<double>& z, const std::vector<double>& u, double z_bottom,
                                         double z_top, int bins) {
  require(bins >= 1, "bins", bins, ">= 1");
  require(u.size() == z.size(), "u.size()", u.size(), "equal to z.size() = " + std::to_string(z.size()));
  require_plates(z_bottom, z_top);
  const auto n = static_cast<std::size_t>(bins);
  const double h = (z_top - z_bottom) / bins;  // m

  DisplacementProfile p;
  p.z_centre.resize(n);
  p.z_mean.assign(n, 0.0);
  p.mean_displacement.assign(n, 0.0);
  p.count.assign(n, 0);
  for (std::size_t b = 0; b < z.size(); ++b) {
    require(std::isfinite(z[b]), element("z", b), z[b], "finite (m)");
    require(std::isfinite(u[b]), element("u", b), u[b], "finite (m)");
    // Clamp before the cast: a far-away ball would overflow the integer.
    const double t = std::clamp(std::floor((z[b] - z_bottom) / h), 0.0, static_cast<double>(n - 1));
    const auto i = static_cast<std::size_t>(t);
    p.z_mean[i] += z[b];
    p.mean_displacement[i] += u[b];
    ++p.count[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    p.z_centre[i] = z_bottom + (static_cast<double>(i) + 0.5) * h;
    const double k = static_cast<double>(p.count[i]);
    p.z_mean[i] = p.count[i] > 0 ? p.z_mean[i] / k : not_a_number;
    p.mean_displacement[i] = p.count[i] > 0 ? p.mean_displacement[i] / k : not_a_number;
  }
  return p;
}

std::vector<double> porosity_profile(const std::vector<double>& z, const std::vector<double>& r, double z_bottom,
                                     double z_top, double area, int bins) {
  require(bins >= 1, "bins", bins, ">= 1");
  require(z.size() == r.size(), "r entries", r.size(), "the number of heights z, " + std::to_string(z.size()));
  require(std::isfinite(area) && area > 0, "area", area, "finite and > 0 (m^2)");
  require_plates(z_bottom, z_top);
  const double slab = (z_top - z_bottom) / bins;
  // Volume of the sphere of radius a centred at 0 below the plane at height t.
  auto below = [](double a, double t) {
    const double h = std::clamp(t + a, 0.0, 2 * a);
    return pi * h * h * (3 * a - h) / 3;
  };
  std::vector<double> solid(static_cast<std::size_t>(bins), 0.0);
  for (std::size_t b = 0; b < z.size(); ++b) {
    require(std::isfinite(z[b]), element("z", b), z[b], "finite (m)");
    require(std::isfinite(r[b]) && r[b] > 0, element("r", b), r[b], "finite and > 0 (m)");
    const int first = std::clamp(static_cast<int>(std::floor((z[b] - r[b] - z_bottom) / slab)), 0, bins - 1);
    const int last = std::clamp(static_cast<int>(std::floor((z[b] + r[b] - z_bottom) / slab)), 0, bins - 1);
    for (int k = first; k <= last; ++k) {
      const double lo = k == 0 ? -r[b] : z_bottom + k * slab - z[b];         // the end slabs take what
      const double hi = k == bins - 1 ? r[b] : z_bottom + (k + 1) * slab - z[b];  // lies beyond a plate
      solid[static_cast<std::size_t>(k)] += below(r[b], hi) - below(r[b], lo);
    }
  }
  std::vector<double> porosity(solid.size());
  for (std::size_t k = 0; k < solid.size(); ++k) porosity[k] = 1.0 - solid[k] / (area * slab);
  return porosity;
}

ShearUniformity shear_uniformity(const DisplacementProfile& profile, double z_bottom, double z_top, double u_bottom,
                                 double u_top) {
  const std::size_t n = profile.z_centre.size();
  require(n >= 3, "profile.z_centre.size()", n, ">= 3 (bins)");
  const std::string sizes = "equal to profile.z_centre.size() = " + std::to_string(n);
  require(profile.z_mean.size() == n, "profile.z_mean.size()", profile.z_mean.size(), sizes);
  require(profile.mean_displacement.size() == n, "profile.mean_displacement.size()", profile.mean_displacement.size(),
          sizes);
  require(profile.count.size() == n, "profile.count.size()", profile.count.size(), sizes);
  require_plates(z_bottom, z_top);
  require(std::isfinite(u_bottom), "u_bottom", u_bottom, "finite (m)");
  require(std::isfinite(u_top), "u_top", u_top, "finite (m)");
  const double height = z_top - z_bottom;

  // (z_mean, mean) of the non-empty bins, all of them and by third.
  std::vector<double> z, m;
  std::array<std::vector<double>, 3> third_z, third_m;
  for (std::size_t i = 0; i < n; ++i) {
    require(std::isfinite(profile.z_centre[i]), element("profile.z_centre", i), profile.z_centre[i], "finite (m)");
    if (profile.count[i] == 0) continue;
    const double zi = profile.z_mean[i], mi = profile.mean_displacement[i];
    require(std::isfinite(zi), element("profile.z_mean", i), zi, "finite (m) in a non-empty bin");
    require(std::isfinite(mi), element("profile.mean_displacement", i), mi, "finite (m) in a non-empty bin");
    const auto third =
        static_cast<std::size_t>(std::clamp(std::floor(3.0 * (profile.z_centre[i] - z_bottom) / height), 0.0, 2.0));
    z.push_back(zi);
    m.push_back(mi);
    third_z[third].push_back(zi);
    third_m[third].push_back(mi);
  }

  ShearUniformity out{not_a_number, not_a_number, not_a_number, not_a_number, not_a_number};
  if (z.size() >= 3) {
    double offset = 0.0;  // mean of the means minus m[0]; exactly 0 if all means are equal
    for (const double mi : m) offset += mi - m[0];
    offset /= static_cast<double>(m.size());
    double ss_res = 0.0, ss_tot = 0.0;
    for (std::size_t i = 0; i < z.size(); ++i) {
      const double uniform = u_bottom + (u_top - u_bottom) * (z[i] - z_bottom) / height;
      ss_res += (m[i] - uniform) * (m[i] - uniform);
      ss_tot += (m[i] - m[0] - offset) * (m[i] - m[0] - offset);
    }
    if (ss_tot > 0.0) out.r_squared = 1.0 - ss_res / ss_tot;
  }
  // 0.0 - slope: a zero slope gives +0, not -0, in the history file.
  out.bottom_third_strain = 0.0 - slope(third_z[0], third_m[0]);
  out.middle_third_strain = 0.0 - slope(third_z[1], third_m[1]);
  out.top_third_strain = 0.0 - slope(third_z[2], third_m[2]);
  if (out.bottom_third_strain != 0.0) {
    out.top_bottom_strain_ratio = out.top_third_strain / out.bottom_third_strain;  // NaN propagates
  }
  return out;
}

double major_direction_deg(double s_dd, double s_zz, double s_dz) {
  if (!(std::isfinite(s_dd) && std::isfinite(s_zz) && std::isfinite(s_dz))) return not_a_number;
  const double deviator = std::sqrt(2.0) * std::hypot(0.5 * (s_zz - s_dd), s_dz);  // Frobenius
  const double norm = std::hypot(s_dd, s_zz, std::sqrt(2.0) * s_dz);
  if (deviator <= relative_zero * norm) return not_a_number;
  const double psi = 0.5 * std::atan2(2.0 * s_dz, s_zz - s_dd) * rad_to_deg;
  return psi <= -90.0 ? psi + 180.0 : psi;  // s_dz = -0.0 would give -90; the range is (-90, 90]
}

double non_coaxiality_deg(const Mat3& stress_compression_positive, const Mat3& strain_rate_compression_positive,
                          const Vec3& d) {
  if (!d.allFinite()) return not_a_number;
  require(std::abs(d.norm() - 1.0) <= 1e-9, "|d|", d.norm(), "1 (unit shear direction)");
  require(std::abs(d.z()) <= 1e-9, "d.z", d.z(), "0 (horizontal shear direction)");
  const double stress = major_direction_dz_deg(stress_compression_positive, d);
  const double strain_rate = major_direction_dz_deg(strain_rate_compression_positive, d);
  double difference = stress - strain_rate;  // in (-180, 180), or NaN
  if (difference > 90.0) difference -= 180.0;
  if (difference <= -90.0) difference += 180.0;
  return difference;
}

}  // namespace dem::measure
