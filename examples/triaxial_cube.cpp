// A drained triaxial test on a cube of balls, written as a custom protocol: six walls compress a
// polydisperse specimen isotropically to 100 kPa under servo control, then the top and bottom
// walls approach each other at a constant axial strain rate while the four lateral servo walls
// keep 100 kPa. Prints and writes (triaxial_cube.csv, or the path given as argument) the axial
// strain, the deviatoric stress q, the mean stress p and the volumetric strain.
//
// The ServoWall objects are driven by one protocol controller rather than registered one by one
// (add_servo_wall): the protocol first updates the loaded areas from the current wall positions,
// and then decides per stage whether the axial walls are servo-controlled or strain-controlled.
#include <cstdio>
#include <random>
#include <vector>

#include <dem/control/servo_wall.hpp>
#include <dem/dem.hpp>
#include <dem/io/csv.hpp>

int main(int argc, char** argv) {
  using namespace dem;
  World world;  // local damping 0.7, no gravity, automatic time step

  // 1000 balls of 0.7-1.0 mm diameter on a jittered 10^3 lattice (no initial overlaps).
  const int n = 10;
  const double spacing = 1.02e-3;  // m
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < n * n * n; ++k) {
    BallSpec ball;
    ball.radius = 0.35e-3 + 0.15e-3 * unit(rng);  // m
    ball.density = 2650.0;                        // kg/m^3
    const Vec3 jitter = (Vec3(unit(rng), unit(rng), unit(rng)) - Vec3::Constant(0.5)) * (spacing - 2 * ball.radius);
    ball.position = (Vec3(k % n, k / n % n, k / (n * n)) + Vec3::Constant(0.5)) * spacing + jitter;
    world.add_ball(ball);
  }

  // Six walls, wall 2 * axis + (side > 0), 40 % wider than the cube so that they overlap at the
  // edges and no ball escapes when lateral walls move out.
  const double size = n * spacing;  // m
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 normal = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero(), centre = Vec3::Constant(size / 2);
      normal[axis] = side;
      u[(axis + 1) % 3] = 0.7 * size;
      v[(axis + 2) % 3] = 0.7 * size;
      centre[axis] = side > 0 ? size : 0.0;
      world.add_wall(make_facet_wall("wall", geometry::make_rectangle(centre, u, v), normal, size * size));
    }
  const auto wall_gap = [&](int axis) {  // m, specimen size along an axis
    return world.wall(2 * axis + 1).reference_point[axis] - world.wall(2 * axis).reference_point[axis];
  };

  // Frictionless walls; frictionless balls while consolidating give a dense specimen, then the
  // sand's friction and rolling resistance (E* Pa, kn/ks, mu, mu_r) are switched on for shearing.
  const auto wall_law = RollingLinearLaw::Params::deformable(5e7, 1.0, 0.0, 0.0);
  const auto slippery = RollingLinearLaw::Params::deformable(5e7, 1.5, 0.0, 0.0);
  const auto sand = RollingLinearLaw::Params::deformable(5e7, 1.5, 0.5, 0.1);
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(wall_law, "ball-facet"));
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(slippery, "ball-ball"));

  const double confining = 100e3;  // Pa
  std::vector<ServoWall> servos;
  for (WallId k = 0; k < 6; ++k) servos.emplace_back(k, ServoSettings{.target_stress = confining, .max_speed = 1.0});
  bool shearing = false;
  double axial_speed = 0.0;  // m/s, each axial wall towards the centre
  world.add_controller([&](World& w) {
    for (int axis = 0; axis < 3; ++axis)  // stresses on the current cross-section
      w.wall(2 * axis).area = w.wall(2 * axis + 1).area = wall_gap((axis + 1) % 3) * wall_gap((axis + 2) % 3);
    for (int k = 0; k < 4; ++k) servos[k](w);
    for (int k = 4; k < 6; ++k) {
      if (shearing)
        w.wall(k).velocity = -axial_speed * w.wall(k).outward_normal;
      else
        servos[k](w);
    }
  });

  // Stage 1: isotropic compression until every wall is on target and the packing is nearly static
  // (a frictionless packing creeps for long below an unbalanced-force ratio of 1e-2).
  const auto consolidated = [&](const World& w) {
    for (const ServoWall& s : servos)
      if (!s.settled()) return false;
    return w.unbalanced_force_ratio() < 1e-2;
  };
  if (!world.run_until(consolidated, 100, 400000)) std::printf("warning: consolidation did not settle\n");
  std::printf("consolidated at step %lld: %zu balls, box %.3f x %.3f x %.3f mm, dt %.3g s\n",
              static_cast<long long>(world.step_count()), world.particles().size(), wall_gap(0) * 1e3,
              wall_gap(1) * 1e3, wall_gap(2) * 1e3, world.time_step());

  // Stage 2: drained triaxial compression at 8 1/s: inertial number 8 d sqrt(rho/p) ~ 1e-3.
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(sand, "ball-ball"));
  const double strain_rate = 8.0, final_strain = 0.12;  // 1/s, -
  const double height0 = wall_gap(2), volume0 = wall_gap(0) * wall_gap(1) * wall_gap(2);
  axial_speed = 0.5 * strain_rate * height0;
  shearing = true;

  io::CsvTable table({"axial_strain", "q_Pa", "p_Pa", "volumetric_strain"});
  const auto log_interval = static_cast<std::int64_t>(0.002 / strain_rate / world.time_step());
  double peak_ratio = 0.0, peak_strain = 0.0;
  std::printf("%10s %10s %10s %8s %10s\n", "eps_a [%]", "q [kPa]", "p [kPa]", "q/p", "eps_v [%]");
  for (int row = 0; wall_gap(2) > (1 - final_strain) * height0; ++row) {
    world.step(log_interval);
    const double axial = 0.5 * (world.wall(4).normal_stress() + world.wall(5).normal_stress());  // Pa
    double lateral = 0.0;
    for (WallId k = 0; k < 4; ++k) lateral += 0.25 * world.wall(k).normal_stress();
    const double q = axial - lateral, p = (axial + 2 * lateral) / 3;
    const double eps_a = 1 - wall_gap(2) / height0;
    const double eps_v = 1 - wall_gap(0) * wall_gap(1) * wall_gap(2) / volume0;  // compression +
    table.add_row({eps_a, q, p, eps_v});
    if (q / p > peak_ratio) peak_ratio = q / p, peak_strain = eps_a;
    if (row % 5 == 4)
      std::printf("%10.2f %10.2f %10.2f %8.3f %10.3f\n", 100 * eps_a, q / 1e3, p / 1e3, q / p, 100 * eps_v);
  }
  table.save(argc > 1 ? argv[1] : "triaxial_cube.csv");
  std::printf("peak q/p = %.3f at axial strain %.2f %% (%lld steps)\n", peak_ratio, 100 * peak_strain,
              static_cast<long long>(world.step_count()));
}
