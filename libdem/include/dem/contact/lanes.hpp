// Contacts in SIMD lanes: the plain-double forms of a contact that the vectorised pair loop uses.
//
// The arithmetic of one contact is a chain of dependent square roots and divisions; the engine
// computes blocks of contacts side by side instead (core/contact_loops.hpp), which the compiler
// turns into SIMD code if every quantity is a plain double. Eigen's Vector3d is not: it is one
// SSE pair plus a scalar with shuffles in between, and its storage copies stop the vectoriser.
// So a law that wants the fast loop writes its force in terms of Lane3 (LinearLaw and
// RollingLinearLaw do), and keeps its history (State) in Lane3 members.
//
// A law may offer versions of force_lanes for special parameters ("lane variants"): it declares
// `static constexpr int lane_variants = N`, `static int lane_variant(const Params&)` (in [0, N)),
// and `template <int Variant = N - 1> static LaneForce force_lanes(...)`, where the last variant is
// right for any parameters. The engine asks once per loop and runs the loop compiled for that
// variant: a term that is zero for every contact of a type then costs nothing per contact, with
// no branch in the vectorised loop. Each variant must give the bits of the general one.
//
// Every operation is evaluated in the order Eigen uses for Vector3d (products per component, sums
// left to right, (x + y) + z; cross as Eigen's generic cross), so a formula gives the same bits
// written with Lane3 or with Vec3.
#pragma once

#include <dem/base/math.hpp>
#include <dem/contact/kinematics.hpp>

// The force functions run once per contact per step inside the engine's templated loop; GCC's
// heuristics otherwise keep them out of line, which costs about a third of the step. A law's own
// force_lanes may use it too; it is the one macro libdem's headers leave defined.
#if defined(__GNUC__)
#define DEM_HOT_INLINE __attribute__((always_inline)) inline
#else
#define DEM_HOT_INLINE inline
#endif

namespace dem {

/// A 3-vector as three plain doubles. No default member values (a store the vectoriser would
/// have to keep): write `Lane3 v{}` for zero.
struct Lane3 {
  double x, y, z;
};

inline Lane3 lane(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
inline Vec3 to_vec3(const Lane3& v) { return Vec3(v.x, v.y, v.z); }

inline Lane3 operator+(const Lane3& a, const Lane3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Lane3 operator-(const Lane3& a, const Lane3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Lane3 operator-(const Lane3& a) { return {-a.x, -a.y, -a.z}; }
inline Lane3 operator*(double s, const Lane3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Lane3 operator/(const Lane3& a, double s) { return {a.x / s, a.y / s, a.z / s}; }
inline double dot(const Lane3& a, const Lane3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double squared_norm(const Lane3& a) { return a.x * a.x + a.y * a.y + a.z * a.z; }
inline Lane3 cross(const Lane3& a, const Lane3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// ContactKinematics in plain doubles (same fields, same conventions).
struct LaneKinematics {
  Lane3 normal;
  double overlap;
  Lane3 relative_velocity;
  Lane3 relative_angular_velocity;
  double radius_1, radius_2, effective_radius, effective_mass, dt;
  ContactKind kind;
};

/// ContactForce in plain doubles. A law's force_lanes sets every field.
struct LaneForce {
  Lane3 force;
  Lane3 moment;
  double normal_force;
  double normal_stiffness;
};

inline LaneKinematics lane(const ContactKinematics& k) {
  return {lane(k.normal), k.overlap, lane(k.relative_velocity), lane(k.relative_angular_velocity),
          k.radius_1, k.radius_2, k.effective_radius, k.effective_mass, k.dt, k.kind};
}
inline ContactForce to_contact_force(const LaneForce& f) {
  ContactForce out;
  out.force = to_vec3(f.force);
  out.moment = to_vec3(f.moment);
  out.normal_force = f.normal_force;
  out.normal_stiffness = f.normal_stiffness;
  return out;
}

}  // namespace dem
