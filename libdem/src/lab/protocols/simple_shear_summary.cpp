// summary.json of the simple-shear test: the specimen, the ASTM D6528 ratios, peak and final
// values, the uniformity from 20 to 40 % strain, timing, and the keys a resume changed.
#include <dem/lab/protocols/simple_shear.hpp>

#include <dem/lab/toolkit/uniformity_probe.hpp>

#include "../../io/json_file.hpp"
#include "../toolkit/run_summary.hpp"

namespace dem::lab {

void SimpleShearTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  const double d_max = config_.grading.largest();
  j["balls"] = ball_count();
  j["porosity_generated"] = generated_porosity();
  j["d_min_m"] = config_.grading.smallest();
  j["d_max_m"] = d_max;
  j["height_m"] = config_.specimen.height;
  j["consolidated_height_m"] = consolidated_height();
  j["diameter_m"] = config_.specimen.diameter;
  const double h_over_d = config_.specimen.height / d_max, d_over_h = config_.specimen.diameter / config_.specimen.height;
  j["H_over_dmax"] = h_over_d;
  j["D_over_H"] = d_over_h;
  j["astm_d6528_H_over_dmax_above_10"] = h_over_d > 10.0;
  j["astm_d6528_D_over_H_above_2_5"] = d_over_h > 2.5;
  if (stage() >= ShearStage::Consolidated) {
    j["shear_rate_per_s"] = shear_rate();
    j["inertial_number"] = inertial_number();
  }
  // Peak and final values from the history.
  const HistoryLog& history = outputs_.history();
  const auto& rows = history.table().rows();
  auto col = [&](const std::string& name) { return history.table().column_index(name); };
  if (!rows.empty()) {
    std::size_t peak = 0;
    double peak_ratio = -1;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double ratio = rows[r][col("vertical_stress")] > 0 ? rows[r][col("shear_stress")] / rows[r][col("vertical_stress")] : 0;
      if (ratio > peak_ratio) peak_ratio = ratio, peak = r;
    }
    io::Json p;
    p["shear_stress_Pa"] = rows[peak][col("shear_stress")];
    p["stress_ratio"] = peak_ratio;
    p["shear_strain"] = rows[peak][col("shear_strain")];
    p["volumetric_strain"] = rows[peak][col("volumetric_strain")];
    j["peak"] = p;
    io::Json f;
    const auto& last = rows.back();
    for (const char* name : {"shear_strain", "shear_stress", "vertical_stress", "volumetric_strain", "sigma_1", "sigma_2",
                             "sigma_3", "principal_rotation_deg", "contacts", "mean_contact_force", "coordination_number", "k0",
                             "rose_count_asymmetry", "rose_force_asymmetry", "rose_count_tilt_deg", "rose_force_tilt_deg",
                             "layer_stress_spread"})
      f[name] = last[col(name)];
    j["final"] = f;
    io::Json c;
    const auto& first = rows.front();
    for (const char* name : {"vertical_stress", "lateral_stress", "k0", "contacts", "mean_contact_force", "porosity",
                             "coordination_number", "sigma_1", "sigma_3", "rose_count_asymmetry", "rose_force_asymmetry",
                             "rose_count_tilt_deg", "rose_force_tilt_deg", "layer_stress_spread"})
      c[name] = first[col(name)];
    j["after_consolidation"] = c;
  }
  for (const auto& [name, state] : {std::pair{"specimen_generated", &generated_state()}, std::pair{"specimen_consolidated", &consolidated_state()}}) {
    if (stage() < (state == &generated_state() ? ShearStage::Generated : ShearStage::Consolidated)) continue;
    io::Json g;
    g["porosity"] = state->porosity;
    g["sphere_porosity"] = state->sphere_porosity;
    g["coordination_number"] = state->coordination_number;
    g["mechanical_coordination_number"] = state->mechanical_coordination_number;
    g["vertical_stress_Pa"] = state->vertical_stress;
    g["k0"] = state->k0;
    g["height_m"] = state->height;
    g["ball_ball_friction"] = state->friction;
    g["ball_ball_rolling_friction"] = state->rolling_friction;
    j[name] = g;
  }
  // Uniformity of the profile summed over the rows from 20 to 40 % strain (the span of the study's
  // Fig. 7), against uniform simple shear with the top held (docs/model.md 8.1).
  if (!rows.empty() && consolidated_height() > 0) {
    const SpanUniformity span = span_uniformity(history.table(), config_.measure.profile_bins, 0.2, 0.4,
                                                config_.output.every_strain, horizontal_direction(legs_.legs().back().direction_deg));
    if (span.found) {
      io::Json u;
      u["from_shear_strain"] = span.from_strain;
      u["to_shear_strain"] = span.to_strain;
      u["profile_r2"] = span.uniformity.r_squared;
      u["strain_bottom_third"] = span.uniformity.bottom_third_strain;
      u["strain_middle_third"] = span.uniformity.middle_third_strain;
      u["strain_top_third"] = span.uniformity.top_third_strain;
      u["top_bottom_strain_ratio"] = span.uniformity.top_bottom_strain_ratio;
      u["every_bin_has_balls"] = span.every_bin_has_balls;
      j["uniformity"] = u;
    }
  }
  save_summary(run_, j, resolved_config_json, run_.wall_seconds());
  if (h_over_d <= 10.0)
    run_.log() << "warning: H/d_max = " << h_over_d << " is not above 10 (ASTM D6528 as quoted by the study)\n";
  if (d_over_h <= 2.5) run_.log() << "warning: D/H = " << d_over_h << " is not above 2.5 (ASTM D6528)\n";
}

}  // namespace dem::lab
