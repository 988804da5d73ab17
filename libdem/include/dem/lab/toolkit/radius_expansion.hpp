// Radius expansion (docs/model.md 7): balls placed at random at a fraction of their size in a
// cylindrical cavity, without overlaps, then grown to full size in stages while the world cycles
// towards equilibrium. The protocol decides how long to cycle between stages and what to do at the
// end (lab/toolkit/ngi_specimen.hpp lowers the friction until the target porosity); these are the parts.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include <dem/core/world.hpp>

namespace dem::lab {

/// A vertical cylinder standing on z = 0 about the z axis.
struct Cylinder {
  double radius = 0.0;  // m
  double height = 0.0;  // m
};

/// Centres for balls of the given radii (m), drawn one after the other from `rng`, uniformly over
/// the positions that keep each ball inside `cavity` and clear of the balls placed before it
/// (rejection sampling on a CellGrid). InputError when a ball finds no room in 100000 draws.
std::vector<Vec3> place_without_overlap(const Cylinder& cavity, const std::vector<double>& radii, std::mt19937_64& rng);

/// Balls that grow from `start_factor` of their size to full size in `stages` stages of
/// `increments` increments each; the world cycles `steps_per_increment` steps after each increment
/// (a jump to full size would overlap neighbours by a large fraction of a radius and trip the
/// instability check), and as long as the protocol wants at the end of each stage.
struct RadiusExpansion {
  std::vector<ParticleId> balls;  // the growing balls, in the order of `diameters`
  std::vector<double> diameters;  // m, full size
  double start_factor = 0.5;      // -, of the full radii when placed
  int stages = 8;
  int increments = 10;
  std::int64_t steps_per_increment = 50;

  /// Radius / full radius after `increment` increments of stage `stage` (1-based; 0 increments of
  /// stage 1 is the start).
  double factor(int stage, int increment) const;
};

/// Sets each growing ball's radius to `factor` x its full radius and readies the world for the new
/// sizes (contacts found again, time step for the new masses). InputError unless there is one
/// diameter per ball.
void set_radii(World& world, const RadiusExpansion& expansion, double factor);

/// Adds balls of density `density` (kg/m^3) at `start_factor` of their size at random places in
/// `cavity` (place_without_overlap) and returns their expansion, with `stages` stages.
RadiusExpansion add_expanding_balls(World& world, const Cylinder& cavity, const std::vector<double>& diameters,
                                    double density, int stages, std::mt19937_64& rng);

}  // namespace dem::lab
