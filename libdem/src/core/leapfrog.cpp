// The leapfrog kernel: one particle at a time, and eight at a time in AVX-512 lanes (leapfrog.hpp).
#include "leapfrog.hpp"

#include <algorithm>
#include <cstring>

#include <dem/core/block_isa.hpp>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define DEM_LEAPFROG_AVX512 1
#include <immintrin.h>
#endif

namespace dem::detail {

namespace {

/// The stability check of a particle just updated: it moved more than the step ratio allows, or
/// its spin is not finite.
inline bool runaway(const ParticleStore& p, const LeapfrogStep& step, std::size_t i) {
  const Vec3 move = p.v[i] * step.dt;
  return !(move.squaredNorm() <= step.step_ratio_sq * p.radius[i] * p.radius[i]) || !p.w[i].allFinite();
}

/// One particle, as the engine always did it: the reference every other path matches.
inline void leapfrog_one(ParticleStore& p, const LeapfrogStep& step, std::int64_t s, LeapfrogTally& tally) {
  const auto i = static_cast<std::size_t>(s);
  if (p.clump[i] >= 0) return;
  const std::uint8_t fixed = p.fixed[i];
  const double alpha = step.local_damping, dt = step.dt;
  const DampingFrame* frame = step.frame;  // velocities relative to it decide the damping's sign
  const Vec3 velocity = frame ? Vec3(p.v[i] - frame->velocity_at(p.x[i])) : p.v[i];
  const Vec3 spin = frame ? Vec3(p.w[i] - frame->spin()) : p.w[i];
  const Vec3 force = damped(p.f[i] + step.gravity / p.inv_mass[i], velocity, alpha);
  const Vec3 torque = damped(p.t[i], spin, alpha);
  if (fixed == 0) {
    p.v[i] += force * (p.inv_mass[i] * dt);
    p.w[i] += torque * (p.inv_inertia[i] * dt);
  } else {
    masked_add(p.v[i], force * (p.inv_mass[i] * dt), fixed, 0);
    masked_add(p.w[i], torque * (p.inv_inertia[i] * dt), fixed, 3);
  }
  const Vec3 move = p.v[i] * dt;
  p.x[i] += move;
  tally.travel_sq = std::max(tally.travel_sq, (p.x[i] - step.x_at_rebuild[i]).squaredNorm());
  tally.near_travel_sq = std::max(tally.near_travel_sq, (p.x[i] - step.x_at_near[i]).squaredNorm());
  if (runaway(p, step, i)) tally.first_unstable = std::min(tally.first_unstable, s);
}

#if defined(DEM_LEAPFROG_AVX512)
static_assert(sizeof(Vec3) == 3 * sizeof(double), "the lanes read Vec3 arrays as plain doubles");

// Eight consecutive particles' 3-vectors are 24 doubles, three registers: register q holds
// component (8q + m) % 3 of particle (8q + m) / 3 in lane m. Per-particle values (inverse mass)
// are spread over the same pattern, so that the update runs component-wise, as the scalar one.
// GCC would contract the products and sums of intrinsics into fused multiply-adds: not here.
#define DEM_AVX512 __attribute__((target("avx512f"), optimize("fp-contract=off")))

/// Lane m of register q of the 24-double pattern belongs to particle spread_index(q)[m].
DEM_AVX512 inline __m512i spread_index(int q) {
  return q == 0 ? _mm512_setr_epi64(0, 0, 0, 1, 1, 1, 2, 2)
         : q == 1 ? _mm512_setr_epi64(2, 3, 3, 3, 4, 4, 4, 5)
                  : _mm512_setr_epi64(5, 5, 6, 6, 6, 7, 7, 7);
}

/// Per-particle values (lane m: particle m) spread over the pattern of register q.
DEM_AVX512 inline __m512d spread(__m512d per_particle, __m512i index) {
  return _mm512_permutex2var_pd(per_particle, index, per_particle);  // (permutexvar warns falsely in GCC 12)
}

/// The same 3-vector u for eight particles: register q of the 24-double pattern.
DEM_AVX512 inline __m512d pattern(const Vec3& u, int q) {
  double lanes[8];
  for (int m = 0; m < 8; ++m) lanes[m] = u[(8 * q + m) % 3];
  return _mm512_loadu_pd(lanes);
}

/// F (1 - alpha sign(F V)), lane by lane, as damped().
DEM_AVX512 inline __m512d damped_lanes(__m512d force, __m512d velocity, __m512d alpha) {
  const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
  const __m512d fv = _mm512_mul_pd(force, velocity);
  const __m512d positive = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(fv, zero, _CMP_GT_OQ), zero, one);
  const __m512d negative = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(fv, zero, _CMP_LT_OQ), zero, one);
  return _mm512_mul_pd(force, _mm512_sub_pd(one, _mm512_mul_pd(alpha, _mm512_sub_pd(positive, negative))));
}

/// Component c of the eight vectors in the pattern s[0..2], gathered into lanes 0-7. Component c
/// of particle m is double 3m + c of the 24: the first pick takes lanes 0-4 (and 5 for c = 0) from
/// s0:s1 (indices 0-15), the second the rest from s2 (its indices 8-15 select s2's 0-7).
DEM_AVX512 inline __m512d component(const __m512d s[3], int c) {
  const __m512i from_01 = _mm512_setr_epi64(c, c + 3, c + 6, c + 9, c + 12, c == 0 ? 15 : 0, 0, 0);
  const __m512i from_2 = c == 0 ? _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13)
                                : _mm512_setr_epi64(0, 1, 2, 3, 4, 8 + c - 1, 8 + c + 2, 8 + c + 5);
  return _mm512_permutex2var_pd(_mm512_permutex2var_pd(s[0], from_01, s[1]), from_2, s[2]);
}

/// Squared norms of the eight vectors in the pattern a[0..2], as Eigen's (x x + y y) + z z.
DEM_AVX512 inline __m512d squared_norms(const __m512d a[3]) {
  const __m512d s[3] = {_mm512_mul_pd(a[0], a[0]), _mm512_mul_pd(a[1], a[1]), _mm512_mul_pd(a[2], a[2])};
  return _mm512_add_pd(_mm512_add_pd(component(s, 0), component(s, 1)), component(s, 2));
}

/// Keeps the larger of `best` and `value` in the lanes of `counted`; a NaN value never wins (as
/// std::max).
DEM_AVX512 inline __m512d keep_larger(__m512d best, __m512d value, __mmask8 counted) {
  return _mm512_mask_blend_pd(_mm512_mask_cmp_pd_mask(counted, value, best, _CMP_GT_OQ), best, value);
}

DEM_AVX512 void leapfrog_avx512(ParticleStore& p, const LeapfrogStep& step, std::int64_t begin, std::int64_t end,
                                LeapfrogTally& tally) {
  double* x = p.x.data()->data();
  double* v = p.v.data()->data();
  double* w = p.w.data()->data();
  const double* f = p.f.data()->data();
  const double* t = p.t.data()->data();
  const double* x_at_rebuild = step.x_at_rebuild->data();
  const double* x_at_near = step.x_at_near->data();
  const Vec3 g = step.gravity;
  const __m512d gravity[3] = {_mm512_setr_pd(g.x(), g.y(), g.z(), g.x(), g.y(), g.z(), g.x(), g.y()),
                              _mm512_setr_pd(g.z(), g.x(), g.y(), g.z(), g.x(), g.y(), g.z(), g.x()),
                              _mm512_setr_pd(g.y(), g.z(), g.x(), g.y(), g.z(), g.x(), g.y(), g.z())};
  const __m512i spread_at[3] = {spread_index(0), spread_index(1), spread_index(2)};
  const bool weightless = g.x() == 0.0 && g.y() == 0.0 && g.z() == 0.0;  // a free ball's 1/m is > 0 and finite
  // A moving damping frame: its velocity, gradient and spin in the same pattern as gravity.
  const DampingFrame* frame = step.frame;
  const Vec3 frame_v = frame ? frame->velocity : Vec3::Zero(), frame_g = frame ? frame->velocity_gradient : Vec3::Zero();
  const Vec3 frame_w = frame ? frame->spin() : Vec3::Zero();
  const __m512d frame_velocity[3] = {pattern(frame_v, 0), pattern(frame_v, 1), pattern(frame_v, 2)};
  const __m512d frame_gradient[3] = {pattern(frame_g, 0), pattern(frame_g, 1), pattern(frame_g, 2)};
  const __m512d frame_spin[3] = {pattern(frame_w, 0), pattern(frame_w, 1), pattern(frame_w, 2)};
  const __m512d frame_height = _mm512_set1_pd(frame ? frame->height : 0.0);
  const __m512d alpha = _mm512_set1_pd(step.local_damping), dt = _mm512_set1_pd(step.dt);
  const __m512d step_ratio_sq = _mm512_set1_pd(step.step_ratio_sq), zero = _mm512_setzero_pd();
  __m512d travel_sq = _mm512_set1_pd(tally.travel_sq), near_travel_sq = _mm512_set1_pd(tally.near_travel_sq);
  std::int64_t i = begin;
  for (; i + 8 <= end; i += 8) {
    // Lanes of free balls are updated; pebbles (moved by their clump) are left alone. A ball
    // with a fixed degree of freedom sends its group of eight to the scalar path.
    const auto at = static_cast<std::size_t>(i);
    const __m256i clump = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&p.clump[at]));
    const auto not_pebble = static_cast<__mmask8>(_mm256_movemask_ps(_mm256_castsi256_ps(clump)));  // clump < 0
    const __m128i fixed = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p.fixed[at]));
    const auto unfixed = static_cast<__mmask8>(_mm_movemask_epi8(_mm_cmpeq_epi8(fixed, _mm_setzero_si128())));
    const __mmask8 free_balls = not_pebble & unfixed;
    if ((free_balls | static_cast<__mmask8>(~not_pebble)) != 0xff) {
      for (std::int64_t s = i; s < i + 8; ++s) leapfrog_one(p, step, s, tally);
      continue;
    }
    const __m512d free_lanes = _mm512_mask_blend_pd(free_balls, zero, _mm512_set1_pd(1.0));
    const __m512d inv_mass = _mm512_loadu_pd(&p.inv_mass[at]);
    const __m512d velocity_gain = _mm512_mul_pd(inv_mass, dt);
    const __m512d spin_gain = _mm512_mul_pd(_mm512_loadu_pd(&p.inv_inertia[at]), dt);
    const std::size_t o = 3 * at;
    __m512d height_in_frame = zero;  // lane m: z of particle m above the frame's reference height
    if (frame) {
      const __m512d positions[3] = {_mm512_loadu_pd(x + o), _mm512_loadu_pd(x + o + 8), _mm512_loadu_pd(x + o + 16)};
      height_in_frame = _mm512_sub_pd(component(positions, 2), frame_height);
    }
    __m512d x_new[3], w_new[3], move[3];
    for (int q = 0; q < 3; ++q) {
      const std::size_t c = o + 8 * static_cast<std::size_t>(q);
      // Without gravity the weight g/(1/m) of a free ball is g's own signed zero: no division.
      const __m512d weight = weightless ? gravity[q] : _mm512_div_pd(gravity[q], spread(inv_mass, spread_at[q]));
      const __m512d force = _mm512_add_pd(_mm512_loadu_pd(f + c), weight);
      const __m512d velocity = _mm512_loadu_pd(v + c);
      const __m512d spin = _mm512_loadu_pd(w + c);
      // Relative to the frame as the scalar path: v - (v_f + (z - h) g_f), w - w_f.
      __m512d relative_velocity = velocity, relative_spin = spin;
      if (frame) {
        const __m512d along = _mm512_mul_pd(spread(height_in_frame, spread_at[q]), frame_gradient[q]);
        relative_velocity = _mm512_sub_pd(velocity, _mm512_add_pd(frame_velocity[q], along));
        relative_spin = _mm512_sub_pd(spin, frame_spin[q]);
      }
      const __m512d v_new = _mm512_add_pd(
          velocity, _mm512_mul_pd(damped_lanes(force, relative_velocity, alpha), spread(velocity_gain, spread_at[q])));
      w_new[q] = _mm512_add_pd(spin, _mm512_mul_pd(damped_lanes(_mm512_loadu_pd(t + c), relative_spin, alpha),
                                                   spread(spin_gain, spread_at[q])));
      move[q] = _mm512_mul_pd(v_new, dt);
      x_new[q] = _mm512_add_pd(_mm512_loadu_pd(x + c), move[q]);
      const __mmask8 written = _mm512_cmp_pd_mask(spread(free_lanes, spread_at[q]), zero, _CMP_NEQ_OQ);
      _mm512_mask_storeu_pd(v + c, written, v_new);
      _mm512_mask_storeu_pd(w + c, written, w_new[q]);
      _mm512_mask_storeu_pd(x + c, written, x_new[q]);
    }
    __m512d since_rebuild[3], since_near[3];
    for (int q = 0; q < 3; ++q) {
      const std::size_t c = o + 8 * static_cast<std::size_t>(q);
      since_rebuild[q] = _mm512_sub_pd(x_new[q], _mm512_loadu_pd(x_at_rebuild + c));
      since_near[q] = _mm512_sub_pd(x_new[q], _mm512_loadu_pd(x_at_near + c));
    }
    travel_sq = keep_larger(travel_sq, squared_norms(since_rebuild), free_balls);
    near_travel_sq = keep_larger(near_travel_sq, squared_norms(since_near), free_balls);
    const __m512d r = _mm512_loadu_pd(&p.radius[at]);
    const __mmask8 slow = _mm512_cmp_pd_mask(squared_norms(move), _mm512_mul_pd(_mm512_mul_pd(step_ratio_sq, r), r),
                                             _CMP_LE_OQ);
    __mmask8 finite = 0xff;  // a spin component is finite where w - w == 0 (Eigen's allFinite)
    for (int q = 0; q < 3; ++q) finite &= _mm512_cmp_pd_mask(_mm512_sub_pd(w_new[q], w_new[q]), zero, _CMP_EQ_OQ);
    if ((slow & finite & free_balls) != free_balls) {  // rare: find the first offender as the scalar check does
      for (std::int64_t s = i; s < i + 8; ++s) {
        if (p.clump[static_cast<std::size_t>(s)] < 0 && runaway(p, step, static_cast<std::size_t>(s))) {
          tally.first_unstable = std::min(tally.first_unstable, s);
          break;
        }
      }
    }
  }
  alignas(64) double lanes_travel[8], lanes_near[8];
  _mm512_store_pd(lanes_travel, travel_sq);
  _mm512_store_pd(lanes_near, near_travel_sq);
  for (int m = 0; m < 8; ++m) {
    tally.travel_sq = std::max(tally.travel_sq, lanes_travel[m]);
    tally.near_travel_sq = std::max(tally.near_travel_sq, lanes_near[m]);
  }
  for (; i < end; ++i) leapfrog_one(p, step, i, tally);
}
#endif

}  // namespace

void leapfrog(ParticleStore& p, const LeapfrogStep& step, std::int64_t begin, std::int64_t end, LeapfrogTally& tally) {
  if (begin >= end) return;  // an empty world may have no reference positions at all
#if defined(DEM_LEAPFROG_AVX512)
  if (block_isa() == BlockIsa::avx512) return leapfrog_avx512(p, step, begin, end, tally);
#endif
  for (std::int64_t s = begin; s < end; ++s) leapfrog_one(p, step, s, tally);
}

}  // namespace dem::detail
