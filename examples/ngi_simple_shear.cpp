// The NGI-type simple-shear test of the study as a script over the lab toolkit, read top to bottom
// as its method: a cylinder of spheres grown by radius expansion inside a stack of clump rings
// between two facet plates, the friction lowered to the target porosity, consolidation by the
// servo-controlled top plate, then shear by the bottom plate while the top plate holds the
// vertical stress, with a history row at every output strain.
//
// The keys are dem-simple-shear's (a preset, then section.key=value), and the script makes the
// same specimen and the same shear as the app does without restarts: every column of its
// history.csv is the app's column of that name, to the last bit (tests/python/test_examples.py).
// It covers the app's default generation (generation.plate = servo).
//
// Usage: ngi_simple_shear [preset] [out folder] [section.key=value ...]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>

#include <dem/dem.hpp>
#include <dem/lab/consolidation.hpp>
#include <dem/lab/friction_schedule.hpp>
#include <dem/lab/history_log.hpp>
#include <dem/lab/radius_expansion.hpp>
#include <dem/lab/shear_leg.hpp>
#include <dem/lab/simple_shear_parts.hpp>
#include <dem/lab/uniformity_probe.hpp>

int main(int argc, char** argv) try {
  using namespace dem;
  io::Config keys(lab::simple_shear_schema());
  for (const auto& [key, value] : lab::preset_values(argc > 1 ? argv[1] : "4D")) keys.set(key, value);
  for (int a = 3; a < argc; ++a) keys.set(argv[a]);
  const lab::SimpleShearConfig c = lab::simple_shear_config(keys);
  const std::filesystem::path out = argc > 2 ? argv[2] : "ngi_simple_shear";
  std::filesystem::create_directories(out);

  // The device: plates and rings, contacts per type (Table 1), one controller every step.
  World world(lab::world_settings(c));
  const lab::ShearCell cell = lab::build_shear_cell(world, lab::shear_cell_spec(c));
  std::unique_ptr<ServoWall> servo;
  bool growing = true, specimen_made = false, shearing = false;
  world.add_controller([&](World& w) {
    if (servo) (*servo)(w);
    if (growing) lab::keep_plate_gap(w, cell, c.specimen.height);  // the radii grow in the cavity
    lab::move_rings(w, cell, specimen_made);
    if (shearing) w.set_damping_frame(lab::shear_damping_frame(c, w, cell));  // docs/model.md 3.1
  });
  // Generation: balls at half size, grown in stages against a low servo stress with the generation
  // friction (plates and rings frictionless), each stage cycled towards equilibrium.
  std::mt19937_64 rng(c.specimen.seed);
  const std::vector<double> diameters = lab::specimen_diameters(c, rng);
  const lab::RadiusExpansion expansion = lab::add_expanding_balls(world, {cell.radius, c.specimen.height}, diameters,
                                                                  c.specimen.density, c.generation.stages, rng);
  lab::Friction friction{c.generation_friction(), c.generation_rolling_friction()};
  lab::set_contact_laws(world, c, friction.sliding, friction.rolling, true);
  servo = std::make_unique<ServoWall>(cell.top, lab::generation_servo(c));
  const auto settle = [&](const std::function<bool()>& settled) {
    for (long steps = 0; steps < c.generation.steps_per_stage; steps += 100) {
      world.step(100);
      if (settled()) break;
    }
  };
  const auto balanced = [&] { return world.unbalanced_force_ratio() < c.generation.equilibrium_ratio; };
  for (int stage = 1; stage <= expansion.stages; ++stage) {
    for (int increment = 1; increment <= expansion.increments; ++increment) {
      lab::set_radii(world, expansion, expansion.factor(stage, increment));
      world.step(expansion.steps_per_increment);
    }
    settle(balanced);
  }
  // Then the friction is halved step by step until the porosity is the target's (docs/model.md 7.1).
  const auto on_stress = [&] {
    return balanced() && std::abs(servo->achieved_stress() - c.generation.stress) <= 0.1 * c.generation.stress;
  };
  settle(on_stress);
  const lab::FrictionSchedule schedule = lab::generation_friction_schedule(c);
  while (const std::optional<lab::Friction> next =
             lab::next_friction(schedule, lab::specimen_porosity(world, cell), friction)) {
    friction = *next;
    lab::set_contact_laws(world, c, friction.sliding, friction.rolling, true);
    settle(on_stress);
  }
  growing = false, specimen_made = true;
  lab::release_rings(world, cell);
  lab::set_contact_laws(world, c, c.ball_ball.friction(), c.ball_ball.rolling_friction(), false);
  std::printf("generated %zu balls in %lld steps, porosity %.4f\n", diameters.size(),
              static_cast<long long>(world.step_count()), lab::specimen_porosity(world, cell));

  // Consolidation: the servo brings the top plate to the vertical stress until it has settled.
  const lab::ConsolidationTarget target = lab::consolidation_target(c, 10);
  lab::start_consolidation(*servo, target);
  const lab::ConsolidationReport report = lab::consolidate(world, *servo, target, world.step_count());
  const double height = cell.plate_gap(world);  // m, H_c
  std::printf("consolidated to %.1f kPa (%s), H_c = %.3f mm\n", report.stress / 1e3,
              report.settled ? "settled" : "not settled", height * 1e3);

  // The history: the plates' stresses and strain, the uniformity probe's columns, the rings.
  const std::vector<lab::ShearLeg> legs = c.shear.legs();
  std::size_t leg = 0;
  const auto direction = [&] { return lab::horizontal_direction(legs[std::min(leg, legs.size() - 1)].direction_deg); };
  lab::HistoryLog history(out / "history.csv");
  history.add("time", [&] { return world.time(); });
  history.add("shear_strain", [&] { return lab::plate_offset(world, cell).norm() / height; });
  history.add("shear_stress", [&] {
    return std::hypot(world.wall(cell.top).force.x() / cell.area, world.wall(cell.top).force.y() / cell.area);
  });
  history.add("vertical_stress", [&] { return world.wall(cell.top).normal_stress(); });
  history.add("height", [&] { return cell.plate_gap(world); });
  history.add("lateral_stress", [&] { return lab::ring_lateral_stress(world, cell); });
  lab::UniformityProbe uniformity(world, cell, c.measure.profile_bins);
  uniformity.add_columns(history, direction);
  lab::add_ring_columns(history, world, cell);
  history.record();

  // Shear at the inertial number of the keys (docs/model.md 3.4), leg after leg.
  const double rate = lab::shear_strain_rate(c, world);  // 1/s
  const auto start_leg = [&] {
    lab::start_shear_leg(world, cell, *servo, lab::shear_leg_motion(c, legs[leg].direction_deg, rate, height));
  };
  lab::ShearPath path(world, cell, height);
  double leg_start = 0.0, next_row = c.output.every_strain;
  start_leg();
  shearing = true;
  while (leg < legs.size()) {
    world.step(10);
    path.advance(world, cell);
    if (path.strain() - leg_start >= legs[leg].strain * (1 - 1e-12)) {
      leg_start += legs[leg++].strain;
      if (leg < legs.size()) start_leg();
    }
    if (leg == legs.size() || path.strain() >= next_row - 1e-12) {
      history.record();
      while (next_row <= path.strain() + 1e-12) next_row += c.output.every_strain;
      std::printf("strain %.4f  tau %.2f kPa  sigma_v %.2f kPa\n", history.last("shear_strain"),
                  history.last("shear_stress") / 1e3, history.last("vertical_stress") / 1e3);
    }
  }
  lab::stop_shear(world, cell);
  std::printf("wrote %s (%lld steps)\n", (out / "history.csv").string().c_str(),
              static_cast<long long>(world.step_count()));
} catch (const std::exception& e) {
  std::fprintf(stderr, "ngi_simple_shear: %s\n", e.what());
  return 1;
}
