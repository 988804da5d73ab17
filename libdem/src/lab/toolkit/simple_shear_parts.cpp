#include <dem/lab/toolkit/simple_shear_parts.hpp>

#include <algorithm>
#include <cmath>

namespace dem::lab {

WorldSettings world_settings(const EngineConfig& engine) {
  WorldSettings s;
  s.local_damping = engine.local_damping;
  s.time_step = engine.time_step;
  s.time_step_safety = engine.time_step_safety;
  s.max_overlap_ratio = engine.max_overlap_ratio;
  s.threads = engine.threads;
  s.adapt_threads = engine.adapt_threads;
  return s;
}

ShearCellSpec shear_cell_spec(const SimpleShearConfig& config) {
  ShearCellSpec cell;
  cell.diameter = config.specimen.diameter;
  cell.height = config.specimen.height;
  cell.pebble_diameter = config.rings.pebble_diameter > 0 ? config.rings.pebble_diameter : config.grading.smallest();
  cell.ring_gap = config.rings.gap > 0 ? config.rings.gap : 0.05 * cell.pebble_diameter;
  cell.ring_density = config.rings.density;
  cell.stack_height = config.rings.stack_height > 0                  ? config.rings.stack_height
                      : config.rings.vertical == RingVertical::Fixed ? 1.1 * cell.height
                                                                     : cell.height;
  cell.max_opening = config.grading.smallest();
  cell.rings = config.rings.vertical;
  return cell;
}

void set_contact_laws(World& world, const SimpleShearConfig& config, double friction, double rolling_friction,
                      bool growing, ModelChange change) {
  auto set = [&](ContactKind kind, std::shared_ptr<const ContactModel> model) {
    if (change == ModelChange::KeepContacts)
      world.retune_contact_model(kind, std::move(model));
    else
      world.set_contact_model(kind, std::move(model));
  };
  set(ContactKind::BallBall, config.ball_ball.model_with_friction(friction, rolling_friction, "ball_ball"));
  // The plates and rings are frictionless while the radii grow, so that the expansion packs the specimen.
  auto boundary = [&](const ContactTypeConfig& c, const char* where) {
    return growing ? c.model_with_friction(0.0, 0.0, where) : c.model(where);
  };
  set(ContactKind::BallFacet, boundary(config.ball_facet, "ball_facet"));
  set(ContactKind::BallPebble, boundary(config.ball_pebble, "ball_pebble"));
}

std::vector<double> specimen_diameters(const SimpleShearConfig& config, std::mt19937_64& rng) {
  const double radius = config.specimen.diameter / 2;
  return sample_diameters(config.grading,
                          (1.0 - config.specimen.porosity) * pi * radius * radius * config.specimen.height, rng);
}

ServoSettings consolidation_servo(const SimpleShearConfig& config) {
  ServoSettings servo;
  servo.target_stress = config.consolidation.vertical_stress;
  servo.relaxation = config.consolidation.servo_relaxation;
  servo.max_speed = config.consolidation.servo_max_speed;
  servo.settle_tolerance = config.consolidation.tolerance;
  servo.settle_steps = static_cast<int>(config.consolidation.settle_steps);
  return servo;
}

ServoSettings generation_servo(const SimpleShearConfig& config) {
  ServoSettings servo = consolidation_servo(config);
  servo.target_stress = config.generation.stress;
  servo.max_speed = config.generation.servo_max_speed;
  return servo;
}

FrictionSchedule generation_friction_schedule(const SimpleShearConfig& config) {
  FrictionSchedule schedule;
  schedule.target_porosity = config.specimen.porosity;
  schedule.porosity_tolerance = config.generation.porosity_tolerance;
  schedule.reduction = config.generation.friction_reduction;
  schedule.floor = 1e-2 * std::max(config.generation_friction(), config.generation_rolling_friction());
  return schedule;
}

ConsolidationTarget consolidation_target(const SimpleShearConfig& config, std::int64_t chunk_steps) {
  ConsolidationTarget target;
  target.vertical_stress = config.consolidation.vertical_stress;
  target.servo_max_speed = config.consolidation.servo_max_speed;
  target.equilibrium_ratio = config.generation.equilibrium_ratio;
  target.max_steps = config.consolidation.max_steps;
  target.chunk_steps = chunk_steps;
  return target;
}

double mean_ball_diameter(const World& world, double fallback) {
  const ParticleStore& p = world.particles();
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) sum += 2 * p.radius[i], ++n;
  return n > 0 ? sum / static_cast<double>(n) : fallback;
}

double shear_strain_rate(const SimpleShearConfig& config, const World& world) {
  if (config.shear.strain_rate > 0.0) return config.shear.strain_rate;
  const double d_mean = mean_ball_diameter(world, config.grading.largest());
  return config.shear.inertial_number /
         (d_mean * std::sqrt(config.specimen.density / config.consolidation.vertical_stress));
}

double shear_servo_speed(const SimpleShearConfig& config, double rate, double height) {
  if (config.shear.servo_max_speed > 0.0) return config.shear.servo_max_speed;
  return std::max(config.consolidation.servo_max_speed, rate * height);
}

ShearLegMotion shear_leg_motion(const SimpleShearConfig& config, double direction_deg, double rate, double height) {
  ShearLegMotion motion;
  motion.direction_deg = direction_deg;
  motion.speed = rate * height;  // m/s of the bottom plate relative to the top
  motion.mode = config.shear.mode;
  motion.moving_plate = config.shear.moving_plate;
  motion.servo_max_speed = shear_servo_speed(config, rate, height);
  return motion;
}

DampingFrame shear_damping_frame(const SimpleShearConfig& config, const World& world, const ShearCell& cell) {
  return config.shear.damping_frame == ShearDampingFrame::Plates ? plate_damping_frame(world, cell) : DampingFrame{};
}

}  // namespace dem::lab
