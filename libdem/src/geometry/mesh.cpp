// Mesh checks and builders. Vertex angles are computed from the segment index, never
// accumulated, so a closed ring meets itself exactly.
#include "dem/geometry/mesh.hpp"

#include <climits>
#include <cmath>
#include <string>

#include "dem/base/errors.hpp"
#include "dem/geometry/triangle.hpp"

namespace dem::geometry {

namespace {

constexpr int max_segments = 1'000'000;  // keeps every vertex index far inside int

void require_length(const std::string& name, double value) {
  require(std::isfinite(value) && value > 0.0, name, value, "finite and > 0 (m)");
}

void require_segments(const std::string& name, int segments) {
  require(segments >= 3 && segments <= max_segments, name, segments, "between 3 and 1000000");
}

void require_finite_point(const std::string& name, const Vec3& p) {
  require(p.allFinite(), name, detail::format_point(p), "finite");
}

// Angle of rim vertex k of n, in rad.
double rim_angle(int k, int n) { return 2.0 * pi * static_cast<double>(k) / n; }

}  // namespace

void TriangleMesh::validate() const {
  require(vertices.size() <= static_cast<std::size_t>(INT_MAX), "mesh vertex count",
          vertices.size(), "<= INT_MAX (indices are int)");
  const int n_vertices = static_cast<int>(vertices.size());
  // The checks come before the messages: building a message per vertex would dominate the cost.
  for (int i = 0; i < n_vertices; ++i) {
    if (vertices[i].allFinite()) continue;
    require_finite_point("mesh vertex " + std::to_string(i), vertices[i]);
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int index : triangles[t]) {
      if (index >= 0 && index < n_vertices) continue;
      require(false, "mesh triangle " + std::to_string(t) + " vertex index", index,
              "in [0, " + std::to_string(n_vertices) + ")");
    }
  }
  if (triangles.empty()) return;

  const auto describe = [this](std::size_t t) {
    const auto& [i, j, k] = triangles[t];
    return "mesh triangle " + std::to_string(t) + " (vertex indices " + std::to_string(i) + ", " +
           std::to_string(j) + ", " + std::to_string(k) + ")";
  };
  const auto [low, high] = bounding_box();
  const double diagonal = (high - low).norm();  // m
  if (diagonal == 0.0) {  // every vertex is the same point: no scale to compare areas with
    throw InputError(describe(0) + ": all mesh vertices coincide at " +
                     detail::format_point(low) + "; triangles must have non-zero area");
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& [i, j, k] = triangles[t];
    try {
      validate_triangle(vertices[i], vertices[j], vertices[k], diagonal);
    } catch (const InputError& e) {
      throw InputError(describe(t) + ": " + e.what());
    }
  }
}

void TriangleMesh::translate(const Vec3& offset) {
  for (Vec3& v : vertices) v += offset;
}

std::pair<Vec3, Vec3> TriangleMesh::bounding_box() const {
  require(!vertices.empty(), "mesh vertex count", 0, ">= 1 for a bounding box");
  Vec3 low = vertices.front();
  Vec3 high = vertices.front();
  for (const Vec3& v : vertices) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  return {low, high};
}

double TriangleMesh::area() const {
  double sum = 0.0;  // m^2
  for (const auto& [i, j, k] : triangles) {
    sum += triangle_area(vertices[i], vertices[j], vertices[k]);
  }
  return sum;
}

TriangleMesh make_disc(const Vec3& centre, double radius, const Vec3& normal, int segments) {
  require_finite_point("disc centre", centre);
  require_length("disc radius", radius);
  require(normal.allFinite() && normal.norm() > 0.0, "disc normal", detail::format_point(normal),
          "a finite, non-zero vector");
  require_segments("disc segments", segments);

  // In-plane basis with u x v = n, so counter-clockwise rim order gives normals along n.
  const Vec3 n = normal.normalized();
  const Vec3 u = n.unitOrthogonal();
  const Vec3 v = n.cross(u);

  TriangleMesh mesh;
  mesh.vertices.reserve(segments + 1);
  mesh.vertices.push_back(centre);
  for (int k = 0; k < segments; ++k) {
    const double angle = rim_angle(k, segments);
    mesh.vertices.push_back(centre + radius * (std::cos(angle) * u + std::sin(angle) * v));
  }
  for (int k = 0; k < segments; ++k) {
    mesh.triangles.push_back({0, 1 + k, 1 + (k + 1) % segments});
  }
  mesh.validate();
  return mesh;
}

TriangleMesh make_rectangle(const Vec3& centre, const Vec3& half_u, const Vec3& half_v) {
  require_finite_point("rectangle centre", centre);
  require_finite_point("rectangle half_u", half_u);
  require_finite_point("rectangle half_v", half_v);
  require_length("rectangle |half_u|", half_u.norm());
  require_length("rectangle |half_v|", half_v.norm());
  // Relative test: cosine of the angle between the sides, not an absolute length.
  const double cosine = half_u.dot(half_v) / (half_u.norm() * half_v.norm());
  require(std::abs(cosine) <= 1e-9, "rectangle cos(angle between half_u and half_v)", cosine,
          "0 within 1e-9 (perpendicular sides)");

  TriangleMesh mesh;
  mesh.vertices = {centre - half_u - half_v, centre + half_u - half_v, centre + half_u + half_v,
                   centre - half_u + half_v};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};  // (v1 - v0) x (v2 - v0) = 4 half_u x half_v
  mesh.validate();
  return mesh;
}

TriangleMesh make_cylinder_shell(const Vec3& base_centre, double radius, double height,
                                 int segments, bool normals_inward) {
  require_finite_point("cylinder base_centre", base_centre);
  require_length("cylinder radius", radius);
  require_length("cylinder height", height);
  require_segments("cylinder segments", segments);

  // Vertices 0..n-1 on the bottom rim, n..2n-1 on the top rim.
  TriangleMesh mesh;
  mesh.vertices.reserve(2 * segments);
  for (const double z : {0.0, height}) {
    for (int k = 0; k < segments; ++k) {
      const double angle = rim_angle(k, segments);
      mesh.vertices.push_back(base_centre +
                              Vec3(radius * std::cos(angle), radius * std::sin(angle), z));
    }
  }
  mesh.triangles.reserve(2 * segments);
  for (int k = 0; k < segments; ++k) {
    const int bottom = k;
    const int bottom_next = (k + 1) % segments;
    const int top = segments + bottom;
    const int top_next = segments + bottom_next;
    // Counter-clockwise seen from outside: (rim tangent) x (+z) points away from the axis.
    if (normals_inward) {
      mesh.triangles.push_back({bottom, top_next, bottom_next});
      mesh.triangles.push_back({bottom, top, top_next});
    } else {
      mesh.triangles.push_back({bottom, bottom_next, top_next});
      mesh.triangles.push_back({bottom, top_next, top});
    }
  }
  mesh.validate();
  return mesh;
}

TriangleMesh merge(const TriangleMesh& first, const TriangleMesh& second) {
  const std::size_t total = first.vertices.size() + second.vertices.size();
  require(total <= static_cast<std::size_t>(INT_MAX), "merged mesh vertex count", total,
          "<= INT_MAX (indices are int)");
  const int offset = static_cast<int>(first.vertices.size());

  TriangleMesh merged = first;
  merged.vertices.insert(merged.vertices.end(), second.vertices.begin(), second.vertices.end());
  merged.triangles.reserve(first.triangles.size() + second.triangles.size());
  for (const auto& [i, j, k] : second.triangles) {
    merged.triangles.push_back({i + offset, j + offset, k + offset});
  }
  return merged;
}

}  // namespace dem::geometry
