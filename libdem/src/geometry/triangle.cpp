// Checks on single triangles. They live here, not in the header, because they build error
// messages and run once per triangle when a wall is built, not once per contact.
#include "dem/geometry/triangle.hpp"

#include <cmath>
#include <sstream>

#include "dem/base/errors.hpp"

namespace dem::geometry {

namespace detail {
std::string format_point(const Vec3& p) {
  std::ostringstream out;
  out.precision(10);  // same as dem::require
  out << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return out.str();
}
}  // namespace detail

void validate_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double length_scale) {
  require(std::isfinite(length_scale) && length_scale > 0.0, "triangle length_scale",
          length_scale, "finite and > 0 (m)");
  const auto vertices = [&] {
    return "a = " + detail::format_point(a) + ", b = " + detail::format_point(b) +
           ", c = " + detail::format_point(c);
  };
  if (!(a.allFinite() && b.allFinite() && c.allFinite())) {
    throw InputError("triangle vertices " + vertices() + ": must be finite");
  }
  const double area = triangle_area(a, b, c);
  const double min_area = 1e-12 * length_scale * length_scale;
  if (!(area >= min_area)) {
    std::ostringstream msg;
    msg.precision(10);
    msg << "triangle area = " << area << " m^2 (vertices " << vertices()
        << "): must be >= 1e-12 * length_scale^2 = " << min_area
        << " m^2; the triangle is degenerate (coincident or collinear vertices)";
    throw InputError(msg.str());
  }
}

}  // namespace dem::geometry
