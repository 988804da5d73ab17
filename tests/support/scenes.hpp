// Small scenes shared by the physics tests. Values follow docs/model.md section 11: balls of radius
// 0.5 mm, density 2650 kg/m^3, E* = 5.3e7 Pa (ball-ball) and 2e7 Pa (ball-facet).
#pragma once

#include <random>

#include <dem/dem.hpp>

namespace dem::testing {

inline constexpr double radius = 0.5e-3;      // m
inline constexpr double density = 2650.0;     // kg/m^3
inline constexpr double modulus_ball = 5.3e7;  // Pa
inline constexpr double modulus_wall = 2.0e7;  // Pa

inline double ball_mass(double r = radius) { return density * 4.0 / 3.0 * pi * r * r * r; }

/// World without damping or gravity, fixed time step.
inline WorldSettings dynamic_settings(double dt) {
  WorldSettings s;
  s.time_step = dt;
  s.local_damping = 0.0;
  return s;
}

inline BallSpec ball_at(const Vec3& x, const Vec3& v = Vec3::Zero(), double r = radius) {
  BallSpec b;
  b.position = x;
  b.radius = r;
  b.density = density;
  b.velocity = v;
  return b;
}

/// Horizontal square floor (top face at z) as a facet wall, pushed downwards by the balls.
inline Wall floor_wall(double z, double half_size) {
  return make_facet_wall("floor",
                         geometry::make_rectangle(Vec3(0, 0, z), Vec3(half_size, 0, 0), Vec3(0, half_size, 0)),
                         -Vec3::UnitZ());
}

/// A closed cube [0, size]^3 of six facet walls (normals outward, pushed out by the balls inside).
inline void add_facet_box(World& world, double size) {
  const double h = size / 2;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 n = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero();
      n[axis] = side, u[(axis + 1) % 3] = h, v[(axis + 2) % 3] = h;
      world.add_wall(make_facet_wall("box", geometry::make_rectangle(Vec3::Constant(h) + n * h, u, v), n));
    }
}

/// A simple cubic lattice of per_side^3 balls 0.62 mm apart with radii 0.30-0.33 mm (so that
/// neighbours overlap: a compressed packing that springs apart) and random spins up to 50 rad/s.
inline std::vector<BallSpec> spinning_lattice(int per_side, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<BallSpec> balls;
  for (int i = 0; i < per_side; ++i)
    for (int j = 0; j < per_side; ++j)
      for (int k = 0; k < per_side; ++k) {
        BallSpec b = ball_at(Vec3(i, j, k) * 0.62e-3, Vec3::Zero(), 0.3e-3 + 0.03e-3 * u(rng));
        b.angular_velocity = Vec3(u(rng), u(rng), u(rng)) * 50.0;
        balls.push_back(b);
      }
  return balls;
}

/// Random polydisperse positions in a box, for broad-phase and conservation tests.
inline std::vector<BallSpec> random_balls(std::size_t n, double box, double r_min, double r_max, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<BallSpec> balls;
  for (std::size_t i = 0; i < n; ++i)
    balls.push_back(ball_at(Vec3(u(rng), u(rng), u(rng)) * box, Vec3::Zero(), r_min + (r_max - r_min) * u(rng)));
  return balls;
}

/// Like random_balls, but no two balls overlap (rejection sampling); may return fewer than n.
inline std::vector<BallSpec> separated_balls(std::size_t n, double box, double r_min, double r_max, unsigned seed) {
  std::vector<BallSpec> placed;
  for (const BallSpec& b : random_balls(20 * n, box, r_min, r_max, seed)) {
    if (placed.size() == n) break;
    bool clear = true;
    for (const BallSpec& o : placed)
      if ((o.position - b.position).norm() < o.radius + b.radius) clear = false;
    if (clear) placed.push_back(b);
  }
  return placed;
}

/// A granular gas in the cube [0, box]^3: up to n balls apart from each other and at least
/// `margin` * box from its faces, each velocity component normal with standard deviation
/// `speed` (m/s). Seeds: the positions' and the velocities'.
inline void add_gas(World& world, std::size_t n, double box, double margin, double r_min, double r_max, double speed,
                    unsigned position_seed, unsigned speed_seed) {
  std::mt19937_64 rng(speed_seed);
  std::normal_distribution<double> component(0.0, speed);
  for (BallSpec b : separated_balls(n, (1.0 - 2.0 * margin) * box, r_min, r_max, position_seed)) {
    b.position += Vec3::Constant(margin * box);
    b.velocity = Vec3(component(rng), component(rng), component(rng));
    world.add_ball(b);
  }
}

}  // namespace dem::testing
