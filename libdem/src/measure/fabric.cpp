// Rose histograms and Fourier fits of contact fabric (docs/model.md 9). The FFT over the bins is
// overkill for 18 bins, but it keeps one code path for fine roses and matches the study's method.
#include <dem/measure/fabric.hpp>

#include <dem/core/errors.hpp>

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace dem::measure {
namespace {

constexpr double deg_to_rad = pi / 180.0;
constexpr double rad_to_deg = 180.0 / pi;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// A normal closer than this to the plane's normal has an angle dominated by rounding in the
// contact geometry (|n| is 1, so this is ~1e-4 degrees of tilt away from perpendicular).
constexpr double min_projected_length = 1e-6;

// Normals come from geometry code in double precision; 1e-6 catches unnormalised vectors
// without rejecting accumulated rounding.
constexpr double unit_tolerance = 1e-6;

Vec3 checked_unit_normal(const ContactSample& c, std::size_t index) {
  const std::string name = "contacts[" + std::to_string(index) + "]";
  const double length = c.normal.norm();
  require(std::isfinite(length) && std::abs(length - 1.0) <= unit_tolerance, name + ".normal length",
          length, "1 within 1e-6 (a finite unit vector)");
  return c.normal / length;
}

int bin_count(double bin_width_deg) {
  const std::string allowed = "a divisor of 180 between 0.001 and 60 degrees (at least 3 bins)";
  require(std::isfinite(bin_width_deg) && bin_width_deg >= 0.001 && bin_width_deg <= 60.0,
          "bin_width_deg", bin_width_deg, allowed);
  const double bins = 180.0 / bin_width_deg;
  require(std::abs(bins - std::round(bins)) <= 1e-9 * bins, "bin_width_deg", bin_width_deg, allowed);
  return static_cast<int>(std::lround(bins));
}

// (first, second) in-plane components, as documented for RosePlane.
std::array<double, 2> project(const Vec3& n, RosePlane plane) {
  switch (plane) {
    case RosePlane::ShearXZ: return {n.x(), n.z()};
    case RosePlane::HorizontalXY: return {n.x(), n.y()};
    case RosePlane::SideYZ: return {n.y(), n.z()};
  }
  throw std::logic_error("rose: unknown RosePlane");
}

// Folds degrees into [0, 180): n and -n are the same contact.
double fold_deg(double angle_deg) {
  double folded = angle_deg - 180.0 * std::floor(angle_deg / 180.0);
  return folded >= 180.0 ? folded - 180.0 : folded;  // -1e-17 + 180 rounds to 180
}

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};
struct FftwPlanDestroy {
  void operator()(fftw_plan p) const { fftw_destroy_plan(p); }
};

// Real-to-complex FFT over the M bins. Returns the k = 0 and k = 1 coefficients referred to the
// bin centres theta_m = (m + 1/2) D: the DFT refers to the lower edges, hence the factor
// exp(-i pi k / M) (docs/model.md 9.2). Planning happens here, in the calling thread.
class BinTransform {
 public:
  explicit BinTransform(int bins)
      : bins_(bins),
        in_(fftw_alloc_real(static_cast<std::size_t>(bins))),
        out_(fftw_alloc_complex(static_cast<std::size_t>(bins / 2 + 1))) {
    if (!in_ || !out_) throw std::bad_alloc();
    plan_.reset(fftw_plan_dft_r2c_1d(bins, in_.get(), out_.get(), FFTW_ESTIMATE));
    if (!plan_) throw std::runtime_error("rose: FFTW could not plan a transform of length " +
                                         std::to_string(bins));
  }

  std::array<std::complex<double>, 2> low_modes(const std::vector<double>& values) {
    std::copy(values.begin(), values.end(), in_.get());
    fftw_execute(plan_.get());
    const fftw_complex* out = out_.get();
    const std::complex<double> mode_0(out[0][0], out[0][1]);
    const std::complex<double> mode_1(out[1][0], out[1][1]);
    return {mode_0, mode_1 * std::polar(1.0, -pi / bins_)};
  }

 private:
  int bins_;
  std::unique_ptr<double, FftwFree> in_;
  std::unique_ptr<fftw_complex, FftwFree> out_;
  std::unique_ptr<std::remove_pointer_t<fftw_plan>, FftwPlanDestroy> plan_;
};

// Second-order fit from the k = 0, 1 modes of binned data: amplitude 2|X_1|/X_0, divided by
// the bin-averaging attenuation c(D) = sin(D)/D, and direction -0.5 arg(X_1) (docs/model.md 9.2).
struct Fit {
  double amplitude;      // -
  double direction_deg;  // [0, 180)
};
Fit fit(const std::array<std::complex<double>, 2>& modes, double sinc) {
  return {2.0 * std::abs(modes[1]) / modes[0].real() / sinc,
          fold_deg(-0.5 * std::arg(modes[1]) * rad_to_deg)};
}

void fill_empty(Rose& r) {
  r.a = r.theta_a_deg = r.f0 = r.a_n = r.theta_n_deg = nan;
  r.a_direct = r.theta_a_direct_deg = r.mean_force_all = nan;
}

}  // namespace

Rose rose(const std::vector<ContactSample>& contacts, RosePlane plane, double bin_width_deg) {
  const int bins = bin_count(bin_width_deg);
  const auto m_bins = static_cast<std::size_t>(bins);
  Rose r{};
  r.plane = plane;
  r.bin_width_deg = bin_width_deg;
  r.bin_lo_deg.resize(m_bins);
  for (std::size_t m = 0; m < m_bins; ++m) r.bin_lo_deg[m] = static_cast<double>(m) * bin_width_deg;
  r.count.assign(m_bins, 0);
  r.fraction.assign(m_bins, 0.0);
  r.mean_normal_force.assign(m_bins, 0.0);

  std::vector<double> force_sum(m_bins, 0.0);  // N
  double cos_2theta_sum = 0.0, sin_2theta_sum = 0.0, force_total = 0.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Vec3 n = checked_unit_normal(contacts[i], i);
    require(std::isfinite(contacts[i].normal_force),
            "contacts[" + std::to_string(i) + "].normal_force", contacts[i].normal_force, "finite (N)");
    const auto [u, v] = project(n, plane);
    const double length_sq = u * u + v * v;
    if (length_sq < min_projected_length * min_projected_length) {
      ++r.contacts_skipped;
      continue;
    }
    const double theta_deg = fold_deg(std::atan2(v, u) * rad_to_deg);
    const auto m = std::min(m_bins - 1, static_cast<std::size_t>(theta_deg / bin_width_deg));
    ++r.count[m];
    force_sum[m] += contacts[i].normal_force;
    force_total += contacts[i].normal_force;
    // cos 2theta and sin 2theta without trigonometry; the fold does not change them.
    cos_2theta_sum += (u * u - v * v) / length_sq;
    sin_2theta_sum += 2.0 * u * v / length_sq;
    ++r.contacts_used;
  }
  if (r.contacts_used == 0) {
    fill_empty(r);
    return r;
  }

  const auto used = static_cast<double>(r.contacts_used);
  for (std::size_t m = 0; m < m_bins; ++m) {
    r.fraction[m] = static_cast<double>(r.count[m]) / used;
    if (r.count[m] > 0) r.mean_normal_force[m] = force_sum[m] / static_cast<double>(r.count[m]);
  }
  r.mean_force_all = force_total / used;
  r.a_direct = 2.0 * std::hypot(cos_2theta_sum, sin_2theta_sum) / used;
  r.theta_a_direct_deg = fold_deg(0.5 * std::atan2(sin_2theta_sum, cos_2theta_sum) * rad_to_deg);

  const double width_rad = bin_width_deg * deg_to_rad;
  const double sinc = std::sin(width_rad) / width_rad;
  BinTransform transform(bins);
  const Fit normals = fit(transform.low_modes(r.fraction), sinc);
  r.a = normals.amplitude;
  r.theta_a_deg = normals.direction_deg;
  auto force_modes = transform.low_modes(r.mean_normal_force);
  for (auto& mode : force_modes) mode /= static_cast<double>(bins);  // F_k = (1/M) sum ...
  r.f0 = force_modes[0].real();
  const Fit forces = fit(force_modes, sinc);
  r.a_n = forces.amplitude;
  r.theta_n_deg = forces.direction_deg;
  return r;
}

Mat3 fabric_tensor(const std::vector<ContactSample>& contacts) {
  require(!contacts.empty(), "contacts.size()", contacts.size(), ">= 1 for a fabric tensor");
  Mat3 sum = Mat3::Zero();
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Vec3 n = checked_unit_normal(contacts[i], i);
    sum += n * n.transpose();
  }
  return sum / static_cast<double>(contacts.size());
}

RoseAsymmetry rose_asymmetry(const Rose& r) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (r.contacts_used == 0) return {nan, nan, nan, nan};
  const std::size_t n = r.count.size();  // bins of equal width from 0: bin m mirrors bin n - 1 - m
  double count_diff = 0.0, count_sum = 0.0, force_diff = 0.0, force_sum = 0.0;
  for (std::size_t m = 0; m < n; ++m) {
    const std::size_t mirror = n - 1 - m;
    count_sum += static_cast<double>(r.count[m]);
    force_sum += r.mean_normal_force[m];
    if (m < mirror) {
      count_diff += std::abs(static_cast<double>(r.count[m] - r.count[mirror]));
      force_diff += std::abs(r.mean_normal_force[m] - r.mean_normal_force[mirror]);
    }
  }
  const auto tilt = [](double theta_deg) { return 90.0 - theta_deg; };  // from the vertical, towards +x
  return {count_diff / count_sum, force_sum > 0.0 ? force_diff / force_sum : nan, tilt(r.theta_a_deg), tilt(r.theta_n_deg)};
}

}  // namespace dem::measure
