// Relative difference (docs/model.md 8). Curves are validated once per public call; the inner
// interpolation then runs without re-checking, so relative_difference stays O(n log m).
#include <dem/measure/relative_difference.hpp>

#include <dem/core/errors.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>

namespace dem::measure {
namespace {

// "name[i]". Built with a stream: GCC 12 at -O3 warns (-Wrestrict, a known false positive)
// on "[" + std::to_string(i) + "]".
std::string element(const std::string& name, std::size_t i) {
  std::ostringstream out;
  out << name << '[' << i << ']';
  return out.str();
}

void validate(const Curve& curve, const std::string& name) {
  require(curve.x.size() == curve.y.size(), name + ".y.size()", curve.y.size(),
          "equal to " + name + ".x.size() = " + std::to_string(curve.x.size()));
  require(!curve.x.empty(), name + ".x.size()", curve.x.size(), ">= 1");
  for (std::size_t i = 0; i < curve.x.size(); ++i) {
    require(std::isfinite(curve.x[i]), element(name + ".x", i), curve.x[i], "finite");
    require(std::isfinite(curve.y[i]), element(name + ".y", i), curve.y[i], "finite");
    if (i > 0 && !(curve.x[i] > curve.x[i - 1])) {
      std::ostringstream previous;
      previous.precision(10);
      previous << element(name + ".x", i - 1) << " = " << curve.x[i - 1] << " (x strictly increasing)";
      require(false, element(name + ".x", i), curve.x[i], "> " + previous.str());
    }
  }
}

// Curve already validated.
double interpolate_valid(const Curve& curve, double x) {
  const auto& xs = curve.x;
  if (x < xs.front() || x > xs.back()) return std::numeric_limits<double>::quiet_NaN();
  // First node >= x; x == xs.front() lands on node 0 and is returned exactly.
  const auto upper = std::lower_bound(xs.begin(), xs.end(), x);
  const auto i = static_cast<std::size_t>(std::distance(xs.begin(), upper));
  if (xs[i] == x) return curve.y[i];
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return curve.y[i - 1] + t * (curve.y[i] - curve.y[i - 1]);
}

}  // namespace

double interpolate(const Curve& curve, double x) {
  validate(curve, "curve");
  require(std::isfinite(x), "x", x, "finite");
  return interpolate_valid(curve, x);
}

RelativeDifference relative_difference(const Curve& lab, const Curve& model, double eps_abs) {
  validate(lab, "lab");
  validate(model, "model");
  require(std::isfinite(eps_abs) && eps_abs >= 0.0, "eps_abs", eps_abs, "finite and >= 0 (units of y)");

  RelativeDifference out{0.0, 0.0, 0, 0};
  double sum = 0.0;
  for (std::size_t k = 0; k < lab.x.size(); ++k) {
    const double y_lab = lab.y[k];
    const double y_model = interpolate_valid(model, lab.x[k]);
    if (std::abs(y_lab) < eps_abs || y_lab == 0.0 || std::isnan(y_model)) {
      ++out.points_skipped;
      continue;
    }
    const double rd = std::abs(y_lab - y_model) / std::abs(y_lab);
    out.max_percent = std::max(out.max_percent, 100.0 * rd);
    sum += rd;
    ++out.points_used;
  }
  if (out.points_used == 0) {
    std::ostringstream why;
    why << "relative_difference: no usable lab point (" << out.points_skipped
        << " skipped); need a lab point with |y_lab| >= eps_abs = " << eps_abs
        << " and y_lab != 0, inside the model's x-range [" << model.x.front() << ", "
        << model.x.back() << "]";
    throw InputError(why.str());
  }
  out.mean_percent = 100.0 * sum / static_cast<double>(out.points_used);
  return out;
}

}  // namespace dem::measure
