// Closest point on a triangle, plus the area, normal and validity checks for one triangle.
//
// Why: a rigid facet wall touches a ball where the ball centre is closest to one of the wall's
// triangles (docs/model.md §0: for a facet, x2 is that closest point). This query runs for every ball
// near a wall at every time step. So it is inline, allocates nothing, takes no square root and
// makes at most six region tests.
//
// Method: the point is classified into the Voronoi region of a vertex, an edge or the face, with
// dot products only (the region tests in Ericson, "Real-Time Collision Detection", 2005, §5.1.5).
// The feature is reported too. A wall built from many triangles can then see that a contact on a
// shared edge or vertex is one contact, not two.
// Rejected: projecting onto the plane and clamping the barycentric coordinates to [0, 1]. It is
// simpler, but it does not give the closest point when the projection lies beyond an edge.
//
// Precondition for the query: the triangle is not degenerate. Walls call validate_triangle once,
// when they are built, not on every query.
#pragma once

#include <string>

#include "dem/base/math.hpp"

namespace dem::geometry {

/// Which part of a triangle a closest point lies on.
enum class Feature : unsigned char { Face, Edge, Vertex };

/// Result of closest_point_on_triangle. 32 bytes.
struct ClosestPoint {
  Vec3 point;       ///< m, the point of the triangle closest to the query point
  Feature feature;  ///< face interior, edge or vertex
  int index;        ///< edge 0: ab, 1: bc, 2: ca; or vertex 0: a, 1: b, 2: c; -1 for the face
};

/// Closest point of the triangle (a, b, c) to p (all in m).
/// On the boundary between two regions, e.g. p exactly above an edge, the lower-dimensional
/// feature (vertex before edge before face) is reported; the point is the same either way, up to
/// rounding. The triangle must not be degenerate (see validate_triangle).
inline ClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                              const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;

  // d1..d6: p relative to each vertex, projected on the two edge directions ab and ac.
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, Feature::Vertex, 0};

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, Feature::Vertex, 1};

  // va, vb, vc are the barycentric coordinates of p's projection onto the plane, each times
  // |ab x ac|^2 (Lagrange's identity turns the cross products into these dot-product terms).
  // A negative one puts the projection beyond the opposite edge.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    return {a + (d1 / (d1 - d3)) * ab, Feature::Edge, 0};  // d1 - d3 = |ab|^2
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, Feature::Vertex, 2};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    return {a + (d2 / (d2 - d6)) * ac, Feature::Edge, 2};  // d2 - d6 = |ac|^2
  }

  const double va = d3 * d6 - d5 * d4;
  const double along_bc = d4 - d3;  // (c - b).(p - b)
  const double along_cb = d5 - d6;  // (b - c).(p - c)
  if (va <= 0.0 && along_bc >= 0.0 && along_cb >= 0.0) {
    return {b + (along_bc / (along_bc + along_cb)) * (c - b), Feature::Edge, 1};  // sum = |bc|^2
  }

  const double inv_sum = 1.0 / (va + vb + vc);  // = 1/|ab x ac|^2
  return {a + (vb * inv_sum) * ab + (vc * inv_sum) * ac, Feature::Face, -1};
}

/// Area of the triangle (a, b, c), in m^2.
inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Unit normal of the triangle (a, b, c), by the right-hand rule a -> b -> c.
/// The triangle must not be degenerate.
inline Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b - a).cross(c - a).normalized();
}

/// Throws InputError, naming the vertices, if a vertex is not finite or the triangle is
/// degenerate: area < 1e-12 * length_scale^2. length_scale (m, > 0) is the size of the object
/// the triangle belongs to, e.g. a mesh's bounding-box diagonal; no absolute tolerance is used.
void validate_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double length_scale);

namespace detail {
/// "(x, y, z)", for error messages (Eigen's own printing puts each component on its own line).
std::string format_point(const Vec3& p);
}  // namespace detail

}  // namespace dem::geometry
