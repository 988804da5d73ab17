// A rigid wall: a mesh of triangles (facets), or an analytic surface (an infinite plane or
// cylinder, as LAMMPS's wall/gran and LIGGGHTS's primitive walls). It moves rigidly with a
// prescribed velocity (set it every step to drive it, e.g. from a servo), and reports what the
// balls do to it: total force, moment about its reference point, contact count and summed normal
// stiffness (for servo gains). Both kinds use the ball-facet contact law and give the same
// outputs; a surface costs one closest-point formula per ball instead of a triangle search.
//
// Contacts with balls are resolved by the engine (one per ball and wall, at the closest point of
// the wall's triangles or surface; see contact_sets.hpp). Split a strongly concave mesh into
// several walls if a ball can touch two of its faces at once.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <dem/base/math.hpp>
#include <dem/geometry/mesh.hpp>

namespace dem {

using WallId = std::int32_t;

/// The shape of a wall that is not a mesh, whose closest point to a ball is exact. Both sides of
/// the surface push balls away, as a facet does.
struct AnalyticSurface {
  enum class Shape : std::uint8_t { None = 0, Plane = 1, Cylinder = 2 };
  Shape shape = Shape::None;   // None: the wall is its mesh
  Vec3 point = Vec3::Zero();   // m, a point of the plane, or of the cylinder's axis (moves with the wall)
  Vec3 axis = Vec3::UnitZ();   // unit: the plane's normal, or the cylinder's axis
  double radius = 0.0;         // m, the cylinder's radius

  /// The point of the surface closest to `x`. On a cylinder's axis every direction is as close:
  /// the one along axis.unitOrthogonal() is taken.
  Vec3 closest_point(const Vec3& x) const {
    const Vec3 along = (x - point).dot(axis) * axis;
    if (shape == Shape::Plane) return x - along;  // x minus its height above the plane
    const Vec3 foot = point + along;  // on the axis
    const Vec3 radial = x - foot;
    const double distance = radial.norm();
    return foot + (distance > 0.0 ? Vec3(radial * (radius / distance)) : Vec3(radius * axis.unitOrthogonal()));
  }
};

struct Wall {
  std::string name;
  AnalyticSurface surface;              // a plane or cylinder; Shape::None: the mesh below
  geometry::TriangleMesh mesh;          // m, current position in the world frame
  Vec3 velocity = Vec3::Zero();         // m/s, rigid translation, applied every step
  Vec3 displacement = Vec3::Zero();     // m, total translation since the wall was added
  Vec3 reference_point = Vec3::Zero();  // m, moves with the wall; moments are taken about it
  Vec3 outward_normal = Vec3::UnitZ();  // unit, direction in which the specimen pushes the wall
  double area = 0.0;                    // m^2, loaded area for stresses (mesh area if 0)

  // Results of the last step.
  Vec3 force = Vec3::Zero();   // N, total force the balls exert on the wall
  Vec3 moment = Vec3::Zero();  // N m, about reference_point
  int contact_count = 0;       // touching balls
  double stiffness_sum = 0.0;  // N/m, sum of normal stiffnesses of touching contacts

  /// Compressive normal stress on the wall (force along outward_normal over area), Pa.
  double normal_stress() const { return force.dot(outward_normal) / area; }
  /// Shear traction on the wall (force in the wall plane over area), Pa.
  Vec3 shear_stress() const { return (force - force.dot(outward_normal) * outward_normal) / area; }
};

/// Builds a wall from a mesh; validates the mesh and sets the area from it unless given.
Wall make_facet_wall(std::string name, geometry::TriangleMesh mesh, const Vec3& outward_normal,
                     double area = 0.0);

/// An infinite plane through `point` normal to `outward_normal` (the direction in which the
/// specimen pushes it; normal_stress() is compressive-positive along it). `area` (m^2, > 0) is the
/// loaded area for stresses and servo gains: a plane has none of its own. Reference point: `point`.
Wall make_plane_wall(std::string name, const Vec3& point, const Vec3& outward_normal, double area);

/// An infinite cylinder of `radius` (m) around the axis through `axis_point` along `axis`, for
/// balls inside or outside it. `area` (m^2, > 0) is the loaded area for stresses (2 pi R H for a
/// specimen of height H). Reference point: `axis_point`; outward normal: `axis`.
Wall make_cylinder_wall(std::string name, const Vec3& axis_point, const Vec3& axis, double radius, double area);

}  // namespace dem
