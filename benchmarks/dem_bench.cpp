// dem-bench: the peers' benchmark system (shared bench inputs for LAMMPS and LIGGGHTS), run by
// libdem: a dense packing in a 70 mm cylinder (side wall, bottom plane, top plane moving down at
// 5 mm/s), constant kn = kt = 7e4 N/m, mu 0.5, rolling resistance kr = kt Rbar^2 with mu_r 0.17,
// mass-proportional dashpots gamma m_eff (LAMMPS `damping mass_velocity`), gravity, no local
// damping. Time step, dashpot rate and skin follow the peers' params.py from the packing's radii.
//
// Prints particle-steps per second of the timed loop, mean ball-ball contacts per ball and the
// vertical stress from the ball-ball contact virial over the current cylinder volume, the
// quantities the peers report, so that speed is compared on the same physics.
#include <sys/resource.h>

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include <dem/dem.hpp>

#include "cpu_steal.hpp"

namespace po = boost::program_options;
using namespace dem;

namespace {

std::vector<BallSpec> read_packing(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("--packing = " + path + ": cannot open the file");
  std::vector<BallSpec> balls;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    BallSpec b;
    if (!(fields >> b.position.x() >> b.position.y() >> b.position.z() >> b.radius))
      throw InputError(path + ":" + std::to_string(number) + ": expected 'x y z radius' (m), got '" + line + "'");
    b.density = 2650.0;
    balls.push_back(b);
  }
  if (balls.empty()) throw InputError("--packing = " + path + ": no balls in the file");
  return balls;
}

double info_value(const std::string& packing, const std::string& key) {
  const auto dot = packing.rfind(".txt");
  std::ifstream in(packing.substr(0, dot) + "_info.txt");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string k;
    double v;
    if (fields >> k >> v && k == key) return v;
  }
  return std::nan("");
}

/// Ball-ball contact virial sum_c d_z F_z over the cylinder volume below the top plate, Pa.
double vertical_stress(const World& world, double top_z) {
  const auto& c = world.pair_contacts(ContactKind::BallBall);
  const auto& p = world.particles();
  double virial = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    const Vec3 d = p.x[static_cast<std::size_t>(c.second[k])] - p.x[static_cast<std::size_t>(c.first[k])];
    virial += d.z() * c.force[k].z();
  }
  return virial / (pi * 0.035 * 0.035 * top_z);
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description opts("dem-bench options");
  std::string packing;
  long steps = 0;
  long rebuilds = 0;
  int threads = 1;
  double wall_speed = 0.005;
  opts.add_options()("help", "this help")("packing", po::value(&packing)->required(), "packing file: x y z radius (m) per line")(
      "steps", po::value(&steps)->default_value(0), "timed steps (0: the peers' count for this size)")(
      "threads", po::value(&threads)->default_value(1), "OpenMP threads")(
      "segments", po::value<int>()->default_value(360), "facets around the cylinder side wall")(
      "report-every", po::value<long>()->default_value(0), "print contacts and stress every N steps (0: never)")(
      "rebuilds", po::value(&rebuilds)->default_value(0),
      "after the run, time this many forced neighbour-list rebuilds (re-sort, pair search, history carried over)")(
      "boundary", po::value<std::string>()->default_value("cylinder"),
      "cylinder: the peers' walls; rings: the simple-shear boundary (clump ring stack and facet discs); "
      "none: no walls (to measure what the boundaries cost)");
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, opts), vm);
    if (vm.count("help")) {
      std::cout << opts << "\n";
      return 0;
    }
    po::notify(vm);
    if (steps < 0) throw InputError("--steps = " + std::to_string(steps) + ": must be >= 0");
    if (rebuilds < 0) throw InputError("--rebuilds = " + std::to_string(rebuilds) + ": must be >= 0");
    auto balls = read_packing(packing);
    double r_min = 1e9, r_max = 0;
    for (const auto& b : balls) r_min = std::min(r_min, b.radius), r_max = std::max(r_max, b.radius);
    // params.py: dt = 0.2 sqrt(m_min/kn) rounded down to 2 digits; gamma_n for damping ratio 0.2
    // between two mean-size balls; skin a quarter of d_min.
    const double kn = 7e4, rho = 2650.0, d_min = 2 * r_min, d_max = 2 * r_max;
    const double m_min = rho * pi / 6 * d_min * d_min * d_min;
    const double d3_mean = (std::pow(d_max, 4) - std::pow(d_min, 4)) / (4 * (d_max - d_min));
    const double m_mean = rho * pi / 6 * d3_mean;
    const double tc = std::sqrt(m_min / kn);
    const double scale = std::pow(10.0, std::floor(std::log10(0.2 * tc)) - 1);
    const double dt = std::stod((std::ostringstream() << std::setprecision(2) << std::floor(0.2 * tc / scale) * scale).str());
    const double gamma_n = std::stod((std::ostringstream() << std::setprecision(3) << 2 * 0.2 * std::sqrt(kn / (m_mean / 2))).str());
    if (steps == 0) steps = balls.size() < 5000 ? 10000 : balls.size() < 50000 ? 5000 : 1000;
    double top_z = info_value(packing, "top_wall_z");
    if (!std::isfinite(top_z)) {
      top_z = 0;
      for (const auto& b : balls) top_z = std::max(top_z, b.position.z() + b.radius);
    }

    WorldSettings s;
    s.time_step = dt;
    s.local_damping = 0.0;
    s.gravity = Vec3(0, 0, -9.81);
    s.skin = 0.25 * d_min;
    s.threads = threads;
    World world(s);
    for (const auto& b : balls) world.add_ball(b);
    // The input copy (96 B per ball) is the benchmark's, not the library's: drop it before the
    // peak RSS is reached (the first neighbour-list build).
    const std::size_t ball_count = balls.size();
    std::vector<BallSpec>().swap(balls);
    const std::string boundary = vm["boundary"].as<std::string>();
    if (boundary != "cylinder" && boundary != "rings" && boundary != "none")
      throw InputError("--boundary = " + boundary + ": must be cylinder, rings or none");
    const int segments = vm["segments"].as<int>();
    // Circumscribed polygon: its flat faces are tangent to the 35 mm circle, as the analytic wall.
    const double r_poly = 0.035 / std::cos(pi / segments);
    WallId top = -1;
    if (boundary == "cylinder") {
      world.add_wall(make_facet_wall("side", geometry::make_cylinder_shell(Vec3(0, 0, -0.001), r_poly, top_z + 0.002, segments, true), Vec3::UnitX()));
      world.add_wall(make_facet_wall("bottom", geometry::make_rectangle(Vec3::Zero(), Vec3(0.0355, 0, 0), Vec3(0, 0.0355, 0)), -Vec3::UnitZ()));
      top = world.add_wall(make_facet_wall("top", geometry::make_rectangle(Vec3(0, 0, top_z), Vec3(0.0355, 0, 0), Vec3(0, 0.0355, 0)), Vec3::UnitZ()));
    } else if (boundary == "rings") {
      // As the simple-shear app builds it: pebbles of the smallest ball diameter, discs as plates.
      RingStackSpec rings;
      rings.inner_radius = 0.035;
      rings.height = top_z;
      rings.ring_height = d_min;
      rings.pebble_radius = d_min / 2;
      rings.gap = 0.05 * d_min;
      for (const ClumpSpec& ring : make_ring_stack(rings)) world.add_clump(ring);
      world.add_wall(make_facet_wall("bottom", geometry::make_disc(Vec3::Zero(), 0.035 + 2 * d_min, -Vec3::UnitZ(), 24), -Vec3::UnitZ()));
      top = world.add_wall(make_facet_wall("top", geometry::make_disc(Vec3(0, 0, top_z), 0.035 + 2 * d_min, Vec3::UnitZ(), 24), Vec3::UnitZ()));
    }
    if (top >= 0) world.wall(top).velocity = Vec3(0, 0, -wall_speed);
    auto law = RollingLinearLaw::Params::constant(kn, kn, 0.5, 0.17);
    law.normal_damping_rate = gamma_n;
    law.shear_damping_rate = gamma_n;
    const auto model = make_contact_model<RollingLinearLaw>(law, "contact");
    for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) world.set_contact_model(k, model);

    world.step(1);  // neighbour lists and contacts, as the peers' setup before the timed run
    const double contacts_start = 2.0 * world.contact_count(ContactKind::BallBall) / ball_count;
    if (const long every = vm["report-every"].as<long>(); every > 0)
      world.add_callback(every, [&](World& w) {
        const double z = top_z - wall_speed * dt * static_cast<double>(w.step_count());
        std::printf("step %lld wall_contacts %d/%d/%d (side/bottom/top) contacts_per_ball %.4f vertical_stress_Pa %.6g kinetic_energy_J %.4g\n",
                    static_cast<long long>(w.step_count()), w.walls().size() > 0 ? w.walls()[0].contact_count : 0,
                    w.walls().size() > 1 ? w.walls()[1].contact_count : 0, w.walls().size() > 2 ? w.walls()[2].contact_count : 0,
                    2.0 * w.contact_count(ContactKind::BallBall) / ball_count,
                    vertical_stress(w, z), w.kinetic_energy());
      });
    const auto ticks0 = bench::CpuTicks::now();
    const auto t0 = std::chrono::steady_clock::now();
    world.step(steps);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double steal = bench::steal_fraction(ticks0, bench::CpuTicks::now());
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    const double top_now = top_z - wall_speed * dt * static_cast<double>(steps + 1);
    std::printf("balls: %zu\nsteps: %ld\ntime_step_s: %.3g\ngamma_n_per_s: %.4g\nskin_m: %.3g\nthreads: %d\n", ball_count,
                steps, dt, gamma_n, 0.25 * d_min, world.threads());
    std::printf("loop_time_s: %.3f\nparticle_steps_per_second: %.4g\n", seconds, ball_count * steps / seconds);
    // Above a few percent the rate above is the hypervisor's, not the code's (cpu_steal.hpp).
    std::printf("cpu_steal_fraction: %.3f\n", steal);
    std::printf("contacts_per_ball_start: %.4f\ncontacts_per_ball_end: %.4f\n", contacts_start,
                2.0 * world.contact_count(ContactKind::BallBall) / ball_count);
    // Candidate pairs per ball (within reach + skin): what the pair loop scans every step.
    const PairContacts& pairs = world.pair_contacts(ContactKind::BallBall);
    std::printf("candidates_per_ball: %.4f\nnear_candidates_per_ball: %.4f\nnear_refreshes: %lld\n",
                2.0 * static_cast<double>(pairs.size()) / ball_count, 2.0 * static_cast<double>(pairs.near.size()) / ball_count,
                static_cast<long long>(world.near_refresh_count()));
    std::printf("vertical_stress_Pa: %.6g\nkinetic_energy_J: %.6g\nrebuilds: %lld\npeak_rss_bytes_per_ball: %.0f\n",
                vertical_stress(world, top_now), world.kinetic_energy(), static_cast<long long>(world.rebuild_count()),
                usage.ru_maxrss * 1024.0 / ball_count);
    // After the peak RSS is read: the timed rebuilds are a separate measurement.
    if (rebuilds > 0) {
      const auto r0 = std::chrono::steady_clock::now();
      for (long r = 0; r < rebuilds; ++r) world.rebuild_now(true);
      const double rebuild_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
      std::printf("rebuild_time_s: %.4g\n", rebuild_seconds / static_cast<double>(rebuilds));
    }
  } catch (const std::exception& e) {
    std::cerr << "dem-bench: " << e.what() << "\n";
    return 2;
  }
}
