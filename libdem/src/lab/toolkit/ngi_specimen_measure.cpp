// What NgiSpecimen measures of its cell: the plates' strains and stresses, the rings' push, the
// measurement sphere at mid-height and the principal stress rotation (docs/model.md 6, 8).
#include <cmath>

#include <dem/lab/toolkit/ngi_specimen.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>
#include <dem/lab/toolkit/specimen_guards.hpp>

namespace dem::lab {

ShearState NgiSpecimen::measure(const Vec3& direction) const {
  const World& w = world_;
  const Wall& top = w.wall(cell_.top);
  const Wall& bottom = w.wall(cell_.bottom);
  ShearState s;
  s.time = w.time();
  s.height = cell_.plate_gap(w);
  const double reference = consolidated_height_ > 0 ? consolidated_height_ : s.height;
  const Vec3 relative = plate_offset(w, cell_);
  s.shear_strain_x = relative.x() / reference;
  s.shear_strain_y = relative.y() / reference;
  s.shear_strain = relative.norm() / reference;
  // The sand, dragged along the shear by the bottom plate, pushes the top plate the same way.
  s.shear_stress_x = top.force.x() / cell_.area;
  s.shear_stress_y = top.force.y() / cell_.area;
  s.shear_stress = std::hypot(s.shear_stress_x, s.shear_stress_y);
  const Vec3 along = s.shear_stress > 0 ? Vec3(Vec3(s.shear_stress_x, s.shear_stress_y, 0) / s.shear_stress) : Vec3(Vec3::UnitX());
  s.shear_stress_bottom = -bottom.force.dot(along) / cell_.area;
  s.vertical_stress = top.normal_stress();
  s.vertical_stress_bottom = bottom.normal_stress();
  const double dilation = consolidated_height_ > 0 ? (s.height - consolidated_height_) / consolidated_height_ : 0.0;
  s.volumetric_strain = (config_.output.volumetric_strain_sign == VolumeSign::DilationPositive) ? dilation : -dilation;

  s.lateral_stress = ring_lateral_stress(w, cell_);
  double mean_force = 0.0;
  std::size_t contacts = 0;
  w.for_each_contact([&](const ContactView& c) {
    if (c.kind != ContactKind::BallBall) return;
    mean_force += c.normal_force;
    ++contacts;
  });
  s.contacts = contacts;
  s.mean_contact_force = contacts > 0 ? mean_force / static_cast<double>(contacts) : 0.0;
  s.kinetic_energy = w.kinetic_energy();
  s.specimen_porosity = specimen_porosity(w, cell_);
  s.balls_outside = balls_outside(w, cell_);

  // The probe sits at mid-height and follows the specimen's mean horizontal displacement.
  MeasurementSphere sphere;
  sphere.centre = 0.5 * (bottom.displacement + top.displacement);
  sphere.centre.z() = bottom.displacement.z() + 0.5 * s.height;
  sphere.radius = config_.measure.sphere_radius_ratio * 0.5 * s.height;
  s.sphere = dem::measure::measure(w, sphere);
  const Vec3& d = direction;
  const Mat3 compression = -s.sphere.stress;
  const double s_dd = d.dot(compression * d), s_dz = d.dot(compression * Vec3::UnitZ());
  const double s_zz = compression(2, 2);
  // Angle of the major compression from vertical towards +d (docs/model.md 6.3); with the bottom
  // moving along +d it tilts towards +d, so it grows positive with shear.
  s.principal_rotation_deg = 0.5 * std::atan2(2 * s_dz, s_zz - s_dd) * 180.0 / pi;
  return s;
}

SpecimenState NgiSpecimen::state() const {
  const ShearState s = measure(Vec3::UnitX());
  SpecimenState out;
  out.porosity = s.specimen_porosity;
  out.sphere_porosity = s.sphere.porosity;
  out.coordination_number = s.sphere.coordination_number;
  out.mechanical_coordination_number = s.sphere.mechanical_coordination_number;
  out.vertical_stress = s.vertical_stress;
  out.k0 = s.vertical_stress > 0 ? s.lateral_stress / s.vertical_stress : 0.0;
  out.height = s.height;
  out.friction = friction_now_;
  out.rolling_friction = rolling_friction_now_;
  return out;
}

}  // namespace dem::lab
