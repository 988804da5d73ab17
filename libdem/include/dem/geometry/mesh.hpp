// Triangle meshes for rigid facet walls, and builders for the shapes of the test apparatus
// (plates as discs or rectangles, cylindrical shells).
//
// Why indexed storage (shared vertices plus index triples) rather than three vertices per
// triangle: neighbouring triangles then share their edges exactly, so a ball on a shared edge
// finds the same closest point from both. Moving a wall also moves each vertex once.
//
// Orientation: a triangle's normal follows the right-hand rule over its vertex order. Every
// builder states where its normals point, so the caller decides which side is the front.
// The builders validate their arguments and their result; a hand-made mesh should call
// validate() before it is used.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "dem/base/math.hpp"

namespace dem::geometry {

/// Triangles sharing vertices. Triangle t has the vertices vertices[triangles[t][0..2]].
struct TriangleMesh {
  std::vector<Vec3> vertices;                // m
  std::vector<std::array<int, 3>> triangles;  // indices into vertices

  /// Throws InputError unless every vertex is finite, every index is in range and no triangle
  /// is degenerate (area < 1e-12 * d^2, d = bounding-box diagonal). Messages name the triangle
  /// or vertex index. An empty mesh is valid.
  void validate() const;

  /// Moves every vertex by offset (m).
  void translate(const Vec3& offset);

  /// Smallest and largest corner of the axis-aligned box around all vertices (m).
  /// Throws InputError for a mesh without vertices.
  std::pair<Vec3, Vec3> bounding_box() const;

  /// Sum of the triangle areas (m^2). The indices must be in range (see validate).
  double area() const;
};

/// Flat disc of `segments` triangles fanned around the centre (m); its rim is a regular polygon
/// with vertices at `radius` (m) from the centre. Every triangle normal equals normal/|normal|.
/// The polygon's area is (segments/2) radius^2 sin(2 pi/segments), a little less than pi radius^2.
/// Needs radius > 0, normal non-zero, 3 <= segments <= 1e6.
TriangleMesh make_disc(const Vec3& centre, double radius, const Vec3& normal, int segments);

/// Rectangle centre +- half_u +- half_v (m) as two triangles; half_u and half_v are
/// perpendicular half side vectors. Both triangle normals equal (half_u x half_v) normalised.
TriangleMesh make_rectangle(const Vec3& centre, const Vec3& half_u, const Vec3& half_v);

/// Open cylindrical shell with axis +z, from base_centre (m) up to base_centre + height (m) ez.
/// Its cross-section is a regular polygon of `segments` sides with vertices at `radius` (m), and
/// each side is a rectangle of two triangles. Normals point towards the axis if normals_inward
/// (balls inside, e.g. a confining ring), else away from it.
/// Needs radius > 0, height > 0, 3 <= segments <= 1e6.
TriangleMesh make_cylinder_shell(const Vec3& base_centre, double radius, double height,
                                 int segments, bool normals_inward);

/// Both meshes in one: the vertices of `second` follow those of `first`, and the indices of
/// `second` are shifted to match. Coincident vertices are not merged.
TriangleMesh merge(const TriangleMesh& first, const TriangleMesh& second);

}  // namespace dem::geometry
