#include <dem/boundary/wall.hpp>

#include <cmath>

#include <dem/base/errors.hpp>

namespace dem {

Wall make_facet_wall(std::string name, geometry::TriangleMesh mesh, const Vec3& outward_normal,
                          double area) {
  require(!mesh.triangles.empty(), "wall '" + name + "' triangle count", 0, "> 0");
  mesh.validate();
  require(outward_normal.allFinite() && outward_normal.norm() > 0.0, "wall '" + name + "' outward_normal",
          "(zero or non-finite)", "a non-zero vector");
  Wall wall;
  wall.name = std::move(name);
  wall.area = area > 0.0 ? area : mesh.area();
  const auto [lo, hi] = mesh.bounding_box();
  wall.reference_point = 0.5 * (lo + hi);
  wall.mesh = std::move(mesh);
  wall.outward_normal = outward_normal.normalized();
  return wall;
}

namespace {

/// A wall whose shape is `surface` (its point and axis checked here), loaded over `area`.
Wall surface_wall(std::string name, AnalyticSurface surface, const char* point_key, const char* axis_key,
                  double area, const char* area_hint) {
  const std::string where = "wall '" + name + "' ";
  require(surface.point.allFinite(), where + point_key, "(non-finite)", "a finite point (m)");
  require(surface.axis.allFinite() && surface.axis.norm() > 0.0, where + axis_key, "(zero or non-finite)",
          "a non-zero vector");
  require(std::isfinite(area) && area > 0.0, where + "area", area, std::string("> 0 m^2 ") + area_hint);
  surface.axis.normalize();
  Wall wall;
  wall.name = std::move(name);
  wall.surface = surface;
  wall.outward_normal = surface.axis;
  wall.reference_point = surface.point;
  wall.area = area;
  return wall;
}

}  // namespace

Wall make_plane_wall(std::string name, const Vec3& point, const Vec3& outward_normal, double area) {
  return surface_wall(std::move(name), {AnalyticSurface::Shape::Plane, point, outward_normal, 0.0}, "point",
                      "outward_normal", area, "(a plane has no area of its own)");
}

Wall make_cylinder_wall(std::string name, const Vec3& axis_point, const Vec3& axis, double radius, double area) {
  require(std::isfinite(radius) && radius > 0.0, "wall '" + name + "' radius", radius, "> 0 m");
  return surface_wall(std::move(name), {AnalyticSurface::Shape::Cylinder, axis_point, axis, radius}, "axis_point",
                      "axis", area, "(2 pi R H for a height H)");
}

}  // namespace dem
