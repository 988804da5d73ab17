// What the contacts of one contact type are: the candidate pairs found by the broad phase (a
// Verlet list: pairs closer than the sum of radii plus the skin), the contact law's history for
// each of them, the forces of the last step that recorded them (World::ContactRecords), and which
// ones touch. How a step shares them out between threads and processes (near lists, thread
// shares, deferred sums) is the engine's plan, not theirs (core/step_plan.hpp).
//
// The history is a byte buffer with one law State per candidate, created and copied only through
// the law-typed ContactModel (core/contact_model.hpp). A candidate that is not touching holds a
// fresh State, so history lives exactly as long as the contact (docs/model.md 1.1: history resets
// when the pieces separate). Forces are written per contact and added into the particles in
// contact order, which makes results independent of the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>
#include <dem/contact/kinematics.hpp>

namespace dem {

/// Untyped per-contact law history: `count` States of `stride` bytes each.
struct StateBuffer {
  std::vector<std::byte> bytes;
  std::size_t stride = 0;
  std::size_t count = 0;
  /// The law type whose States these are (ContactModel::law_tag): history carries over to a new
  /// model only for the same law type, never for another law whose State merely has this size.
  const void* law = nullptr;
  std::byte* at(std::size_t k) { return bytes.data() + k * stride; }
  const std::byte* at(std::size_t k) const { return bytes.data() + k * stride; }
};

/// Ball-ball or ball-pebble candidates. Piece 1 (`first`) is always a ball.
struct PairContacts {
  ContactKind kind = ContactKind::BallBall;
  std::vector<std::int32_t> first, second;  // storage indices of the two pieces
  /// In a periodic cell, per candidate: which image of piece 2 piece 1 touches, as an image code
  /// (boundary/periodic_cell.hpp: the image vector n, components -1, 0, 1, in one byte; the
  /// branch is x2 + h n - x1). Found by the broad phase with the candidate and fixed until the
  /// next rebuild, which wraps the positions into the cell and finds every candidate's image
  /// again, so the contact keeps its history by its particles' ids as anywhere else. Empty
  /// without a periodic cell: the loops then never read it. A contact with a partner held by
  /// another process will name it the same way (a ghost is the owner's particle plus h n), so
  /// one mechanism serves images and ghosts.
  std::vector<std::uint8_t> image;
  StateBuffer state;
  /// The forces of the last step that recorded them (a World records them on the steps after
  /// which they can be read, World::ContactRecords).
  std::vector<Vec3> force;           // N, on piece 2 (piece 1 gets -force)
  std::vector<double> normal_force;  // N, elastic, compression positive; 0 if not touching
  /// 1 where the contact touched in the last step (non-zero normal force or force), written every
  /// step: a contact the loops must end when it separates, and whose history a rebuild keeps. One
  /// byte, so that finding those costs the loops little memory traffic.
  std::vector<std::uint8_t> touching;
  /// Per-particle incidence (CSR): particle i's contacts are the entries
  /// [incidence_offsets[i], incidence_offsets[i + 1]) of incidence_entries, each contact * 2 + side
  /// (side 1: i is piece 2), in contact order. Made with the list; restart files hold it.
  std::vector<std::int32_t> incidence_offsets, incidence_entries;
  std::size_t size() const { return first.size(); }
};

/// Sets `touching` from the normal forces and forces (after a load: a restart file holds the
/// records of its last step).
inline void mark_touching(PairContacts& c) {
  c.touching.assign(c.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k)
    c.touching[k] = (k < c.normal_force.size() && c.normal_force[k] != 0.0) || (k < c.force.size() && !c.force[k].isZero(0.0));
}

/// The torque on piece 2 about its centre, from the force on it and the torque on piece 1: the
/// two differ by the moment of the force over the branch d = x2 - x1 (T1 + T2 = -d x F), so a
/// contact stores only T1. `branch` comes from the engine's pair geometry (core/pair_geometry.hpp).
inline Vec3 second_torque(const Vec3& branch, const Vec3& force, const Vec3& torque_first) {
  return -branch.cross(force) - torque_first;
}

/// Ball-wall candidates: one per (ball, wall). For mesh walls, with the wall's triangles near that
/// ball: a ball gets a single contact per wall at the closest point of those triangles, so a ball
/// on the shared edge of two triangles is never counted twice and keeps its history across the
/// edge. For analytic walls (`surfaces`), at the closest point of the wall's surface.
struct WallContacts {
  bool surfaces = false;  // the walls' analytic surfaces (Wall::surface), no triangles
  std::vector<std::int32_t> ball, wall;
  std::vector<std::int32_t> triangle_begin, triangle_end;  // range in `triangles` (mesh walls)
  std::vector<std::int32_t> triangles;                      // triangle indices in the wall's mesh
  StateBuffer state;
  std::vector<Vec3> force;           // N, on the wall (the ball gets -force)
  std::vector<Vec3> torque_ball;     // N m, on the ball about its centre
  std::vector<Vec3> point;           // m, contact point
  std::vector<Vec3> moment;          // N m, pure moment on the wall (rolling resistance)
  std::vector<double> normal_force;  // N, elastic, compression positive; 0 if not touching
  std::vector<double> normal_stiffness;  // N/m, 0 if not touching
  std::size_t size() const { return ball.size(); }
};

}  // namespace dem
