// `dem-bench --generate`: the benchmark packings, made by libdem, the same recipe every time.
//
// Recipe (version 1), for N balls with diameters uniform in [d_min, d_max]:
//   1. diameters drawn from a 64-bit Mersenne Twister (std::mt19937_64, whose sequence the C++
//      standard fixes) with the given seed, uniform deviates from its top 53 bits;
//   2. the cavity: the 70 mm cylinder closed at z = 0 and at H0, the height at which the
//      full-size balls fill it at solid fraction 0.57;
//   3. the balls at 0.7 of their size placed at random without overlap in the cavity (solid
//      fraction 0.2), one after the other, each tried at uniform random points until it fits;
//   4. the radii grown to full size in 30 equal increments, 100 steps each, frictionless
//      (mu = mu_r = 0, the benchmark's stiffnesses and dashpots, no local damping), with
//      gravity, the top plane fixed at H0;
//   5. compression: the top plane moves down at 0.05, 0.1 or 0.2 m/s (1750, 14k, 112k: speed
//      times mean diameter the same, so the same inertial number, as smaller balls rearrange
//      faster; a faster plate leaves a looser packing) until the ball-ball contact virial's
//      vertical stress exceeds 200 kPa (checked every 10 steps), then stops;
//   6. friction (mu 0.5, mu_r 0.17) switched on, walls fixed, 3,000 steps at the benchmark's
//      time step;
//   7. written as '# key value' header lines (counts, grading, cylinder, top plane height,
//      porosity, contacts per ball, stress, recipe) and 'x y z radius' lines in m, by ball id.
// Steps 4-5 run at 1.5 times the benchmark's time step (no friction and no rolling springs).
// libdem's results do not depend on the thread count, so neither does the file.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>

#include "bench_system.hpp"

namespace dem::bench {

namespace {

struct SizeSpec {
  const char* name;
  const char* alias;
  std::size_t balls;
  double d_min, d_max;  // m
  double compression_speed;  // m/s
};
constexpr SizeSpec sizes[] = {
    {"1750", "4D", 1750, 2.4e-3, 4.8e-3, 0.05},
    {"14k", "2D", 14000, 1.2e-3, 2.4e-3, 0.1},
    {"112k", "1D", 112000, 0.6e-3, 1.2e-3, 0.2},
};

constexpr int recipe_version = packing_recipe;
constexpr double cavity_solid_fraction = 0.57;
constexpr double start_scale = 0.7;
constexpr int growth_increments = 30;
constexpr std::int64_t steps_per_increment = 100;
constexpr double target_stress = 2e5;  // Pa
constexpr std::int64_t stress_check_every = 10;
constexpr std::int64_t relax_steps = 3000;

double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Random sequential placement without overlap in the cylinder of radius R between z = 0 and h.
std::vector<Vec3> place(const std::vector<double>& radius, double h, std::mt19937_64& rng) {
  const double R = cylinder_radius;
  const double cell = 2 * *std::max_element(radius.begin(), radius.end());
  const int nxy = static_cast<int>(std::ceil(2 * R / cell)) + 1, nz = static_cast<int>(std::ceil(h / cell)) + 1;
  std::vector<std::int32_t> head(static_cast<std::size_t>(nxy) * nxy * nz, -1), next(radius.size(), -1);
  auto cell_of = [&](const Vec3& x, int axis) {
    const double offset = axis < 2 ? R : 0.0;
    return std::clamp(static_cast<int>(std::floor((x[axis] + offset) / cell)), 0, (axis < 2 ? nxy : nz) - 1);
  };
  std::vector<Vec3> x(radius.size());
  for (std::size_t n = 0; n < radius.size(); ++n) {
    const double r = radius[n];
    for (long attempt = 0;; ++attempt) {
      if (attempt == 10000000) throw InputError("--generate: no room for ball " + std::to_string(n) + " in the cavity");
      const Vec3 p((2 * unit(rng) - 1) * (R - r), (2 * unit(rng) - 1) * (R - r), r + unit(rng) * (h - 2 * r));
      if (p.head<2>().norm() > R - r) continue;
      const int ci = cell_of(p, 0), cj = cell_of(p, 1), ck = cell_of(p, 2);
      bool clear = true;
      for (int a = std::max(ci - 1, 0); a <= std::min(ci + 1, nxy - 1) && clear; ++a)
        for (int b = std::max(cj - 1, 0); b <= std::min(cj + 1, nxy - 1) && clear; ++b)
          for (int c = std::max(ck - 1, 0); c <= std::min(ck + 1, nz - 1) && clear; ++c)
            for (std::int32_t o = head[(static_cast<std::size_t>(c) * nxy + b) * nxy + a]; o >= 0 && clear; o = next[o])
              clear = (x[o] - p).squaredNorm() >= (radius[o] + r) * (radius[o] + r);
      if (!clear) continue;
      x[n] = p;
      auto& h0 = head[(static_cast<std::size_t>(ck) * nxy + cj) * nxy + ci];
      next[n] = h0;
      h0 = static_cast<std::int32_t>(n);
      break;
    }
  }
  return x;
}

struct State {
  double contacts_per_ball, stress, kinetic_energy;
};

State state(const World& world, double top_z, std::size_t balls) {
  return {2.0 * static_cast<double>(world.contact_count(ContactKind::BallBall)) / static_cast<double>(balls),
          vertical_stress(world, top_z), world.kinetic_energy()};
}

}  // namespace

void generate_packing(const GenerateOptions& options) {
  const SizeSpec* size = nullptr;
  for (const SizeSpec& s : sizes)
    if (options.size == s.name || options.size == s.alias) size = &s;
  if (size == nullptr) throw InputError("--generate = " + options.size + ": must be 1750, 14k or 112k");
  if (options.out.empty()) throw InputError("--generate needs --out FILE");
  const auto t_start = std::chrono::steady_clock::now();
  const SystemParams sys = system_params(size->d_min, size->d_max);
  const std::size_t n = size->balls;
  const double R = cylinder_radius;

  // 1-3: diameters, cavity, placement at reduced size.
  std::mt19937_64 rng(options.seed);
  std::vector<double> radius(n);
  double solid = 0.0;
  for (double& r : radius) {
    r = (size->d_min + unit(rng) * (size->d_max - size->d_min)) / 2;
    solid += 4.0 / 3.0 * pi * r * r * r;
  }
  const double h0 = solid / (cavity_solid_fraction * pi * R * R);
  std::vector<double> small(n);
  for (std::size_t i = 0; i < n; ++i) small[i] = start_scale * radius[i];
  const std::vector<Vec3> x = place(small, h0, rng);
  std::printf("generate %s: %zu balls, d %.3g-%.3g mm, seed %llu; cavity %.3f mm high; placed in %.1f s\n", size->name, n,
              size->d_min * 1e3, size->d_max * 1e3, options.seed, h0 * 1e3, seconds_since(t_start));
  std::fflush(stdout);

  WorldSettings s;
  s.time_step = 1.5 * sys.time_step;
  s.local_damping = 0.0;
  s.gravity = Vec3(0, 0, -9.81);
  s.skin = sys.skin;
  s.threads = options.threads;
  World world(s);
  for (std::size_t i = 0; i < n; ++i) {
    BallSpec b;
    b.position = x[i];
    b.radius = small[i];
    b.density = density;
    world.add_ball(b);
  }
  const WallId top = add_cylinder_walls(world, h0, h0 + 0.001, 360);
  const auto frictionless = bench_law(sys.gamma_n, 0.0, 0.0);
  for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) world.set_contact_model(k, frictionless);

  // 4: growth in the closed cavity. Ball ids are the order of addition; storage is re-sorted.
  auto t0 = std::chrono::steady_clock::now();
  for (int k = 1; k <= growth_increments; ++k) {
    const double factor = k == growth_increments ? 1.0 : start_scale + (1.0 - start_scale) * k / growth_increments;
    ParticleStore& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i) p.set_radius(i, factor * radius[static_cast<std::size_t>(p.id[i])]);
    world.invalidate_contacts();
    world.step(steps_per_increment);
  }
  State st = state(world, h0, n);
  std::printf("growth: %lld steps in %.1f s, contacts per ball %.3f, stress %.4g Pa\n", static_cast<long long>(world.step_count()),
              seconds_since(t0), st.contacts_per_ball, st.stress);
  std::fflush(stdout);

  // 5: compression by the top plane to the target stress.
  t0 = std::chrono::steady_clock::now();
  const std::int64_t grown_at = world.step_count();
  world.wall(top).velocity = Vec3(0, 0, -size->compression_speed);
  auto top_z = [&] { return h0 + world.wall(top).displacement.z(); };
  const bool reached = world.run_until([&](const World& w) { return vertical_stress(w, top_z()) > target_stress; }, stress_check_every,
                                       static_cast<std::int64_t>(0.5 * h0 / size->compression_speed / s.time_step));
  if (!reached) throw InputError("--generate: the compression did not reach " + std::to_string(target_stress) + " Pa");
  world.wall(top).velocity = Vec3::Zero();
  const double z_top = top_z();
  st = state(world, z_top, n);
  std::printf("compression: %lld steps in %.1f s, top plane %.4f mm, contacts per ball %.3f, stress %.4g Pa\n",
              static_cast<long long>(world.step_count() - grown_at), seconds_since(t0), z_top * 1e3, st.contacts_per_ball, st.stress);
  std::fflush(stdout);

  // 6: friction on, walls fixed, dashpots only.
  t0 = std::chrono::steady_clock::now();
  const auto frictional = bench_law(sys.gamma_n, friction, rolling_friction);
  for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) world.retune_contact_model(k, frictional);
  world.set_time_step(sys.time_step);
  world.step(relax_steps);
  st = state(world, z_top, n);
  std::printf("relaxation: %lld steps in %.1f s, contacts per ball %.4f, stress %.6g Pa, kinetic energy %.3g J\n",
              static_cast<long long>(relax_steps), seconds_since(t0), st.contacts_per_ball, st.stress, st.kinetic_energy);

  // 7: the file, balls in id order.
  const ParticleStore& p = world.particles();
  double volume = 0.0;
  for (std::size_t i = 0; i < n; ++i) volume += 4.0 / 3.0 * pi * std::pow(p.radius[i], 3);
  const std::string tmp = options.out + ".part";
  {
    std::ofstream out(tmp);
    if (!out) throw InputError("--out = " + options.out + ": cannot write " + tmp);
    char line[256];
    auto put = [&](const char* format, auto... values) {
      std::snprintf(line, sizeof line, format, values...);
      out << line;
    };
    put("# libdem benchmark packing: dem-bench --generate %s --seed %llu (recipe %d, benchmarks/packing_generator.cpp)\n",
        size->name, options.seed, recipe_version);
    put("# lines: x y z radius (m), one ball per line; header lines: '# key value' (SI units)\n");
    put("# balls %zu\n# dmin %g\n# dmax %g\n# density %g\n", n, size->d_min, size->d_max, density);
    put("# cylinder_radius %g\n# bottom_wall_z 0\n# top_wall_z %.17g\n", R, z_top);
    put("# porosity_in_cylinder %.6f\n# contacts_per_ball %.6f\n# pair_virial_szz_Pa %.8g\n# kinetic_energy_J %.6g\n",
        1.0 - volume / (pi * R * R * z_top), st.contacts_per_ball, st.stress, st.kinetic_energy);
    put("# seed %llu\n# recipe %d\n# generation_steps %lld\n", options.seed, recipe_version, static_cast<long long>(world.step_count()));
    for (std::size_t id = 0; id < n; ++id) {
      const std::size_t i = p.index_of(static_cast<ParticleId>(id));
      put("%.17g %.17g %.17g %.17g\n", p.x[i].x(), p.x[i].y(), p.x[i].z(), p.radius[i]);
    }
    if (!out.flush()) throw InputError("--out = " + options.out + ": write failed");
  }
  if (std::rename(tmp.c_str(), options.out.c_str()) != 0) throw InputError("--out = " + options.out + ": cannot rename " + tmp);
  std::printf("wrote %s: top plane %.4f mm, porosity %.4f, %.1f s in all\n", options.out.c_str(), z_top * 1e3,
              1.0 - volume / (pi * R * R * z_top), seconds_since(t_start));
}

}  // namespace dem::bench
