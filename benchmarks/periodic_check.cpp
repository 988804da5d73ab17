// periodic-check: libdem's side of the periodic-cell cross-check against LAMMPS
// (benchmarks/compare-periodic writes the LAMMPS side from what this prints).
//
// `periodic-check --generate --out FILE`: a periodic packing made by libdem. Balls of the
// benchmark's 4D grading (diameters uniform by number in [2.4, 4.8] mm, 2650 kg/m^3) at random
// without overlap in a cubic cell (lab::fill_periodic_cell, solid fraction 0.3), compressed
// frictionless by the cell servo to an isotropic stress (the normal stresses at --stress, the
// shear stresses at zero: the cell shears a little, so it may be triclinic) with local damping
// 0.7, until every stress is within 0.5 % of its target and the unbalanced force ratio is below
// 0.01. Written as '# key value' header lines (the cell matrix cell_ab, upper triangular as a
// LAMMPS triclinic box, its origin, counts) and 'x y z radius' lines (m), positions in the cell.
//
// `periodic-check --packing FILE --path simple-shear|uniaxial --strain S --rate R`: the packing,
// at rest and without contact history, deformed by a constant velocity gradient: simple shear
// L_xz = R (the tilt xz grows at R h_zz, LAMMPS's `fix deform xz erate R`) to a shear strain S, or
// uniaxial compression L_zz = -R (a true strain rate, LAMMPS's `z trate -R`) to an axial strain
// S = 1 - h_zz / h0_zz. The dem-bench law (rrlinear: kn = kt = 7e4 N/m, mu 0.5, mu_r 0.17,
// kr = kt Reff^2, mass-proportional dashpots gamma_n m_eff on both springs), its time step and
// dashpot rate for the grading (bench_system.hpp); no gravity, no local damping, the cell never
// re-mapped (LAMMPS's `flip no`); --friction, --rolling-friction and --damping-rate (gamma_n,
// 0: no dashpots) replace the law's values. Prints the parameters as 'key: value' lines, then
// --rows + 1 rows of the cell stress (the contact part of measure::cell_stress, compression
// positive, Pa).
//
// Step alignment: libdem's step k computes the forces from the positions at (k - 1) dt, LAMMPS's
// step k from those at k dt (velocity Verlet, velocities half a step behind in both), so a row
// labelled step k is read after k + 1 libdem steps: the forces of the same positions.
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>

#include <dem/dem.hpp>
#include <dem/lab/toolkit/periodic_specimen.hpp>

#include "bench_system.hpp"

namespace po = boost::program_options;
using namespace dem;
using namespace dem::bench;

namespace {

constexpr double d_min = 2.4e-3, d_max = 4.8e-3;  // m, dem-bench's 4D grading
constexpr const char* cell_keys[3][3] = {
    {"cell_xx", "cell_xy", "cell_xz"}, {"cell_yx", "cell_yy", "cell_yz"}, {"cell_zx", "cell_zy", "cell_zz"}};

WorldSettings world_settings(double dt, double local_damping, int threads) {
  WorldSettings s;
  s.time_step = dt;
  s.local_damping = local_damping;
  s.gravity = Vec3::Zero();
  s.skin = 0.25 * d_min;
  s.threads = threads;
  s.adapt_threads = false;
  return s;
}

/// The cell stress of the last step's contacts, compression positive (Pa).
Mat3 contact_stress(const World& world) { return -measure::cell_stress(world).contact_part; }

void generate(const std::string& out, long balls, std::uint64_t seed, double stress, int threads) {
  const SystemParams sys = system_params(d_min, d_max);
  World world(world_settings(sys.time_step, 0.7, threads));
  lab::PeriodicSpecimenSettings spec;
  spec.grading.d_min = d_min;
  spec.grading.d_max = d_max;
  spec.balls = balls;
  spec.seed = seed;
  spec.density = density;
  spec.section = "generate";
  lab::fill_periodic_cell(world, spec);
  world.set_contact_model(ContactKind::BallBall, bench_law(sys.gamma_n, 0.0, 0.0));
  CellServoSettings servo = CellServoSettings::isotropic(stress, 2.0);
  servo.relaxation = 0.1;
  for (std::size_t a = 3; a < 6; ++a) servo.stress_controlled[a] = true;  // shear stresses held at zero
  add_cell_servo(world, servo);
  bool reached = false;
  while (!reached) {
    if (world.step_count() >= 2'000'000) throw InputError("--generate: the isotropic compression did not settle within 2,000,000 steps");
    world.step(100);
    reached = lab::isotropic_state_reached(world, stress, 0.005, 0.01);
    if (world.step_count() % 10000 == 0) {
      const Mat3 s = contact_stress(world);
      std::printf("step %lld: normal stresses %.4g %.4g %.4g Pa, unbalanced force ratio %.3g\n",
                  static_cast<long long>(world.step_count()), s(0, 0), s(1, 1), s(2, 2), world.unbalanced_force_ratio());
      std::fflush(stdout);
    }
  }
  const PeriodicCell& cell = *world.periodic_cell();
  const Mat3& h = cell.matrix();
  const ParticleStore& p = world.particles();
  double solid = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) solid += 4.0 / 3.0 * pi * std::pow(p.radius[i], 3);
  const Mat3 sigma = contact_stress(world);
  std::ofstream f(out);
  if (!f) throw InputError("--out = " + out + ": cannot write the file");
  f << std::setprecision(17);
  f << "# periodic packing made by periodic-check --generate (libdem): x y z radius (m) below\n";
  f << "# balls " << p.size() << "\n# seed " << seed << "\n# d_min " << d_min << "\n# d_max " << d_max << "\n";
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) f << "# " << cell_keys[a][b] << " " << h(a, b) << "\n";
  f << "# origin_x " << cell.origin().x() << "\n# origin_y " << cell.origin().y() << "\n# origin_z " << cell.origin().z() << "\n";
  f << "# porosity " << 1.0 - solid / cell.volume() << "\n# mean_stress " << sigma.trace() / 3 << "\n";
  f << "# contacts_per_ball " << 2.0 * world.contact_count(ContactKind::BallBall) / p.size() << "\n";
  f << "# steps " << world.step_count() << "\n";
  // By ball id, at their positions inside the cell.
  for (std::size_t id = 0; id < p.size(); ++id) {
    const std::size_t i = p.index_of(static_cast<ParticleId>(id));
    const Vec3 x = cell.wrapped(p.x[i]);
    f << x.x() << " " << x.y() << " " << x.z() << " " << p.radius[i] << "\n";
  }
  std::printf("wrote %s: %zu balls, cell %.6g x %.6g x %.6g mm, porosity %.4f, p %.6g Pa, %lld steps\n", out.c_str(),
              p.size(), h(0, 0) * 1e3, h(1, 1) * 1e3, h(2, 2) * 1e3, 1.0 - solid / cell.volume(), sigma.trace() / 3,
              static_cast<long long>(world.step_count()));
}

void deform(const std::string& packing_path, const std::string& path, double strain, double rate, long rows, double mu, double mu_r,
            double damping_rate, int threads) {
  if (path != "simple-shear" && path != "uniaxial")
    throw InputError("--path = " + path + ": must be simple-shear or uniaxial");
  if (!(strain > 0.0 && strain < 0.5)) throw InputError("--strain = " + std::to_string(strain) + ": must be in (0, 0.5)");
  if (!(rate > 0.0)) throw InputError("--rate = " + std::to_string(rate) + ": must be > 0 (1/s)");
  if (rows < 1) throw InputError("--rows = " + std::to_string(rows) + ": must be >= 1");
  const Packing packing = read_packing(packing_path);
  Mat3 h;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      h(a, b) = packing.header_value(cell_keys[a][b]);
      if (!std::isfinite(h(a, b))) throw InputError("--packing = " + packing_path + ": no '# " + cell_keys[a][b] + "' line");
    }
  const Vec3 origin(packing.header_value("origin_x"), packing.header_value("origin_y"), packing.header_value("origin_z"));
  const SystemParams sys = system_params(d_min, d_max);
  const double dt = sys.time_step;
  const double gamma_n = damping_rate >= 0.0 ? damping_rate : sys.gamma_n;
  // Steps to the strain at the constant rate: the shear grows linearly, the axial stretch
  // exponentially (a constant true rate).
  const double time = path == "simple-shear" ? strain / rate : -std::log(1.0 - strain) / rate;
  const long steps = std::lround(time / dt);
  const long every = std::max(1L, steps / rows);
  World world(world_settings(dt, 0.0, threads));
  for (const BallSpec& b : packing.balls) world.add_ball(b);
  PeriodicCell cell(h, origin);
  cell.set_tilt_remap(false);
  Mat3 gradient = Mat3::Zero();
  if (path == "simple-shear")
    gradient(0, 2) = rate;
  else
    gradient(2, 2) = -rate;
  cell.set_velocity_gradient(gradient);
  world.set_periodic_cell(cell);
  world.set_contact_model(ContactKind::BallBall, bench_law(gamma_n, mu, mu_r));
  std::printf("balls: %zu\npath: %s\nstrain: %.17g\nrate_per_s: %.17g\nsteps: %ld\nevery: %ld\ntime_step_s: %.17g\n"
              "gamma_n_per_s: %.17g\nskin_m: %.17g\nnormal_stiffness_N_per_m: %.17g\nshear_stiffness_N_per_m: %.17g\n"
              "friction: %.17g\nrolling_friction: %.17g\ndensity_kg_per_m3: %.17g\n",
              packing.balls.size(), path.c_str(), strain, rate, steps, every, dt, gamma_n, sys.skin, normal_stiffness,
              normal_stiffness, mu, mu_r, density);
  std::printf("columns: step strain sxx syy szz syz sxz sxy contacts kinetic_mean_stress\n");
  const auto row = [&](long step) {
    const measure::CellStress s = measure::cell_stress(world);
    const Mat3 c = -s.contact_part;
    // The strain of the positions the forces were computed at (step k, k dt).
    const double t = static_cast<double>(step) * dt;
    const double e = path == "simple-shear" ? rate * t : 1.0 - std::exp(-rate * t);
    std::printf("row %ld %.10g %.12g %.12g %.12g %.12g %.12g %.12g %zu %.6g\n", step, e, c(0, 0), c(1, 1), c(2, 2), c(1, 2),
                c(0, 2), c(0, 1), world.contact_count(ContactKind::BallBall), -s.kinetic_part.trace() / 3);
  };
  world.step(1);  // the forces of the positions at step 0
  row(0);
  // The steps alone are timed (not the rows' stress sums): the cost of a periodic step, to set
  // beside dem-bench's walled one of the same grading, law and time step.
  double stepping = 0.0;
  for (long k = every; k <= steps; k += every) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(every);
    stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row(k);
  }
  const double stepped = static_cast<double>(steps / every * every);
  std::printf("loop_time_s: %.3f\nparticle_steps_per_second: %.4g\ncontacts_per_ball_end: %.4f\nthreads: %d\n", stepping,
              static_cast<double>(packing.balls.size()) * stepped / stepping,
              2.0 * static_cast<double>(world.contact_count(ContactKind::BallBall)) / static_cast<double>(packing.balls.size()),
              world.threads());
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description opts("periodic-check options");
  std::string out, packing, path;
  long balls = 1000, rows = 10;
  unsigned long long seed = 1;
  double stress = 1e5, strain = 0.02, rate = 1.0, mu = friction, mu_r = rolling_friction, damping_rate = -1.0;
  int threads = 1;
  opts.add_options()("help", "this help")("generate", "make a periodic packing and write it to --out")(
      "out", po::value(&out), "packing file written by --generate")(
      "balls", po::value(&balls)->default_value(1000), "balls of --generate")(
      "seed", po::value(&seed)->default_value(1), "random seed of --generate")(
      "stress", po::value(&stress)->default_value(1e5), "isotropic stress of --generate (Pa)")(
      "packing", po::value(&packing), "packing file to deform (written by --generate)")(
      "path", po::value(&path)->default_value("simple-shear"), "simple-shear (L_xz = rate) or uniaxial (L_zz = -rate)")(
      "strain", po::value(&strain)->default_value(0.02), "shear strain or axial strain at the end")(
      "rate", po::value(&rate)->default_value(1.0), "shear rate or true axial strain rate (1/s)")(
      "rows", po::value(&rows)->default_value(10), "stress rows after the start")(
      "friction", po::value(&mu)->default_value(friction), "ball-ball friction of the deformation")(
      "rolling-friction", po::value(&mu_r)->default_value(rolling_friction), "ball-ball rolling friction of the deformation")(
      "damping-rate", po::value(&damping_rate)->default_value(-1.0),
      "gamma_n of both dashpots (1/s) in the deformation; negative: the benchmark's for the grading")(
      "threads", po::value(&threads)->default_value(1), "OpenMP threads");
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, opts), vm);
    if (vm.count("help")) {
      std::cout << opts << "\n";
      return 0;
    }
    po::notify(vm);
    if (threads < 1) throw InputError("--threads = " + std::to_string(threads) + ": must be >= 1");
    if (vm.count("generate")) {
      if (out.empty()) throw InputError("--generate needs --out FILE");
      if (balls < 100) throw InputError("--balls = " + std::to_string(balls) + ": must be >= 100 (a cell three search cells wide)");
      if (!(stress > 0.0)) throw InputError("--stress = " + std::to_string(stress) + ": must be > 0 (Pa)");
      generate(out, balls, seed, stress, threads);
      return 0;
    }
    if (packing.empty()) throw InputError("--packing FILE (or --generate --out FILE) is required");
    if (!(mu >= 0.0)) throw InputError("--friction = " + std::to_string(mu) + ": must be >= 0");
    if (!(mu_r >= 0.0)) throw InputError("--rolling-friction = " + std::to_string(mu_r) + ": must be >= 0");
    deform(packing, path, strain, rate, rows, mu, mu_r, damping_rate, threads);
  } catch (const std::exception& e) {
    std::cerr << "periodic-check: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
