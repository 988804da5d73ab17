#include <dem/boundary/facet_wall.hpp>

#include <dem/core/errors.hpp>

namespace dem {

FacetWall make_facet_wall(std::string name, geometry::TriangleMesh mesh, const Vec3& outward_normal,
                          double area) {
  require(!mesh.triangles.empty(), "wall '" + name + "' triangle count", 0, "> 0");
  mesh.validate();
  require(outward_normal.allFinite() && outward_normal.norm() > 0.0, "wall '" + name + "' outward_normal",
          "(zero or non-finite)", "a non-zero vector");
  FacetWall wall;
  wall.name = std::move(name);
  wall.area = area > 0.0 ? area : mesh.area();
  const auto [lo, hi] = mesh.bounding_box();
  wall.reference_point = 0.5 * (lo + hi);
  wall.mesh = std::move(mesh);
  wall.outward_normal = outward_normal.normalized();
  return wall;
}

}  // namespace dem
