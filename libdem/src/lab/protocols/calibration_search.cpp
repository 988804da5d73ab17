// Batched root and pattern searches of the calibration (see calibration.hpp for why these).
#include <dem/lab/protocols/calibration.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <dem/core/errors.hpp>

namespace dem::lab {

using detail::short_text;

// ---------------------------------------------------------------- RootSearch

RootSearch::RootSearch(Settings settings) : s_(settings) {
  require(std::isfinite(s_.lower) && std::isfinite(s_.upper) && s_.lower < s_.upper, "root search bounds", short_text(s_.lower) + ", " + short_text(s_.upper),
          "finite with lower < upper");
  require(s_.start >= s_.lower && s_.start <= s_.upper, "root search start", s_.start,
          "within [" + short_text(s_.lower) + ", " + short_text(s_.upper) + "]");
  require_positive("root search first_step", s_.first_step);
  require_positive("root search max_step", s_.max_step);
  require_positive("root search slope_guess", s_.slope_guess);
  require_non_negative("root search tolerance", s_.tolerance);
  require_non_negative("root search u_tolerance", s_.u_tolerance);
  require(s_.batch_size >= 1, "root search batch_size", s_.batch_size, ">= 1");
  require(s_.max_evaluations >= 0, "root search max_evaluations", s_.max_evaluations, ">= 0");
}

void RootSearch::seed(double u, double g) {
  require(std::isfinite(u) && std::isfinite(g), "root search seed", short_text(u) + ", " + short_text(g), "finite");
  const auto at = std::lower_bound(points_.begin(), points_.end(), u, [](const Point& p, double x) { return p.u < x; });
  points_.insert(at, Point{u, g});
  check_done();
}

double RootSearch::best() const {
  require(!points_.empty(), "root search points", 0, "at least one before best()");
  const auto it = std::min_element(points_.begin(), points_.end(),
                                   [](const Point& a, const Point& b) { return std::abs(a.g) < std::abs(b.g); });
  return it->u;
}

double RootSearch::best_value() const {
  const double u = best();
  for (const Point& p : points_)
    if (p.u == u) return p.g;
  return 0.0;  // unreachable
}

void RootSearch::finish(const std::string& why) {
  if (done_) return;
  done_ = true;
  reason_ = why;
}

void RootSearch::check_done() {
  if (done_ || points_.empty()) return;
  if (std::abs(best_value()) <= s_.tolerance) return finish("converged: |mismatch| = " + short_text(std::abs(best_value())) + " <= " + short_text(s_.tolerance));
  for (std::size_t i = 0; i + 1 < points_.size(); ++i)
    if (points_[i].g * points_[i + 1].g < 0 && points_[i + 1].u - points_[i].u <= s_.u_tolerance)
      return finish("converged: bracket narrower than " + short_text(s_.u_tolerance));
  if (evaluations_ >= s_.max_evaluations) finish("trial budget of the stage used");
}

std::vector<double> RootSearch::candidates() const {
  const int b = s_.batch_size;
  auto clamp = [&](double u) { return std::clamp(u, s_.lower, s_.upper); };
  std::vector<double> c;
  if (points_.empty()) {
    if (b == 1) return {clamp(s_.start)};
    for (int j = 0; j < b; ++j) c.push_back(clamp(s_.start - 0.5 * s_.first_step + s_.first_step * j / (b - 1)));
    return c;
  }
  // A sign change between neighbours brackets a root; take the one at the best-matching point.
  std::size_t bracket = points_.size();
  double bracket_score = 0.0;
  for (std::size_t i = 0; i + 1 < points_.size(); ++i) {
    if (!(points_[i].g * points_[i + 1].g < 0)) continue;
    const double score = std::min(std::abs(points_[i].g), std::abs(points_[i + 1].g));
    if (bracket == points_.size() || score < bracket_score) bracket = i, bracket_score = score;
  }
  if (bracket < points_.size()) {
    const Point a = points_[bracket], z = points_[bracket + 1];
    const double w = z.u - a.u;
    double p = a.u - a.g * w / (z.g - a.g);  // regula falsi
    p = std::clamp(p, a.u + 0.1 * w, z.u - 0.1 * w);
    c.push_back(p);
    const double side = (z.u - p > p - a.u) ? 1.0 : -1.0;  // first extra point towards the larger part
    for (int j = 1; j < b; ++j) {
      const double offset = 0.15 * w * ((j + 1) / 2) * ((j % 2 == 1) ? side : -side);
      c.push_back(std::clamp(p + offset, a.u + 0.02 * w, z.u - 0.02 * w));
    }
    return c;
  }
  // No sign change yet: a secant step from the two best points (or the guessed slope), limited.
  std::vector<Point> by_match = points_;
  std::stable_sort(by_match.begin(), by_match.end(), [](const Point& x, const Point& y) { return std::abs(x.g) < std::abs(y.g); });
  const Point best_point = by_match.front();
  double slope = s_.slope_guess;
  if (by_match.size() >= 2 && by_match[1].u != best_point.u) {
    const double secant = (by_match[1].g - best_point.g) / (by_match[1].u - best_point.u);
    if (std::isfinite(secant) && secant > 0.1 * s_.slope_guess) slope = secant;  // a flat or falling secant is noise
  }
  const double move = std::clamp(-best_point.g / slope, -s_.max_step, s_.max_step);
  const double p = clamp(best_point.u + move);
  c.push_back(p);
  for (int j = 1; j < b; ++j) c.push_back(clamp(p + j * (p - best_point.u)));  // further out, to catch a bracket
  return c;
}

std::vector<double> RootSearch::propose() {
  if (!done_ && evaluations_ >= s_.max_evaluations) finish("trial budget of the stage used");
  if (done_) return {};
  const double same = 1e-9 * (s_.upper - s_.lower);
  std::vector<double> batch;
  for (double u : candidates()) {
    const bool known = std::any_of(points_.begin(), points_.end(), [&](const Point& p) { return std::abs(p.u - u) <= same; }) ||
                       std::any_of(batch.begin(), batch.end(), [&](double v) { return std::abs(v - u) <= same; });
    if (!known && static_cast<int>(batch.size()) < s_.max_evaluations - evaluations_) batch.push_back(u);
  }
  if (batch.empty()) finish("no new point within the bounds [" + short_text(s_.lower) + ", " + short_text(s_.upper) + "]");
  return batch;
}

void RootSearch::tell(const std::vector<double>& u, const std::vector<double>& g) {
  require(u.size() == g.size(), "root search values", g.size(), "one per point (" + std::to_string(u.size()) + ")");
  for (std::size_t k = 0; k < u.size(); ++k) {
    require(std::isfinite(u[k]) && std::isfinite(g[k]), "root search value", short_text(u[k]) + ", " + short_text(g[k]), "finite");
    const auto at = std::lower_bound(points_.begin(), points_.end(), u[k], [](const Point& p, double x) { return p.u < x; });
    points_.insert(at, Point{u[k], g[k]});
  }
  evaluations_ += static_cast<int>(u.size());
  check_done();
}

// ---------------------------------------------------------------- PatternSearch

PatternSearch::PatternSearch(Settings settings) : s_(std::move(settings)) {
  const std::size_t n = s_.start.size();
  require(n >= 1, "pattern search dimensions", n, ">= 1");
  for (const auto* v : {&s_.lower, &s_.upper, &s_.step, &s_.min_step})
    require(v->size() == n, "pattern search settings size", v->size(), "one per dimension (" + std::to_string(n) + ")");
  for (std::size_t d = 0; d < n; ++d) {
    require(s_.lower[d] <= s_.start[d] && s_.start[d] <= s_.upper[d], "pattern search start", s_.start[d],
            "within [" + short_text(s_.lower[d]) + ", " + short_text(s_.upper[d]) + "]");
    require_positive("pattern search step", s_.step[d]);
    require_positive("pattern search min_step", s_.min_step[d]);
  }
  require(s_.shrink > 0 && s_.shrink < 1, "pattern search shrink", s_.shrink, "in (0, 1)");
  require(s_.max_evaluations >= 0, "pattern search max_evaluations", s_.max_evaluations, ">= 0");
  require(std::isfinite(s_.start_value), "pattern search start_value", s_.start_value, "finite");
  centre_ = s_.start;
  centre_value_ = s_.start_value;
  known_.push_back(s_.start);
  step_ = s_.step;
}

std::vector<std::vector<double>> PatternSearch::propose() {
  if (evaluations_ >= s_.max_evaluations) finish("trial budget of the stage used");
  if (done_) return {};
  auto same = [&](const std::vector<double>& a, const std::vector<double>& b) {
    for (std::size_t d = 0; d < a.size(); ++d)
      if (std::abs(a[d] - b[d]) > 1e-9 * (s_.upper[d] - s_.lower[d])) return false;
    return true;
  };
  while (true) {
    std::vector<std::vector<double>> batch;
    for (std::size_t d = 0; d < centre_.size(); ++d)
      for (double sign : {-1.0, 1.0}) {
        std::vector<double> x = centre_;
        x[d] = std::clamp(centre_[d] + sign * step_[d], s_.lower[d], s_.upper[d]);
        const bool known = std::any_of(known_.begin(), known_.end(), [&](const auto& k) { return same(k, x); });
        if (!known && static_cast<int>(batch.size()) < s_.max_evaluations - evaluations_) batch.push_back(x);
      }
    if (!batch.empty()) return batch;
    // Every neighbour is known (or outside the bounds): as after a round without improvement.
    if (!shrink()) return {};
  }
}

void PatternSearch::tell(const std::vector<std::vector<double>>& x, const std::vector<double>& f) {
  require(x.size() == f.size(), "pattern search values", f.size(), "one per point (" + std::to_string(x.size()) + ")");
  evaluations_ += static_cast<int>(x.size());
  std::size_t best = x.size();
  for (std::size_t k = 0; k < x.size(); ++k) {
    require(std::isfinite(f[k]), "pattern search value", f[k], "finite");
    if (f[k] < centre_value_ && (best == x.size() || f[k] < f[best])) best = k;
  }
  for (const auto& point : x) known_.push_back(point);
  if (best < x.size()) {
    centre_ = x[best];
    centre_value_ = f[best];
  } else if (!shrink()) {
    return;
  }
  if (evaluations_ >= s_.max_evaluations) finish("trial budget of the stage used");
}

bool PatternSearch::shrink() {
  bool small = true;
  for (std::size_t d = 0; d < step_.size(); ++d) {
    step_[d] *= s_.shrink;
    small = small && step_[d] < s_.min_step[d];
  }
  if (small) finish("step below the smallest step");
  return !small;
}

void PatternSearch::finish(const std::string& why) {
  if (done_) return;
  done_ = true;
  reason_ = why;
}

}  // namespace dem::lab
