// A rigid wall made of triangles (facets). It moves rigidly with a prescribed velocity (set it
// every step to drive it, e.g. from a servo), and reports what the balls do to it: total force,
// moment about its reference point, contact count and summed normal stiffness (for servo gains).
//
// Contacts with balls are resolved by the engine (one per ball and wall, at the closest point
// of the wall's triangles; see contact_sets.hpp). Split a strongly concave shape into several
// walls if a ball can touch two of its faces at once.
#pragma once

#include <string>

#include <dem/core/math.hpp>
#include <dem/geometry/mesh.hpp>

namespace dem {

using WallId = std::int32_t;

struct FacetWall {
  std::string name;
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
FacetWall make_facet_wall(std::string name, geometry::TriangleMesh mesh, const Vec3& outward_normal,
                          double area = 0.0);

}  // namespace dem
