// Storage of the contacts of one contact type: the candidate pairs found by the broad phase
// (a Verlet list: pairs closer than the sum of radii plus the skin), the contact law's history
// for each of them, and the forces of the last step that recorded them (World::ContactRecords).
//
// The history is a byte buffer with one law State per candidate, created and copied only through
// the law-typed ContactModel (core/contact_model.hpp). A candidate that is not touching holds a fresh
// State, so history lives exactly as long as the contact (docs/model.md 1.1: history resets when the
// pieces separate). Forces are written per contact and added into the particles in contact
// order, which makes results independent of the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <dem/base/math.hpp>
#include <dem/contact/kinematics.hpp>
#include <dem/contact/lanes.hpp>

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

/// One contact's part of a particle's force and torque sums, left by a thread for the engine to
/// add after the earlier threads' parts (the serial contact order): piece 1 gets -force, piece 2
/// +force.
struct DeferredSum {
  std::int32_t particle;
  bool first_piece;
  Lane3 force;   // N, on piece 2
  Lane3 torque;  // N m, on this particle about its centre
};

/// Ball-ball or ball-pebble candidates. Piece 1 (`first`) is always a ball.
struct PairContacts {
  ContactKind kind = ContactKind::BallBall;
  std::vector<std::int32_t> first, second;  // storage indices of the two pieces
  StateBuffer state;
  /// The forces of the last step that recorded them (KernelContext::record_pair_forces; a World
  /// records on the steps after which they can be read, World::ContactRecords).
  std::vector<Vec3> force;           // N, on piece 2 (piece 1 gets -force)
  std::vector<double> normal_force;  // N, elastic, compression positive; 0 if not touching
  /// 1 where the contact touched in the last step (non-zero normal force or force), written every
  /// step: a contact the loops must end when it separates, and whose history a rebuild keeps. One
  /// byte, so that finding those costs the loops little memory traffic.
  std::vector<std::uint8_t> touching;
  /// The candidates that can touch before the World next refreshes this list, ascending: the
  /// others are more than a near skin apart (WorldSettings::near_skin), so the loops skip them.
  /// In a dense packing about a quarter of the candidates are that far apart.
  std::vector<std::int32_t> near;
  /// With several threads, thread t takes the contacts [shares[t], shares[t + 1]) (planned by
  /// the World, weighted by which contacts touch and by how fast each thread went, so that the
  /// threads finish together). A thread that finishes first takes chunks of steal_chunk near
  /// candidates from the end of another's share (contact_loops.hpp).
  std::vector<std::int64_t> shares;
  /// Per share, its longest run of contacts [begin, end) whose particles no other share touches
  /// (World::plan_shares): a later share adds their sums directly, without asking per particle
  /// whether to defer them (the answer is no for every one).
  std::vector<std::pair<std::int64_t, std::int64_t>> unshared_run;
  /// Per thread: the near candidates it computed since the plan, and the seconds it took (the
  /// next plan gives a thread on a faster core a larger share).
  std::vector<std::int64_t> share_done;
  std::vector<double> share_seconds;
  /// Scratch of a threaded step: share t's parts of the particles shared with earlier shares
  /// (KernelContext::shared), and every part of each chunk another thread took (one list per
  /// chunk, in contact order), added after the loop in contact order.
  std::vector<std::vector<DeferredSum>> deferred, taken;
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

/// A ball-facet candidate's closest-point search on one triangle costs about this many pair
/// candidates: the wall loop weighs its triangle tests by it when choosing threads, and a spread
/// World when it balances its subdomains.
inline constexpr std::int64_t triangle_test_weight = 4;
/// An analytic-wall candidate (one closest-point formula, then the law) costs about this many pair
/// candidates: 25 against 17 ns a candidate on the 14k benchmark. Used as triangle_test_weight is.
inline constexpr std::int64_t analytic_wall_weight = 2;

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
