// dem-bench: the peers' benchmark system (LAMMPS and LIGGGHTS run it from the inputs that
// benchmarks/compare-peers writes), run by libdem: a dense packing in a 70 mm cylinder (side wall,
// bottom plane, top plane moving down at 5 mm/s), constant kn = kt = 7e4 N/m, mu 0.5, rolling
// resistance kr = kt Rbar^2 with mu_r 0.17, mass-proportional dashpots gamma m_eff (LAMMPS
// `damping mass_velocity`), gravity, no local damping. Time step, dashpot rate and skin follow
// from the packing's radii (bench_system.hpp); --describe prints them for the peers' inputs.
//
// Prints particle-steps per second of the timed loop, mean ball-ball contacts per ball and the
// vertical stress from the ball-ball contact virial over the current cylinder volume, the
// quantities the peers report, so that speed is compared on the same physics.
//
// `dem-bench --generate 1750|14k|112k --out FILE` makes the benchmark packing itself
// (packing_generator.cpp), so that nothing outside the repository is needed.
//
// Under mpirun (a build with libdem::mpi) the run is spread over the ranks (World::spread_over):
// `mpirun -n 2 dem-bench --packing FILE --threads 1` is the strong-scaling measurement, and
// --digest prints a hash of the final state that is the same for any rank and thread count.
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
#include <utility>

#include <dem/core/block_isa.hpp>
#include <dem/dem.hpp>
#include <dem/lab/toolkit/cementation.hpp>

#include "bench_system.hpp"
#include "cpu_steal.hpp"
#include "cli/task_farm.hpp"

namespace po = boost::program_options;
using namespace dem;
using namespace dem::bench;

namespace {

/// FNV-1a over the bytes of every particle's position, velocities, force and torque (storage
/// order) and every wall's force and displacement: equal digests, the same state bit for bit.
std::uint64_t state_digest(const World& world) {
  std::uint64_t h = 1469598103934665603ULL;
  const auto add = [&h](const auto& values) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (std::size_t b = 0; b < values.size() * sizeof(values[0]); ++b) h = (h ^ bytes[b]) * 1099511628211ULL;
  };
  const ParticleStore& p = world.particles();
  add(p.x), add(p.v), add(p.w), add(p.f), add(p.t);
  for (const Wall& w : world.walls()) add(std::vector<Vec3>{w.force, w.displacement});
  return h;
}

/// --isa: the contact blocks' and the leapfrog's instruction set for the whole run. One the
/// processor lacks is an error, not a quiet fallback, so that a measurement is of what it says.
void use_isa(const std::string& name) {
  using detail::BlockIsa;
  const std::pair<const char*, BlockIsa> known[] = {
      {"avx512", BlockIsa::avx512}, {"avx2", BlockIsa::avx2}, {"scalar", BlockIsa::scalar}};
  if (name == "best") return;
  for (const auto& [known_name, isa] : known)
    if (name == known_name) {
      if (static_cast<int>(isa) > static_cast<int>(detail::detected_block_isa()))
        throw InputError("--isa = " + name + ": this processor (or compiler) does not offer it");
      detail::use_block_isa(isa);
      return;
    }
  throw InputError("--isa = " + name + ": must be best, avx512, avx2 or scalar");
}

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<parallel::TaskFarm> farm;
  try {
    farm = cli::open_task_farm(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "dem-bench: " << e.what() << "\n";
    return 2;
  }
  // One rank reports: the others run the same steps silently.
  if (!farm->leads() && std::freopen("/dev/null", "w", stdout) == nullptr) return 2;
  po::options_description opts("dem-bench options");
  std::string packing;
  long steps = 0;
  long rebuilds = 0;
  int threads = 1;
  GenerateOptions generate;
  opts.add_options()("help", "this help")("packing", po::value(&packing), "packing file: x y z radius (m) per line")(
      "steps", po::value(&steps)->default_value(0), "timed steps (0: the peers' count for this size)")(
      "threads", po::value(&threads)->default_value(1), "OpenMP threads")(
      "pin-threads", "keep the team at --threads every step (the engine otherwise runs a step on fewer while that is "
      "faster, as on a busy machine: core/thread_team.hpp)")(
      "segments", po::value<int>()->default_value(360), "facets around the cylinder side wall")(
      "report-every", po::value<long>()->default_value(0), "print contacts and stress every N steps (0: never)")(
      "rebuilds", po::value(&rebuilds)->default_value(0),
      "after the run, time this many forced neighbour-list rebuilds (re-sort, pair search, history carried over)")(
      "boundary", po::value<std::string>()->default_value("cylinder"),
      "cylinder: the peers' walls as facets (side wall of --segments); analytic: the same walls as an analytic "
      "cylinder and planes; rings: the simple-shear boundary (clump ring stack and facet discs); "
      "none: no walls (to measure what the boundaries cost)")(
      "describe", "print the run's parameters (time step, dashpot rate, skin, top plane, steps) for --packing and exit "
      "(what compare-peers gives LAMMPS and LIGGGHTS)")(
      "generate", po::value(&generate.size),
      "make the benchmark packing 1750, 14k or 112k with libdem (seeded, the same every time; see packing_generator.cpp) "
      "and write it to --out")(
      "out", po::value(&generate.out), "packing file written by --generate")(
      "seed", po::value(&generate.seed)->default_value(1), "random seed of --generate")(
      "law", po::value<std::string>()->default_value("rrlinear"),
      "contact law: rrlinear (the peers' benchmark law) or hertz-mindlin (its stiffness matched at the packing's "
      "mean overlap, bench_system.hpp), to time one against the other")(
      "damping-model", po::value<std::string>()->default_value("liggghts"),
      "hertz-mindlin's dashpot: liggghts (LIGGGHTS's model hertz) or tsuji (LAMMPS's damping tsuji), the peer "
      "compare-peers --law hertz runs it against")(
      "rolling-friction", po::value<double>()->default_value(rolling_friction),
      "rolling friction mu_r of either law (0: no rolling resistance; LAMMPS's rolling sds has no Hertz-scaled "
      "spring, so compare-peers runs the tsuji comparison without it)")(
      "rolling", po::value<std::string>()->default_value("epsd"),
      "hertz-mindlin's rolling resistance: epsd (LIGGGHTS's epsd2 spring), cdt (its constant directional torque) or "
      "sds (LAMMPS's rolling sds spring of --rolling-stiffness), the model compare-peers --law hertz gives the peer")(
      "rolling-stiffness", po::value<double>()->default_value(0.0),
      "k_roll (N/m) of --rolling sds: the rolling spring k_roll R*^2")(
      "cement", po::value<double>()->default_value(0.0),
      "bond every pair of balls whose gap is below this x their mean radius (lab::cement) with linear parallel "
      "bonds too strong to break, their kn A the contacts' normal stiffness at the mean radius: the bonded step's "
      "cost against the plain one's (0: no bonds)")(
      "digest", "print a hash of the final state (state_digest), the same bit for bit for any rank and thread count")(
      "isa", po::value<std::string>()->default_value("best"),
      "instruction set of the contact blocks and the leapfrog: best (the processor's), avx512, avx2 or scalar; "
      "every one gives the same bits, so that their speeds can be compared on one machine");
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, opts), vm);
    if (vm.count("help")) {
      std::cout << opts << "\n";
      return 0;
    }
    po::notify(vm);
    if (threads < 1) throw InputError("--threads = " + std::to_string(threads) + ": must be >= 1");
    use_isa(vm["isa"].as<std::string>());
    if (vm.count("generate")) {
      if (vm.count("packing")) throw InputError("--generate and --packing: give one of them");
      if (farm->processes() > 1) throw InputError("--generate runs in one process: run it without mpirun");
      generate.threads = threads;
      generate_packing(generate);
      return 0;
    }
    if (packing.empty()) throw InputError("--packing FILE (or --generate SIZE --out FILE) is required");
    if (steps < 0) throw InputError("--steps = " + std::to_string(steps) + ": must be >= 0");
    if (rebuilds < 0) throw InputError("--rebuilds = " + std::to_string(rebuilds) + ": must be >= 0");
    Packing input = read_packing(packing);
    auto& balls = input.balls;
    double r_min = 1e9, r_max = 0;
    for (const auto& b : balls) r_min = std::min(r_min, b.radius), r_max = std::max(r_max, b.radius);
    // The peers' parameter rules (bench_system.hpp) from the packing's smallest and largest balls.
    const SystemParams sys = system_params(2 * r_min, 2 * r_max);
    const double dt = sys.time_step, gamma_n = sys.gamma_n, d_min = sys.d_min, wall_speed = bench::wall_speed;
    if (steps == 0) steps = balls.size() < 5000 ? 10000 : balls.size() < 50000 ? 5000 : 1000;
    double top_z = input.header_value("top_wall_z");
    if (!std::isfinite(top_z)) {
      top_z = 0;
      for (const auto& b : balls) top_z = std::max(top_z, b.position.z() + b.radius);
    }
    const std::string law = vm["law"].as<std::string>();
    if (law != "rrlinear" && law != "hertz-mindlin")
      throw InputError("--law = " + law + ": must be rrlinear or hertz-mindlin");
    const std::string damping_name = vm["damping-model"].as<std::string>();
    if (damping_name != "liggghts" && damping_name != "tsuji")
      throw InputError("--damping-model = " + damping_name + ": must be liggghts or tsuji");
    if (damping_name != "liggghts" && law != "hertz-mindlin")
      throw InputError("--damping-model = " + damping_name + ": only with --law hertz-mindlin (--law is " + law + ")");
    const HertzDamping damping = damping_name == "tsuji" ? HertzDamping::tsuji : HertzDamping::liggghts;
    const std::string rolling_name = vm["rolling"].as<std::string>();
    if (rolling_name != "epsd" && rolling_name != "cdt" && rolling_name != "sds")
      throw InputError("--rolling = " + rolling_name + ": must be epsd, cdt or sds");
    if (rolling_name != "epsd" && law != "hertz-mindlin")
      throw InputError("--rolling = " + rolling_name + ": only with --law hertz-mindlin (--law is " + law + ")");
    const HertzRolling rolling = rolling_name == "cdt" ? HertzRolling::cdt : rolling_name == "sds" ? HertzRolling::sds : HertzRolling::epsd;
    const double rolling_stiffness = vm["rolling-stiffness"].as<double>();
    const double mu_r = vm["rolling-friction"].as<double>();
    if (!(mu_r >= 0.0)) throw InputError("--rolling-friction = " + std::to_string(mu_r) + ": must be >= 0");
    if (vm.count("describe")) {
      std::printf("balls: %zu\nsteps: %ld\ntime_step_s: %.17g\ngamma_n_per_s: %.17g\nskin_m: %.17g\ntop_wall_z_m: %.17g\n"
                  "cylinder_radius_m: %.17g\nwall_speed_m_per_s: %.17g\nnormal_stiffness_N_per_m: %.17g\nshear_stiffness_N_per_m: %.17g\n"
                  "friction: %.17g\nrolling_friction: %.17g\ndensity_kg_per_m3: %.17g\ngravity_m_per_s2: 9.81\n"
                  "packing_recipe: %.0f\ngenerator_recipe: %d\n",
                  balls.size(), steps, dt, gamma_n, sys.skin, top_z, cylinder_radius, wall_speed, normal_stiffness, normal_stiffness,
                  friction, mu_r, density, input.header_value("recipe"), packing_recipe);
      if (law == "hertz-mindlin") {
        // The material the peers' Hertz laws take (compare-peers --law hertz), and what it derives to.
        HertzMindlinParams h = bench_hertz_params(balls, friction, mu_r, damping, rolling);
        h.rolling_stiffness = rolling_stiffness;
        h.validate("--rolling-stiffness: the law");
        std::printf("law: hertz-mindlin\ndamping_model: %s\nrolling: %s\nyoungs_modulus_Pa: %.17g\npoissons_ratio: %.17g\n"
                    "restitution: %.17g\neffective_modulus_Pa: %.17g\neffective_shear_modulus_Pa: %.17g\n"
                    "rolling_stiffness_N_per_m: %.17g\n",
                    to_string(h.damping_model), to_string(h.rolling), h.youngs_modulus, h.poissons_ratio, h.restitution,
                    h.effective_modulus, h.effective_shear_modulus, h.rolling_stiffness);
      }
      return 0;
    }

    WorldSettings s;
    s.time_step = dt;
    s.local_damping = 0.0;
    s.gravity = Vec3(0, 0, -9.81);
    s.skin = 0.25 * d_min;
    s.threads = threads;
    s.adapt_threads = vm.count("pin-threads") == 0;
    World world(s);
    for (const auto& b : balls) world.add_ball(b);
    // The input copy (96 B per ball) is the benchmark's, not the library's: drop it before the
    // peak RSS is reached (the first neighbour-list build).
    const std::size_t ball_count = balls.size();
    std::shared_ptr<const ContactModel> model;
    if (law == "rrlinear") {
      model = bench_law(gamma_n, friction, mu_r);
    } else {
      HertzMindlinParams h = bench_hertz_params(balls, friction, mu_r, damping, rolling);  // needs the packing
      h.rolling_stiffness = rolling_stiffness;
      model = make_contact_model<HertzMindlinLaw>(h, "--rolling-stiffness: the law");
    }
    std::vector<BallSpec>().swap(balls);
    const std::string boundary = vm["boundary"].as<std::string>();
    if (boundary != "cylinder" && boundary != "analytic" && boundary != "rings" && boundary != "none")
      throw InputError("--boundary = " + boundary + ": must be cylinder, analytic, rings or none");
    const int segments = vm["segments"].as<int>();
    WallId top = -1;
    if (boundary == "cylinder") {
      top = add_cylinder_walls(world, top_z, top_z + 0.001, segments);
    } else if (boundary == "analytic") {
      top = add_analytic_walls(world, top_z);
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
    for (ContactKind k : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) world.set_contact_model(k, model);
    const auto domains = cli::open_domains(*farm);
    if (domains) world.spread_over(domains);

    world.step(1);  // neighbour lists and contacts, as the peers' setup before the timed run
    if (const double gap_ratio = vm["cement"].as<double>(); gap_ratio > 0.0) {
      require(!domains, "--cement", gap_ratio, "one process (bonds do not cross ranks yet)");
      const double r_mean = 0.25 * (2 * r_min + 2 * r_max);
      ParallelBondMaterial cement;
      cement.normal_stiffness = cement.shear_stiffness = normal_stiffness / (pi * r_mean * r_mean);  // Pa/m
      cement.tensile_strength = cement.cohesion = 1e15;  // Pa: none breaks
      const std::size_t bonds = lab::cement(world, cement, gap_ratio);
      std::printf("bonds: %zu (%.3f per ball)\n", bonds, 2.0 * static_cast<double>(bonds) / static_cast<double>(ball_count));
    }
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
    world.reset_step_timing();
    const std::uint64_t sent0 = domains ? domains->bytes_sent() : 0;
    const auto ticks0 = bench::CpuTicks::now();
    const std::int64_t regions0 = parallel_regions().load();
    const auto t0 = std::chrono::steady_clock::now();
    world.step(steps);
    const std::int64_t regions = parallel_regions().load() - regions0;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double steal = bench::steal_fraction(ticks0, bench::CpuTicks::now());
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    const double top_now = top_z - wall_speed * dt * static_cast<double>(steps + 1);
    std::printf("balls: %zu\nsteps: %ld\ntime_step_s: %.3g\ngamma_n_per_s: %.4g\nskin_m: %.3g\nthreads: %d\n", ball_count,
                steps, dt, gamma_n, 0.25 * d_min, world.threads());
    std::printf("ranks: %d\n", world.ranks());
    // Parallel regions per step: each ends in a barrier where the threads wait for the slowest.
    std::printf("parallel_regions_per_step: %.2f\n", static_cast<double>(regions) / static_cast<double>(steps));
    // Steps the adapting team ran on fewer threads than --threads (a busy machine).
    std::printf("steps_on_fewer_threads: %lld\n",
                static_cast<long long>(world.step_count() - world.thread_team().steps_on(world.threads())));
    // What rank 0 sent per step of the loop (ghosts, gathered sums, the rebuilds' and the end's
    // synchronisation), bytes.
    if (domains) std::printf("sent_bytes_per_step: %.0f\n", static_cast<double>(domains->bytes_sent() - sent0) / static_cast<double>(steps));
    std::printf("loop_time_s: %.3f\nparticle_steps_per_second: %.4g\n", seconds, ball_count * steps / seconds);
    // Where the loop's time went on this rank (StepTiming; communication: spread over ranks).
    const StepTiming& split = world.step_timing();
    std::printf("step_time_s: rebuilds %.3f ball_ball %.3f ball_pebble %.3f ball_facet %.3f force_sums %.3f integration %.3f "
                "communication %.3f\n", split.rebuilds, split.ball_ball, split.ball_pebble, split.ball_facet, split.force_sums,
                split.integration, split.communication);
    // Above a few percent the rate above is the hypervisor's, not the code's (cpu_steal.hpp).
    std::printf("cpu_steal_fraction: %.3f\n", steal);
    std::printf("contacts_per_ball_start: %.4f\ncontacts_per_ball_end: %.4f\n", contacts_start,
                2.0 * world.contact_count(ContactKind::BallBall) / ball_count);
    // Candidate pairs per ball (within reach + skin): what the pair loop scans every step.
    const PairContacts& pairs = world.pair_contacts(ContactKind::BallBall);
    const PairPlan& pair_plan = world.pair_plan(ContactKind::BallBall);
    std::printf("candidates_per_ball: %.4f\nnear_candidates_per_ball: %.4f\nnear_refreshes: %lld\n",
                2.0 * static_cast<double>(pairs.size()) / ball_count, 2.0 * static_cast<double>(pair_plan.near.size()) / ball_count,
                static_cast<long long>(world.near_refresh_count()));
    std::printf("vertical_stress_Pa: %.6g\nkinetic_energy_J: %.6g\nrebuilds: %lld\npeak_rss_bytes_per_ball: %.0f\n",
                vertical_stress(world, top_now), world.kinetic_energy(), static_cast<long long>(world.rebuild_count()),
                usage.ru_maxrss * 1024.0 / ball_count);
    if (vm.count("digest")) std::printf("state_digest: %016llx\n", static_cast<unsigned long long>(state_digest(world)));
    // After the peak RSS is read: the timed rebuilds are a separate measurement.
    if (rebuilds > 0) {
      const auto r0 = std::chrono::steady_clock::now();
      for (long r = 0; r < rebuilds; ++r) world.rebuild_now(true);
      const double rebuild_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
      std::printf("rebuild_time_s: %.4g\n", rebuild_seconds / static_cast<double>(rebuilds));
    }
  } catch (const std::exception& e) {
    return cli::end_on_error(*farm, "dem-bench", e, 2, std::cerr);
  }
}
