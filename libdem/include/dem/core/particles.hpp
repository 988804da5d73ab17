// Particle storage as a structure of arrays: the fields touched every step (position, velocity,
// angular velocity, force, torque, radius, inverse mass and inertia) are separate contiguous
// arrays; the rest (ids, groups, clump membership, fixity) is cold metadata.
//
// Invariants: every array has size(); index i is a *position* in storage and changes when the
// engine re-sorts particles for cache locality; id[i] is the stable identity that contact history,
// clumps and outputs use. `index_of(id)` maps back.
//
// Pebbles (the spheres of a clump) live here too, with clump[i] >= 0: the broad phase then finds
// ball-pebble contacts like any other pair. Their motion is slaved to their clump; their
// inv_mass is the clump's, so that contact laws see the right effective mass.
#pragma once

#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>

namespace dem {

using ParticleId = std::int32_t;

/// Bits of `ParticleStore::fixed`: a fixed degree of freedom keeps its velocity component.
enum Dof : std::uint8_t {
  dof_x = 1, dof_y = 2, dof_z = 4, dof_rx = 8, dof_ry = 16, dof_rz = 32,
  dof_translation = 7, dof_rotation = 56, dof_all = 63
};

/// Input for one ball.
struct BallSpec {
  Vec3 position = Vec3::Zero();          // m
  double radius = 0.0;                   // m
  double density = 0.0;                  // kg/m^3
  Vec3 velocity = Vec3::Zero();          // m/s
  Vec3 angular_velocity = Vec3::Zero();  // rad/s
  int group = 0;                         // user tag (material, layer...)
  std::uint8_t fixed = 0;                // Dof bits
};

struct ParticleStore {
  // hot, SoA
  std::vector<Vec3> x;  // m, position
  std::vector<Vec3> v;  // m/s, velocity (half a step behind positions, leapfrog)
  std::vector<Vec3> w;  // rad/s, angular velocity
  std::vector<Vec3> f;  // N, contact force of the current step
  std::vector<Vec3> t;  // N m, contact torque of the current step
  std::vector<double> radius;       // m
  std::vector<double> mass;         // kg (a pebble: its share is not used, see clump)
  std::vector<double> inv_mass;     // 1/kg (a pebble: 1/clump mass)
  std::vector<double> inv_inertia;  // 1/(kg m^2), sphere 1/(2/5 m R^2)
  // cold
  std::vector<ParticleId> id;
  std::vector<int> group;
  std::vector<std::int32_t> clump;  // -1 for a free ball, else the owning clump
  std::vector<std::uint8_t> fixed;  // Dof bits

  std::size_t size() const { return x.size(); }
  bool is_pebble(std::size_t i) const { return clump[i] >= 0; }

  /// Appends a particle and returns its stable id.
  ParticleId add(const BallSpec& spec, std::int32_t owner_clump = -1);

  /// Current storage index of a stable id.
  std::size_t index_of(ParticleId pid) const { return static_cast<std::size_t>(index_of_id_[pid]); }

  /// Reorders storage so that new position k holds old position order[k], on up to `threads`
  /// OpenMP threads (the same result for any count).
  void permute(const std::vector<std::int32_t>& order, int threads = 1);

  /// Rebuilds the id -> index map from `id` (after the arrays were filled from a checkpoint).
  void restore_index();

  /// Sets the radius of ball i, keeping its density: mass and inertia follow.
  void set_radius(std::size_t i, double new_radius);

 private:
  std::vector<std::int32_t> index_of_id_;
};

}  // namespace dem
