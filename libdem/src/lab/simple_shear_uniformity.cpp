// The measures that show whether the specimen shears uniformly (docs/model.md 8.1): the horizontal
// displacement profile over each output interval, its R^2 against uniform simple shear and the
// strains of the thirds; the porosity of the same height bins; three layer spheres;
// non-coaxiality; contacts within a detection gap; each ring's displacement.
#include <algorithm>
#include <cmath>
#include <limits>

#include <dem/core/errors.hpp>
#include <dem/lab/simple_shear.hpp>
#include <dem/measure/shear_uniformity.hpp>

namespace dem::lab {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// tau_dz / sigma_zz of a compression-positive stress, NaN if the sphere held no ball.
struct Layer {
  double stress_ratio = nan, porosity = nan;
};

Layer layer_at(const World& w, const Vec3& centre, double radius, const Vec3& d) {
  MeasurementSphere sphere{centre, radius};
  const ParticleStore& p = w.particles();
  bool any = false;
  for (std::size_t i = 0; i < p.size() && !any; ++i)
    any = !p.is_pebble(i) && (p.x[i] - centre).squaredNorm() < radius * radius;
  if (!any) return {};  // a 4D specimen has few balls per layer: a missing value, not an error
  const SphereMeasurement m = dem::measure::measure(w, sphere);
  const Mat3 c = -m.stress;
  return {c(2, 2) != 0.0 ? d.dot(c * Vec3::UnitZ()) / c(2, 2) : nan, m.porosity};
}

}  // namespace

std::vector<double> SimpleShearTest::uniformity_columns(const ShearState& s) {
  const World& w = *world_;
  const FacetWall& top = w.wall(cell_.top);
  const FacetWall& bottom = w.wall(cell_.bottom);
  const Vec3 d = leg_direction(std::min(leg_, legs_.size() - 1));
  const ParticleStore& p = w.particles();
  std::vector<double> out;

  // Contacts two ways: active (F_n > 0: ShearState::contacts) and within the detection gap.
  const double detection = config_.measure.detection_gap_ratio * config_.grading.smallest();
  const PairContacts& pairs = w.pair_contacts(ContactKind::BallBall);
  std::size_t detected = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto i = static_cast<std::size_t>(pairs.first[k]), j = static_cast<std::size_t>(pairs.second[k]);
    if ((p.x[j] - p.x[i]).norm() - p.radius[i] - p.radius[j] < detection) ++detected;
  }
  const Mat3 stress = -s.sphere.stress, strain_rate = -s.sphere.strain_rate;  // compression positive
  const double rate_direction = measure::major_direction_deg(d.dot(strain_rate * d), strain_rate(2, 2),
                                                             d.dot(strain_rate * Vec3::UnitZ()));
  out.insert(out.end(), {s.specimen_porosity, static_cast<double>(s.balls_outside), static_cast<double>(detected),
                         s.sphere.mechanical_coordination_number, rate_direction,
                         measure::non_coaxiality_deg(stress, strain_rate, d)});

  // The profile of the displacement along d since the last row, by the balls' mid-interval height.
  const double z_bottom = bottom.displacement.z(), z_top = config_.specimen.height + top.displacement.z();
  std::vector<double> z, u;
  const bool have_reference = !profile_reference_.empty();
  if (have_reference) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.is_pebble(i)) continue;
      const Vec3& x0 = profile_reference_[static_cast<std::size_t>(p.id[i])];
      z.push_back(0.5 * (x0.z() + p.x[i].z()));
      u.push_back((p.x[i] - x0).dot(d));
    }
  }
  const double u_bottom = (bottom.displacement - profile_bottom_).dot(d), u_top = (top.displacement - profile_top_).dot(d);
  measure::ShearUniformity uniformity{nan, nan, nan, nan, nan};
  std::vector<double> bins(static_cast<std::size_t>(config_.measure.profile_bins), nan);
  if (have_reference && u_bottom != u_top) {  // the first row, and a pause, have no profile
    const measure::DisplacementProfile profile = measure::displacement_profile(z, u, z_bottom, z_top, config_.measure.profile_bins);
    uniformity = measure::shear_uniformity(profile, z_bottom, z_top, u_bottom, u_top);
    bins = profile.mean_displacement;
  }
  out.insert(out.end(), {uniformity.r_squared, uniformity.bottom_third_strain, uniformity.middle_third_strain,
                         uniformity.top_third_strain, uniformity.top_bottom_strain_ratio, bottom.displacement.x(),
                         bottom.displacement.y(), top.displacement.x(), top.displacement.y()});
  // Layers: three spheres filling the thirds, each at the uniform-shear position of its centre.
  for (int third = 0; third < 3; ++third) {
    const double fraction = (2 * third + 1) / 6.0;
    Vec3 centre = bottom.displacement + fraction * (top.displacement - bottom.displacement);
    centre.z() = z_bottom + fraction * (z_top - z_bottom);
    const Layer layer = layer_at(w, centre, (z_top - z_bottom) / 6, d);
    out.insert(out.end(), {layer.stress_ratio, layer.porosity});
  }
  out.insert(out.end(), bins.begin(), bins.end());
  // The porosity of the same height bins, now: where the specimen is looser or dilates.
  std::vector<double> z_now, r_now;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) z_now.push_back(p.x[i].z()), r_now.push_back(p.radius[i]);
  const std::vector<double> porosity = measure::porosity_profile(z_now, r_now, z_bottom, z_top, cell_.area, config_.measure.profile_bins);
  out.insert(out.end(), porosity.begin(), porosity.end());
  for (const Clump& ring : w.clumps()) out.insert(out.end(), {ring.displacement.x(), ring.displacement.y()});

  // This row starts the next interval.
  profile_reference_.assign(p.id.empty() ? 0 : static_cast<std::size_t>(*std::max_element(p.id.begin(), p.id.end())) + 1,
                            Vec3::Constant(nan));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) profile_reference_[static_cast<std::size_t>(p.id[i])] = p.x[i];
  profile_bottom_ = bottom.displacement;
  profile_top_ = top.displacement;
  return out;
}

}  // namespace dem::lab
