// K0 consolidation, then constant-volume simple shear: a protocol written from the lab toolkit's
// parts on a World this program owns. A small cylindrical specimen is made by radius expansion
// inside a stack of clump rings, loaded one-dimensionally by the servo-controlled top plate to
// 50, 100 and 200 kPa (the rings keep the cross-section, so the lateral stress they feel over the
// vertical stress is K0), then sheared at constant height: with the volume held, the vertical
// stress is free to change, as the pore pressure would in an undrained test.
//
// Writes the shear stage (k0_constant_volume.csv, or the path given as argument): shear strain,
// shear stress, vertical stress, stress ratio, height. Usage: k0_constant_volume [csv [strain]].
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <dem/dem.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/consolidation.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/radius_expansion.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>

int main(int argc, char** argv) {
  using namespace dem;
  const std::string csv = argc > 1 ? argv[1] : "k0_constant_volume.csv";
  const double final_strain = argc > 2 ? std::stod(argv[2]) : 0.15;  // -

  World world;  // local damping 0.7, automatic time step

  // The cell: 20 mm x 8 mm, rings of 1.4 mm pebbles that move with the specimen's height.
  lab::ShearCellSpec spec;
  spec.diameter = 0.020;
  spec.height = 0.008;
  spec.pebble_diameter = 1.4e-3;
  spec.ring_gap = 0.07e-3;
  spec.max_opening = 1.4e-3;
  spec.rings = lab::RingVertical::Follow;
  const lab::ShearCell cell = lab::build_shear_cell(world, spec);

  // Contacts (E* Pa, kn/ks, mu, mu_r), no dashpots (local damping only, as the study): frictionless
  // while the radii grow, for a dense specimen.
  const auto set_law = [&](ContactKind kind, double modulus, double mu, double mu_r) {
    const auto law = RollingLinearLaw::Params::deformable(modulus, 1.0, mu, mu_r);
    world.set_contact_model(kind, make_contact_model<RollingLinearLaw>(law, "law"));
  };
  set_law(ContactKind::BallBall, 1.2e7, 0.0, 0.0);
  set_law(ContactKind::BallFacet, 2e7, 0.0, 0.0);
  set_law(ContactKind::BallPebble, 2e7, 0.0, 0.0);

  // The specimen: diameters uniform on 1.4-2.4 mm for a porosity of 0.40, placed at half size.
  lab::Grading grading;
  grading.scale = 2.0;
  std::mt19937_64 rng(7);
  const double cavity = cell.area * spec.height;  // m^3
  const std::vector<double> diameters = lab::sample_diameters(grading, (1 - 0.40) * cavity, rng);
  const lab::RadiusExpansion expansion =
      lab::add_expanding_balls(world, {cell.radius, spec.height}, diameters, 2650.0, 4, rng);

  // One controller: the servo (once there is one), then the rings and, while shearing, the damping
  // frame (uniform shear between the plates, docs/model.md 3.1), which read the plate velocities.
  std::unique_ptr<ServoWall> servo;
  bool specimen_made = false, shearing = false;
  world.add_controller([&](World& w) {
    if (servo) (*servo)(w);
    lab::move_rings(w, cell, specimen_made);
    if (shearing) w.set_damping_frame(lab::plate_damping_frame(w, cell));
  });

  // Radius expansion in the closed cell, cycling to equilibrium after each stage.
  const auto balanced = [](const World& w) { return w.unbalanced_force_ratio() < 1e-2; };
  for (int stage = 1; stage <= expansion.stages; ++stage) {
    for (int increment = 1; increment <= expansion.increments; ++increment) {
      lab::set_radii(world, expansion, expansion.factor(stage, increment));
      world.step(expansion.steps_per_increment);
    }
    world.run_until(balanced, 100, 20000);
  }
  specimen_made = true;
  lab::release_rings(world, cell);
  std::printf("%zu balls generated in %lld steps\n", diameters.size(), static_cast<long long>(world.step_count()));

  // K0 consolidation in three load steps, with the sand's friction. The radii grew against the
  // rings, which keep some of that lateral stress: K0 starts above 1 and falls towards the normally
  // consolidated value as the vertical stress grows.
  set_law(ContactKind::BallBall, 1.2e7, 0.5, 0.1);
  set_law(ContactKind::BallFacet, 2e7, 0.9, 0.9);
  set_law(ContactKind::BallPebble, 2e7, 0.1, 0.1);
  servo = std::make_unique<ServoWall>(cell.top, ServoSettings{.target_stress = 50e3, .max_speed = 0.05, .settle_steps = 300});
  std::printf("%12s %12s %12s %8s %10s\n", "sigma_v [kPa]", "sigma_h [kPa]", "height [mm]", "K0", "settled");
  for (const double stress : {50e3, 100e3, 200e3}) {
    const lab::ConsolidationTarget target{.vertical_stress = stress, .max_steps = 200000};
    lab::start_consolidation(*servo, target);
    const lab::ConsolidationReport report = lab::consolidate(world, *servo, target, world.step_count());
    const double lateral = lab::ring_lateral_stress(world, cell);
    std::printf("%12.2f %12.2f %12.4f %8.3f %10s\n", report.stress / 1e3, lateral / 1e3, cell.plate_gap(world) * 1e3,
                lateral / report.stress, report.settled ? "yes" : "no");
  }

  // Constant-volume shear at an inertial number of 1e-3 (docs/model.md 3.4).
  const double height = cell.plate_gap(world);  // m
  const double mean_diameter = 0.5 * (grading.smallest() + grading.largest());                 // m
  const double strain_rate = 1e-3 / (mean_diameter * std::sqrt(2650.0 / 200e3));  // 1/s, I = 1e-3
  lab::start_shear_leg(world, cell, *servo,
                       {.direction_deg = 0.0, .speed = strain_rate * height, .mode = lab::ShearMode::ConstantVolume});
  lab::ShearPath path(world, cell, height);
  shearing = true;
  io::CsvTable table({"shear_strain", "shear_stress_Pa", "vertical_stress_Pa", "stress_ratio", "height_m"});
  const auto steps_per_row = static_cast<std::int64_t>(0.005 / strain_rate / world.time_step());
  std::printf("%10s %10s %12s %8s\n", "gamma [%]", "tau [kPa]", "sigma_v [kPa]", "tau/sv");
  while (path.strain() < final_strain) {
    world.step(steps_per_row);
    path.advance(world, cell);
    const double tau = world.wall(cell.top).force.x() / cell.area, sigma_v = world.wall(cell.top).normal_stress();
    table.add_row({path.strain(), tau, sigma_v, tau / sigma_v, cell.plate_gap(world)});
    std::printf("%10.2f %10.2f %12.2f %8.3f\n", 100 * path.strain(), tau / 1e3, sigma_v / 1e3, tau / sigma_v);
  }
  lab::stop_shear(world, cell);
  table.save(csv);
  std::printf("wrote %s (%lld steps)\n", csv.c_str(), static_cast<long long>(world.step_count()));
}
