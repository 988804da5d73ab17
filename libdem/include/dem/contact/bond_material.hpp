// What a cement is, as a user gives it: the parallel bond's stiffnesses and the mean and standard
// deviation of its strengths, from which each bond's own parameters are drawn
// (ParallelBondLaw::Params). PFC's `pb_ten` / `pb_coh` take a mean and a deviation the same way
// (Potyondy & Cundall 2004, section 3.1).
//
// The draw is a pure function of (seed, the two balls' ids): no generator state, so the same bond
// gets the same strengths whatever order bonds are made in, on any thread or process, and a
// resumed run needs nothing more than the bonds it saved. A strength is normal, truncated at zero
// (drawn again while negative: a negative strength is no cement at all).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/contact/parallel_bond.hpp>
#include <dem/core/particles.hpp>

namespace dem {

struct ParallelBondMaterial {
  double radius_multiplier = 1.0;     // -, lambda: Rb = lambda min(R1, R2)
  double normal_stiffness = 0.0;      // Pa/m
  double shear_stiffness = 0.0;       // Pa/m
  double tensile_strength = 0.0;      // Pa, mean
  double tensile_strength_std = 0.0;  // Pa
  double cohesion = 0.0;              // Pa, mean
  double cohesion_std = 0.0;          // Pa
  double friction_angle = 0.0;        // rad
  std::uint64_t seed = 1;             // the draw's key

  void validate(const std::string& where) const {
    require(radius_multiplier > 0.0 && radius_multiplier <= 1.0, where + ".radius_multiplier", radius_multiplier,
            "in (0, 1]");
    require_positive(where + ".normal_stiffness", normal_stiffness);
    require_positive(where + ".shear_stiffness", shear_stiffness);
    require(std::isfinite(tensile_strength) && tensile_strength >= 0.0, where + ".tensile_strength",
            tensile_strength, "finite and >= 0 Pa");
    require(std::isfinite(tensile_strength_std) && tensile_strength_std >= 0.0, where + ".tensile_strength_std",
            tensile_strength_std, "finite and >= 0 Pa");
    require(std::isfinite(cohesion) && cohesion >= 0.0, where + ".cohesion", cohesion, "finite and >= 0 Pa");
    require(std::isfinite(cohesion_std) && cohesion_std >= 0.0, where + ".cohesion_std", cohesion_std,
            "finite and >= 0 Pa");
    require(friction_angle >= 0.0 && friction_angle < 0.5 * pi, where + ".friction_angle", friction_angle,
            "in [0, pi/2) rad");
  }

  /// The parameters of the bond between balls `a` and `b` (stable ids; either order) of radii
  /// `radius_a` and `radius_b` (m).
  ParallelBondLaw::Params draw(ParticleId a, ParticleId b, double radius_a, double radius_b) const {
    const auto low = static_cast<std::uint64_t>(std::min(a, b)), high = static_cast<std::uint64_t>(std::max(a, b));
    const std::uint64_t key = mix(seed ^ mix((high << 32) | (low & 0xffffffffULL)));
    ParallelBondLaw::Params p;
    p.radius = radius_multiplier * std::min(radius_a, radius_b);
    p.normal_stiffness = normal_stiffness;
    p.shear_stiffness = shear_stiffness;
    p.tensile_strength = truncated_normal(tensile_strength, tensile_strength_std, key, 0);
    p.cohesion = truncated_normal(cohesion, cohesion_std, key, 1);
    p.friction_angle = friction_angle;
    return p;
  }

  /// SplitMix64's finaliser (Steele, Lea & Flood 2014): a well-mixed 64-bit hash.
  static std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  /// A uniform deviate in (0, 1) from the key, the stream and a counter.
  static double uniform(std::uint64_t key, std::uint64_t stream, std::uint64_t counter) {
    const std::uint64_t bits = mix(key ^ mix(stream * 0x100000001b3ULL + counter));
    return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53;
  }
  /// mean + std N(0, 1) (Box-Muller), drawn again while negative (64 tries, then 0).
  static double truncated_normal(double mean, double std, std::uint64_t key, std::uint64_t stream) {
    if (std == 0.0) return mean;
    for (std::uint64_t k = 0; k < 64; ++k) {
      const double u1 = uniform(key, stream, 2 * k), u2 = uniform(key, stream, 2 * k + 1);
      const double x = mean + std * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * pi * u2);
      if (x >= 0.0) return x;
    }
    return 0.0;
  }
};

}  // namespace dem
