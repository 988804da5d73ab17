#include <dem/lab/toolkit/cyclic_path.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>

namespace dem::lab {

namespace {

const char* const shape_names[] = {"sine", "circle", "ellipse", "figure8", "series"};

}  // namespace

CyclicShape cyclic_shape_from(const std::string& name, const std::string& key) {
  for (int k = 0; k < 5; ++k)
    if (name == shape_names[k]) return static_cast<CyclicShape>(k);
  throw InputError(key + " = '" + name + "': allowed sine, circle, ellipse, figure8, series");
}

std::string to_string(CyclicShape shape) { return shape_names[static_cast<int>(shape)]; }

CyclicPath::CyclicPath(CyclicShape shape, double direction_deg, double minor_ratio) : shape_(shape), q_(minor_ratio) {
  require(shape != CyclicShape::Series, "cyclic path shape", "series", "a drawn shape (a series comes from_csv)");
  require(std::isfinite(direction_deg), "cyclic path direction_deg", direction_deg, "finite (deg)");
  require(std::isfinite(minor_ratio) && minor_ratio >= 0.0, "cyclic path minor_ratio", minor_ratio, ">= 0");
  const double a = direction_deg * pi / 180.0;
  d_ = Vec3(std::cos(a), std::sin(a), 0.0);
  e_ = Vec3(-std::sin(a), std::cos(a), 0.0);
}

CyclicPath CyclicPath::from_csv(const std::filesystem::path& file, double period) {
  const io::CsvData data = io::read_csv(file);
  const std::string where = "cyclic series " + file.string();
  const bool by_time = std::find(data.columns.begin(), data.columns.end(), "time") != data.columns.end();
  const bool by_cycle = std::find(data.columns.begin(), data.columns.end(), "cycle") != data.columns.end();
  require(by_time != by_cycle, where + " columns", data.columns.size(), "one of 'cycle' (-) or 'time' (s), then 'x' and 'y'");
  require(data.rows.size() >= 2, where + " rows", data.rows.size(), ">= 2");
  if (by_time) require(std::isfinite(period) && period > 0.0, where + ": period for a 'time' column", period, "> 0 (s)");
  CyclicPath path(CyclicShape::Sine, 0.0, 0.0);
  path.shape_ = CyclicShape::Series;
  const std::size_t t = data.column(by_time ? "time" : "cycle"), x = data.column("x"), y = data.column("y");
  for (const auto& row : data.rows) {
    const double n = by_time ? row[t] / period : row[t];
    require(n >= 0.0 && (path.cycles_.empty() || n > path.cycles_.back()), where + " row " + std::to_string(path.cycles_.size() + 1) +
            (by_time ? " time" : " cycle"), row[t], ">= 0 and increasing");
    path.cycles_.push_back(n);
    path.x_.push_back(row[x]);
    path.y_.push_back(row[y]);
  }
  return path;
}

double CyclicPath::length_cycles() const {
  return shape_ == CyclicShape::Series ? cycles_.back() : std::numeric_limits<double>::infinity();
}

Vec3 CyclicPath::at(double cycles) const {
  const double w = 2.0 * pi * cycles;
  const double ramp = std::min(1.0, 4.0 * cycles);  // circle and ellipse: from the origin over a quarter cycle
  switch (shape_) {
    case CyclicShape::Sine: return std::sin(w) * d_;
    case CyclicShape::Circle: return ramp * (std::sin(w) * d_ + std::cos(w) * e_);
    case CyclicShape::Ellipse: return ramp * (std::sin(w) * d_ + q_ * std::cos(w) * e_);
    case CyclicShape::Figure8: return std::sin(w) * d_ + q_ * std::sin(2.0 * w) * e_;
    case CyclicShape::Series: break;
  }
  if (cycles <= cycles_.front()) return Vec3(x_.front(), y_.front(), 0.0);
  if (cycles >= cycles_.back()) return Vec3(x_.back(), y_.back(), 0.0);
  const auto hi = static_cast<std::size_t>(std::upper_bound(cycles_.begin(), cycles_.end(), cycles) - cycles_.begin());
  const std::size_t lo = hi - 1;
  const double s = (cycles - cycles_[lo]) / (cycles_[hi] - cycles_[lo]);
  return Vec3(x_[lo] + s * (x_[hi] - x_[lo]), y_[lo] + s * (y_[hi] - y_[lo]), 0.0);
}

}  // namespace dem::lab
