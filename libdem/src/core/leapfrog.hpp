// The leapfrog update of free particles (World::integrate's per-particle loop) as a kernel over a
// range of storage indices, so that it can run eight particles at a time in AVX-512 lanes.
//
// One particle's update is about two hundred scalar instructions (two damped 3-vectors, two
// travel norms, the stability check) and nothing else in the step waits on it: eight particles
// side by side take about a third of the time. Every path gives the scalar bits: IEEE operations
// lane by lane in the scalar order, and no fused multiply-add.
#pragma once

#include <cstdint>

#include <dem/core/damping_frame.hpp>
#include <dem/core/math.hpp>
#include <dem/core/particles.hpp>

namespace dem::detail {

/// Local damping (docs/model.md 3.1): F_i (1 - alpha sign(F_i V_i)) for each degree of freedom,
/// V the velocity relative to the damping frame.
inline Vec3 damped(const Vec3& force, const Vec3& velocity, double alpha) {
  Vec3 out;
  for (int a = 0; a < 3; ++a) {
    const double fv = force[a] * velocity[a];
    out[a] = force[a] * (1.0 - alpha * ((fv > 0.0) - (fv < 0.0)));
  }
  return out;
}

/// velocity += increment, except the components whose Dof bit (from bit `shift` on) is fixed.
inline void masked_add(Vec3& velocity, const Vec3& increment, std::uint8_t fixed, int shift) {
  for (int a = 0; a < 3; ++a)
    if (!(fixed & (1U << (a + shift)))) velocity[a] += increment[a];
}

/// What one step of leapfrog needs besides the particles.
struct LeapfrogStep {
  Vec3 gravity;              // m/s^2
  double local_damping;      // -, alpha
  double dt;                 // s
  double step_ratio_sq;      // (largest move in one step / radius)^2
  const Vec3* x_at_rebuild;  // m, positions at the last neighbour-list rebuild
  const Vec3* x_at_near;     // m, positions at the last near-list refresh
  const DampingFrame* frame; // the frame damping measures velocities against; nullptr: the fixed frame
};

/// What a range of particles reports: the largest squared travels since the rebuild and since
/// the near refresh (m^2, merged into the values passed in), and the lowest index that moved more
/// than the step ratio allows or whose spin is not finite (unchanged if none did).
struct LeapfrogTally {
  double travel_sq;
  double near_travel_sq;
  std::int64_t first_unstable;
};

/// Advances the free particles of storage indices [begin, end) by one step (pebbles are left to
/// their clump; fixed degrees of freedom keep their velocity), with the processor's best
/// instruction set (detail::block_isa(), as the pair loops).
void leapfrog(ParticleStore& p, const LeapfrogStep& step, std::int64_t begin, std::int64_t end, LeapfrogTally& tally);

}  // namespace dem::detail
