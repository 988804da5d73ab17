// Measurement spheres (docs/model.md 6): the averaged state of the balls in a spherical region, as
// PFC's "measure" logic reports it: stress, porosity, coordination numbers, contact fabric and
// strain rate. The study reads a sphere at the specimen centre to plot stress paths and the
// rotation of principal stresses.
//
// Which contacts count (pebbles and facets are boundary, never "balls"):
//   - ball-based stress (the default, 6.1 a): every contact of a ball whose centre is inside,
//     including its facet and pebble contacts, with the force the ball receives. Porosity
//     corrects the volume, so cut balls at the sphere's surface cost no accuracy.
//   - contact-based stress (Love-Weber, 6.1 b): contacts whose contact point is inside. A
//     ball-ball contact contributes its branch vector x2 - x1; a ball-facet or ball-pebble contact
//     contributes only the ball's arm x_c - x_ball, because the boundary body is not part of the
//     granular volume. With these choices a ball well inside the sphere adds the same moment to
//     both forms.
//   - coordination numbers: every contact of the balls inside (boundary contacts too: they carry
//     the ball's load as much as ball-ball contacts do).
//   - fabric: ball-ball contacts with contact point inside (docs/model.md 9.1 default).
//
// Only contacts with a positive elastic normal force (World::for_each_contact) exist here.
// A sphere that contains no ball centre throws: it is almost always a misplaced sphere (wrong
// units or origin), and a silent row of NaN in an output file is harder to trace.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <dem/core/math.hpp>
#include <dem/measure/fabric.hpp>
#include <dem/measure/principal_stress.hpp>

namespace dem {

class World;
struct MeasurementSphere;
struct SphereMeasurement;

namespace measure {

/// Measures the state of the last step inside `sphere` with one pass over the particles and one
/// over the contacts (O(N): meant for output intervals, not for every step). Also spelled
/// `sphere.measure(world)`. (It cannot be `dem::measure(...)`: `dem::measure` is this namespace.)
/// Throws InputError for an invalid sphere, or when no ball centre lies inside it.
SphereMeasurement measure(const World& world, const MeasurementSphere& sphere);

/// The ball-ball contacts whose contact point lies inside `sphere`, as fabric samples (normal
/// and elastic normal force, N), e.g. for rose(). The same set as SphereMeasurement::fabric.
/// Throws InputError for an invalid sphere; an empty result is not an error.
std::vector<ContactSample> ball_contacts_inside(const World& world, const MeasurementSphere& sphere);

/// Volume of the intersection of two spheres of radii r1 and r2 (m) whose centres are
/// `distance` (m) apart, m^3: the lens formula, or the smaller sphere if one contains the other.
/// Throws InputError for a negative or non-finite argument.
double sphere_intersection_volume(double r1, double r2, double distance);

}  // namespace measure

/// What a measurement sphere reports. Stresses are tension positive (continuum convention).
struct SphereMeasurement {
  /// Pa, ball-based porosity-corrected stress (docs/model.md 6.1 a), symmetrised:
  /// (1 - n) / sum V_b * sum_b sum_c (x_c - x_b) (outer) F_c^(b).
  Mat3 stress = Mat3::Zero();
  /// Pa, contact-based Love-Weber stress (docs/model.md 6.1 b), symmetrised:
  /// -(1 / V_S) sum_{x_c in S} F_c (outer) L_c.
  Mat3 stress_contacts = Mat3::Zero();
  /// -, 1 - (volume of ball parts inside the sphere) / V_S; ball-sphere intersections are exact
  /// (lens volumes), overlaps between balls are counted twice (ignored), pebbles are not solid.
  double porosity = 0.0;
  /// -, contacts per ball, summed over the balls inside over their count.
  double coordination_number = 0.0;
  /// -, the same over the balls with at least 2 contacts (rattlers and single contacts out);
  /// 0 when no ball inside has 2 contacts.
  double mechanical_coordination_number = 0.0;
  std::size_t balls = 0;     ///< balls whose centre is inside
  std::size_t contacts = 0;  ///< ball-ball contacts whose contact point is inside
  /// -, fabric tensor phi_ij = (1/N) sum n_i n_j of those ball-ball contacts (docs/model.md 9.3);
  /// NaN when there is none.
  Mat3 fabric = Mat3::Zero();
  /// 1/s, symmetric part of the least-squares velocity gradient of the balls inside (docs/model.md
  /// 6.2). Velocities are half a step behind positions (leapfrog); at quasi-static rates the
  /// mismatch is of order L dt relative. NaN when the balls inside do not span 3-D (fewer than 4
  /// balls, or all coplanar).
  Mat3 strain_rate = Mat3::Zero();
  /// Principal stresses of `stress`, compression positive (docs/model.md 6.3).
  measure::PrincipalStresses principal{};
};

/// A spherical measurement region, fixed in space.
struct MeasurementSphere {
  Vec3 centre = Vec3::Zero();  // m
  double radius = 0.0;         // m

  /// Throws InputError unless the centre is finite and the radius is finite and > 0.
  /// `where` names the sphere in the message.
  void validate(const std::string& where = "measurement sphere") const;

  /// Same as measure::measure(world, *this).
  SphereMeasurement measure(const World& world) const { return dem::measure::measure(world, *this); }
};

}  // namespace dem
