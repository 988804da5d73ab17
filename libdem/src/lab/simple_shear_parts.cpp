#include <dem/lab/simple_shear_parts.hpp>

namespace dem::lab {

WorldSettings world_settings(const SimpleShearConfig& config) {
  WorldSettings s;
  s.local_damping = config.engine.local_damping;
  s.time_step = config.engine.time_step;
  s.time_step_safety = config.engine.time_step_safety;
  s.max_overlap_ratio = config.engine.max_overlap_ratio;
  s.threads = config.engine.threads;
  return s;
}

ShearCellSpec shear_cell_spec(const SimpleShearConfig& config) {
  ShearCellSpec cell;
  cell.diameter = config.specimen.diameter;
  cell.height = config.specimen.height;
  cell.pebble_diameter = config.rings.pebble_diameter > 0 ? config.rings.pebble_diameter : config.grading.smallest();
  cell.ring_gap = config.rings.gap > 0 ? config.rings.gap : 0.05 * cell.pebble_diameter;
  cell.ring_density = config.rings.density;
  cell.stack_height = config.rings.stack_height > 0 ? config.rings.stack_height
                      : config.rings.vertical == RingVertical::Fixed ? 1.1 * cell.height : cell.height;
  cell.max_opening = config.grading.smallest();
  cell.rings = config.rings.vertical;
  return cell;
}

RollingLinearLaw::Params contact_law(const ContactTypeConfig& c, double friction, double rolling_friction) {
  auto p = RollingLinearLaw::Params::deformable(c.effective_modulus, c.stiffness_ratio, friction, rolling_friction);
  p.normal_damping_ratio = c.normal_damping_ratio;
  p.shear_damping_ratio = c.shear_damping_ratio;
  return p;
}

void set_contact_laws(World& world, const SimpleShearConfig& config, double friction, double rolling_friction, bool growing,
                      ModelChange change) {
  auto set = [&](ContactKind kind, std::shared_ptr<const ContactModel> model) {
    if (change == ModelChange::KeepContacts) world.retune_contact_model(kind, std::move(model));
    else world.set_contact_model(kind, std::move(model));
  };
  set(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(contact_law(config.ball_ball, friction, rolling_friction), "ball_ball"));
  auto boundary = [&](const ContactTypeConfig& c) {
    return growing ? contact_law(c, 0.0, 0.0) : contact_law(c, c.friction, c.rolling_friction);
  };
  set(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(boundary(config.ball_facet), "ball_facet"));
  set(ContactKind::BallPebble, make_contact_model<RollingLinearLaw>(boundary(config.ball_pebble), "ball_pebble"));
}

std::vector<double> specimen_diameters(const SimpleShearConfig& config, std::mt19937_64& rng) {
  const double radius = config.specimen.diameter / 2;
  return sample_diameters(config.grading, (1.0 - config.specimen.porosity) * pi * radius * radius * config.specimen.height, rng);
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

}  // namespace dem::lab
