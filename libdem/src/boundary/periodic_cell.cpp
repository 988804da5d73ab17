#include <dem/boundary/periodic_cell.hpp>

#include <cmath>
#include <sstream>

#include <dem/base/errors.hpp>

namespace dem {

namespace {

void check_matrix(const Mat3& h) {
  std::ostringstream text;
  text << "[" << h.row(0) << "; " << h.row(1) << "; " << h.row(2) << "]";
  require(h.allFinite() && h.determinant() > 0.0, "periodic cell matrix h (m, edge vectors as columns)", text.str(),
          "finite, with det h > 0 (three right-handed, independent edge vectors)");
}

}  // namespace

PeriodicCell::PeriodicCell(const Mat3& h, const Vec3& origin) : origin_(origin) {
  require(origin.allFinite(), "periodic cell origin", "(non-finite)", "finite");
  set_matrix(h);
}

PeriodicCell PeriodicCell::box(const Vec3& low, const Vec3& high) {
  return PeriodicCell((high - low).asDiagonal().toDenseMatrix(), low);
}

void PeriodicCell::set_matrix(const Mat3& h) {
  check_matrix(h);
  h_ = h;
  h_inverse_ = h.inverse();
}

void PeriodicCell::set_velocity_gradient(const Mat3& velocity_gradient) {
  require(velocity_gradient.allFinite(), "periodic cell velocity gradient L (1/s)", "(non-finite)", "finite");
  velocity_gradient_ = velocity_gradient;
}

void PeriodicCell::advance(double dt) {
  if (velocity_gradient_.isZero(0.0)) return;
  const Mat3 a = dt * velocity_gradient_;
  // exp(A) = I + A + A^2/2 + A^3/6 + A^4/24 + ..., in Horner's form
  const Mat3 step = Mat3::Identity() + a * (Mat3::Identity() + a * (0.5 * Mat3::Identity() + a * (Mat3::Identity() / 6.0 + a / 24.0)));
  set_matrix(step * h_);
}

Vec3 PeriodicCell::widths() const {
  const double v = volume();
  Vec3 w;
  for (int a = 0; a < 3; ++a) w[a] = v / h_.col((a + 1) % 3).cross(h_.col((a + 2) % 3)).norm();
  return w;
}

std::array<int, 3> PeriodicCell::cells_out(const Vec3& x) const {
  const Vec3 s = reduced(x);
  std::array<int, 3> m{0, 0, 0};
  for (int a = 0; a < 3; ++a)
    if (periodic_[static_cast<std::size_t>(a)]) m[static_cast<std::size_t>(a)] = static_cast<int>(std::floor(s[a]));
  return m;
}

Vec3 PeriodicCell::wrapped(const Vec3& x) const {
  const std::array<int, 3> m = cells_out(x);
  if (m[0] == 0 && m[1] == 0 && m[2] == 0) return x;
  return x - image_shift(m);
}

Vec3 PeriodicCell::image_shift(const std::array<int, 3>& n) const {
  return h_ * Vec3(static_cast<double>(n[0]), static_cast<double>(n[1]), static_cast<double>(n[2]));
}

Vec3 PeriodicCell::image_velocity_shift(const std::array<int, 3>& n) const {
  return velocity_gradient_ * image_shift(n);
}

ImageShifts PeriodicCell::image_shifts() const {
  ImageShifts shifts;
  for (int code = 0; code < image_count; ++code) {
    const auto n = image_vector(static_cast<ImageCode>(code));
    shifts.position[static_cast<std::size_t>(code)] = image_shift(n);
    shifts.velocity[static_cast<std::size_t>(code)] = image_velocity_shift(n);
  }
  return shifts;
}

bool PeriodicCell::remap_tilt(double tilt_limit) {
  if (!tilt_remap_) return false;
  Mat3 h = h_;
  bool changed = false;
  // Edge `moved` minus k times edge `along`, k the rounded tilt factor, if that factor exceeds the
  // limit. The factor is the component of `moved` along the unit vector `axis` (the Gram-Schmidt
  // axis of `along`) divided by `along`'s own component there.
  const auto reduce = [&](int moved, int along, const Vec3& axis) {
    const double factor = h.col(moved).dot(axis) / h.col(along).dot(axis);
    if (!(std::abs(factor) > tilt_limit)) return;
    h.col(moved) -= std::round(factor) * h.col(along);
    changed = true;
  };
  // The order of LAMMPS's flips: the third edge along the second, then along the first, then the
  // second along the first.
  const Vec3 first_axis = h.col(0).normalized();
  const Vec3 second_axis = (h.col(1) - h.col(1).dot(first_axis) * first_axis).normalized();
  reduce(2, 1, second_axis);
  reduce(2, 0, first_axis);
  reduce(1, 0, first_axis);
  if (changed) set_matrix(h);
  return changed;
}

double PeriodicCell::image_travel_since(const Mat3& then) const {
  const Mat3 moved = h_ - then;
  return moved.col(0).norm() + moved.col(1).norm() + moved.col(2).norm();
}

std::string axis_names(const std::array<bool, 3>& axes) {
  std::string names;
  for (int a = 0; a < 3; ++a)
    if (axes[static_cast<std::size_t>(a)]) names += std::string(names.empty() ? "" : " ") + "xyz"[a];
  return names.empty() ? "none" : names;
}

}  // namespace dem
