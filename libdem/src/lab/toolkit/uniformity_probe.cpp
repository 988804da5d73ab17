#include <dem/lab/toolkit/uniformity_probe.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/measure/measurement_sphere.hpp>

namespace dem::lab {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// tau_dz / sigma_zz of a compression-positive stress, NaN if the sphere held no ball.
struct Layer {
  double stress_ratio = nan, porosity = nan, vertical_stress = nan;  // -, -, Pa
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
  return {c(2, 2) != 0.0 ? d.dot(c * Vec3::UnitZ()) / c(2, 2) : nan, m.porosity, c(2, 2)};
}

std::vector<std::string> probe_columns(int bins) {
  std::vector<std::string> c = {"profile_r2",
                                "strain_bottom_third",
                                "strain_middle_third",
                                "strain_top_third",
                                "top_bottom_strain_ratio",
                                "bottom_dx",
                                "bottom_dy",
                                "top_dx",
                                "top_dy"};
  for (const char* layer : {"bottom", "middle", "top"})
    for (const char* what : {"stress_ratio", "porosity"}) c.push_back(std::string("layer_") + layer + "_" + what);
  c.push_back("layer_stress_spread");
  for (int b = 0; b < bins; ++b) c.push_back("profile_u_" + std::to_string(b + 1));
  for (int b = 0; b < bins; ++b) c.push_back("profile_porosity_" + std::to_string(b + 1));
  return c;
}

}  // namespace

UniformityProbe::UniformityProbe(const World& world, const ShearCell& cell, int bins)
    : world_(world), cell_(cell), bins_(bins) {
  require(bins >= 3, "profile bins", bins, ">= 3");
}

void UniformityProbe::add_columns(HistoryLog& log, std::function<Vec3()> direction) {
  log.add(probe_columns(bins_),
          [this, direction = std::move(direction)](std::vector<double>& row) { measure(direction(), row); });
}

void UniformityProbe::measure(const Vec3& d, std::vector<double>& out) {
  const World& w = world_;
  const Wall& top = w.wall(cell_.top);
  const Wall& bottom = w.wall(cell_.bottom);
  const ParticleStore& p = w.particles();

  // The profile of the displacement along d since the last row, by the balls' mid-interval height.
  const double z_bottom = bottom.displacement.z(), z_top = cell_.built_height + top.displacement.z();
  std::vector<double> z, u;
  const bool have_reference = !interval_.positions.empty();
  if (have_reference) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.is_pebble(i)) continue;
      const Vec3& x0 = interval_.positions[static_cast<std::size_t>(p.id[i])];
      z.push_back(0.5 * (x0.z() + p.x[i].z()));
      u.push_back((p.x[i] - x0).dot(d));
    }
  }
  const double u_bottom = (bottom.displacement - interval_.bottom).dot(d),
               u_top = (top.displacement - interval_.top).dot(d);
  measure::ShearUniformity uniformity{nan, nan, nan, nan, nan};
  std::vector<double> bins(static_cast<std::size_t>(bins_), nan);
  if (have_reference && u_bottom != u_top) {  // the first row, and a pause, have no profile
    const measure::DisplacementProfile profile = measure::displacement_profile(z, u, z_bottom, z_top, bins_);
    uniformity = measure::shear_uniformity(profile, z_bottom, z_top, u_bottom, u_top);
    bins = profile.mean_displacement;
  }
  out.insert(out.end(), {uniformity.r_squared, uniformity.bottom_third_strain, uniformity.middle_third_strain,
                         uniformity.top_third_strain, uniformity.top_bottom_strain_ratio, bottom.displacement.x(),
                         bottom.displacement.y(), top.displacement.x(), top.displacement.y()});
  // Layers: three spheres filling the thirds, each at the uniform-shear position of its centre.
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest, sum = 0.0;
  for (int third = 0; third < 3; ++third) {
    const double fraction = (2 * third + 1) / 6.0;
    Vec3 centre = bottom.displacement + fraction * (top.displacement - bottom.displacement);
    centre.z() = z_bottom + fraction * (z_top - z_bottom);
    const Layer layer = layer_at(w, centre, (z_top - z_bottom) / 6, d);
    out.insert(out.end(), {layer.stress_ratio, layer.porosity});
    lowest = std::min(lowest, layer.vertical_stress), highest = std::max(highest, layer.vertical_stress);
    sum += layer.vertical_stress;
  }
  // The stress-concentration index: how far the layers' vertical stresses spread, (max - min) / mean
  // (NaN when a layer holds no ball: its NaN stress makes the sum NaN).
  out.push_back(std::isnan(sum) || sum <= 0.0 ? nan : 3.0 * (highest - lowest) / sum);
  out.insert(out.end(), bins.begin(), bins.end());
  // The porosity of the same height bins, now: where the specimen is looser or dilates.
  std::vector<double> z_now, r_now;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) z_now.push_back(p.x[i].z()), r_now.push_back(p.radius[i]);
  const std::vector<double> porosity = measure::porosity_profile(z_now, r_now, z_bottom, z_top, cell_.area, bins_);
  out.insert(out.end(), porosity.begin(), porosity.end());

  // This row starts the next interval.
  interval_.positions.assign(
      p.id.empty() ? 0 : static_cast<std::size_t>(*std::max_element(p.id.begin(), p.id.end())) + 1,
      Vec3::Constant(nan));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) interval_.positions[static_cast<std::size_t>(p.id[i])] = p.x[i];
  interval_.bottom = bottom.displacement;
  interval_.top = top.displacement;
}

SpanUniformity span_uniformity(const io::CsvTable& history, int bins, double from, double to, double every_strain,
                               const Vec3& direction) {
  SpanUniformity span;
  const auto& rows = history.rows();
  auto col = [&](const std::string& name) { return history.column_index(name); };
  std::vector<double> summed(static_cast<std::size_t>(bins), 0.0);
  double strain_from = -1, strain_to = -1;
  std::size_t first_row = 0, last_row = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const double strain = rows[r][col("shear_strain")];
    // Rows fall a little past their nominal strains: half an interval of slack on both ends.
    const double slack = 0.5 * every_strain;
    if (strain <= from + slack || strain > to + slack) continue;
    if (strain_from < 0) strain_from = rows[r - 1][col("shear_strain")], first_row = r;
    strain_to = strain;
    last_row = r;
    for (int b = 0; b < bins; ++b) {
      const double u = rows[r][col("profile_u_" + std::to_string(b + 1))];
      if (std::isnan(u)) span.every_bin_has_balls = false;
      summed[static_cast<std::size_t>(b)] += u;
    }
  }
  if (!(strain_to > strain_from && strain_from >= 0)) return span;
  measure::DisplacementProfile profile;
  const double height = rows.back()[col("height")];
  for (int b = 0; b < bins; ++b) {
    const double z = (b + 0.5) * height / bins;
    profile.z_centre.push_back(z);
    profile.z_mean.push_back(z);
    const double u = summed[static_cast<std::size_t>(b)];
    profile.mean_displacement.push_back(u);  // NaN where a bin had no ball at some row
    profile.count.push_back(std::isnan(u) ? 0 : 1);
  }
  // The plates' displacements along the direction over the span (the top moves too with
  // shear.moving_plate = both).
  auto plate = [&](std::size_t r, const char* x, const char* y) {
    return Vec3(rows[r][col(x)], rows[r][col(y)], 0.0).dot(direction);
  };
  const double u_bottom = plate(last_row, "bottom_dx", "bottom_dy") - plate(first_row - 1, "bottom_dx", "bottom_dy");
  const double u_top = plate(last_row, "top_dx", "top_dy") - plate(first_row - 1, "top_dx", "top_dy");
  span.found = true;
  span.from_strain = strain_from;
  span.to_strain = strain_to;
  span.uniformity = measure::shear_uniformity(profile, 0.0, height, u_bottom, u_top);
  return span;
}

}  // namespace dem::lab
