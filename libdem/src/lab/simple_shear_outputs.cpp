// Measurements, outputs and restart files of the simple-shear protocol.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/lab/fabric_log.hpp>
#include <dem/lab/resume_rules.hpp>
#include <dem/lab/simple_shear.hpp>
#include <dem/lab/snapshots.hpp>
#include <dem/measure/shear_uniformity.hpp>

#include "../io/json_file.hpp"

namespace dem::lab {

namespace {

std::string label_for(double strain) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "strain_%04.1f", 100.0 * strain);  // e.g. strain_20.0 (percent)
  std::string s(buf);
  for (char& c : s)
    if (c == ' ') c = '0';
  return s;
}


// The files a run reads back when it resumes from a restart written in another folder:
// history.csv, fabric.csv and snapshots/ (hard links where possible: they are only read, and
// every writer replaces files by renaming, which leaves the originals alone). The resumed run then
// trims them to the restart point, as it does in the restart's own folder.
void copy_run_files(const std::filesystem::path& from, const std::filesystem::path& to) {
  namespace fs = std::filesystem;
  fs::create_directories(to);
  for (const char* name : {"history.csv", "fabric.csv"})
    if (fs::exists(from / name)) fs::copy_file(from / name, to / name, fs::copy_options::overwrite_existing);
  if (!fs::exists(from / "snapshots")) return;
  fs::remove_all(to / "snapshots");
  std::error_code linked;
  fs::copy(from / "snapshots", to / "snapshots", fs::copy_options::recursive | fs::copy_options::create_hard_links, linked);
  if (linked) {
    fs::remove_all(to / "snapshots");
    fs::copy(from / "snapshots", to / "snapshots", fs::copy_options::recursive);
  }
}

// Pairs of the list whose surfaces are closer than `gap` (m): touching, or about to.
std::size_t contacts_within_gap(const World& w, ContactKind kind, double gap) {
  const ParticleStore& p = w.particles();
  const PairContacts& pairs = w.pair_contacts(kind);
  std::size_t n = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto i = static_cast<std::size_t>(pairs.first[k]), j = static_cast<std::size_t>(pairs.second[k]);
    if ((p.x[j] - p.x[i]).norm() - p.radius[i] - p.radius[j] < gap) ++n;
  }
  return n;
}

bool same_folder(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  const bool same = std::filesystem::equivalent(a, b, error);
  return !error && same;
}

}  // namespace

ShearState SimpleShearTest::measure() const {
  const World& w = *world_;
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
  s.balls_outside = balls_outside();

  // The probe sits at mid-height and follows the specimen's mean horizontal displacement.
  MeasurementSphere sphere;
  sphere.centre = 0.5 * (bottom.displacement + top.displacement);
  sphere.centre.z() = bottom.displacement.z() + 0.5 * s.height;
  sphere.radius = config_.measure.sphere_radius_ratio * 0.5 * s.height;
  s.sphere = dem::measure::measure(w, sphere);
  const Vec3 d = (stage_ >= ShearStage::Shearing && leg_ < legs_.size()) ? leg_direction(leg_)
                 : leg_direction(std::min(leg_, legs_.size() - 1));
  const Mat3 compression = -s.sphere.stress;
  const double s_dd = d.dot(compression * d), s_dz = d.dot(compression * Vec3::UnitZ());
  const double s_zz = compression(2, 2);
  // Angle of the major compression from vertical towards +d (docs/model.md 6.3); with the bottom
  // moving along +d it tilts towards +d, so it grows positive with shear.
  s.principal_rotation_deg = 0.5 * std::atan2(2 * s_dz, s_zz - s_dd) * 180.0 / pi;
  return s;
}

SpecimenState SimpleShearTest::specimen_state() const {
  const ShearState s = measure();
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

void SimpleShearTest::add_history_columns() {
  // The state of the row, measured once, read by the columns that follow.
  history_.before_row([this] { row_ = measure(); });
  const ShearState& s = row_;
  auto field = [&](const char* name, const double& value) { history_.add(name, [&value] { return value; }); };
  auto count = [&](const char* name, const std::size_t& value) { history_.add(name, [&value] { return static_cast<double>(value); }); };
  // The current leg's direction in the plane of the shear (the last one's once the path is done).
  auto direction = [this] { return leg_direction(std::min(leg_, legs_.size() - 1)); };
  auto compression = [&s](int i, int j) { return [&s, i, j] { return -s.sphere.stress(i, j); }; };
  field("time", s.time);
  history_.add("step", [this] { return static_cast<double>(world_->step_count()); });
  history_.add("stage", [this] { return static_cast<double>(stage_); });
  field("shear_strain_x", s.shear_strain_x);
  field("shear_strain_y", s.shear_strain_y);
  field("shear_strain", s.shear_strain);
  field("shear_stress_x", s.shear_stress_x);
  field("shear_stress_y", s.shear_stress_y);
  field("shear_stress", s.shear_stress);
  field("shear_stress_bottom", s.shear_stress_bottom);
  field("vertical_stress", s.vertical_stress);
  field("vertical_stress_bottom", s.vertical_stress_bottom);
  field("height", s.height);
  field("volumetric_strain", s.volumetric_strain);
  field("lateral_stress", s.lateral_stress);
  history_.add("k0", [&s] { return s.vertical_stress > 0 ? s.lateral_stress / s.vertical_stress : 0.0; });
  field("sigma_1", s.sphere.principal.sigma_1);
  field("sigma_2", s.sphere.principal.sigma_2);
  field("sigma_3", s.sphere.principal.sigma_3);
  field("principal_rotation_deg", s.principal_rotation_deg);
  history_.add("ms_sxx", compression(0, 0));
  history_.add("ms_syy", compression(1, 1));
  history_.add("ms_szz", compression(2, 2));
  history_.add("ms_sxy", compression(0, 1));
  history_.add("ms_sxz", compression(0, 2));
  history_.add("ms_syz", compression(1, 2));
  history_.add("ms_shear_stress", [&s, direction] {
    const Vec3 d = direction();
    return d.dot(Mat3(-s.sphere.stress) * Vec3::UnitZ());
  });
  field("coordination_number", s.sphere.coordination_number);
  count("contacts", s.contacts);
  field("mean_contact_force", s.mean_contact_force);
  field("porosity", s.sphere.porosity);
  field("kinetic_energy", s.kinetic_energy);
  history_.add("inertial_number", [this] { return stage_ >= ShearStage::Consolidated ? inertial_number() : 0.0; });
  // How uniformly it shears, and the study's non-coaxiality (docs/model.md 8.1).
  field("specimen_porosity", s.specimen_porosity);
  count("balls_outside", s.balls_outside);
  // Contacts two ways: active (F_n > 0: "contacts") and within the detection gap.
  history_.add("contacts_within_detection", [this] {
    return static_cast<double>(
        contacts_within_gap(*world_, ContactKind::BallBall, config_.measure.detection_gap_ratio * config_.grading.smallest()));
  });
  field("mechanical_coordination_number", s.sphere.mechanical_coordination_number);
  history_.add("strain_rate_direction_deg", [&s, direction] {
    const Vec3 d = direction();
    const Mat3 rate = -s.sphere.strain_rate;  // compression positive
    return measure::major_direction_deg(d.dot(rate * d), rate(2, 2), d.dot(rate * Vec3::UnitZ()));
  });
  history_.add("non_coaxiality_deg", [&s, direction] {
    return measure::non_coaxiality_deg(Mat3(-s.sphere.stress), Mat3(-s.sphere.strain_rate), direction());
  });
  uniformity_ = std::make_unique<UniformityProbe>(*world_, cell_, config_.measure.profile_bins);
  uniformity_->add_columns(history_, direction);
  add_ring_columns(history_, *world_, cell_);
}

void SimpleShearTest::record_history() {
  history_.record();
  require_no_escape();  // after the row: it shows the state in which the ball was lost
}

void SimpleShearTest::record_outputs(bool force) {
  const double strain = path_.strain();
  const auto fabric_due = [&] {
    return next_fabric_ < config_.output.fabric_strains.size() && strain >= config_.output.fabric_strains[next_fabric_] - 1e-12;
  };
  const auto snapshot_due = [&] {
    return next_snapshot_ < config_.output.snapshot_strains.size() &&
           strain >= config_.output.snapshot_strains[next_snapshot_] - 1e-12;
  };
  const bool row = force || strain >= next_output_strain_ - 1e-12;
  if (row || fabric_due() || snapshot_due()) world_->gather_state();  // after a step that left only the walls whole
  if (row) {
    record_history();
    while (next_output_strain_ <= path_.strain() + 1e-12) next_output_strain_ += config_.output.every_strain;
  }
  for (; fabric_due(); ++next_fabric_)
    fabric_->record(*world_, label_for(config_.output.fabric_strains[next_fabric_]), strain);
  for (; snapshot_due(); ++next_snapshot_)
    snapshots_->write(*world_, label_for(config_.output.snapshot_strains[next_snapshot_]), world_->time(), strain);
}

void SimpleShearTest::maybe_save_restart() {
  if (world_->step_count() - last_restart_step_ < config_.output.restart_every_steps) return;
  last_restart_step_ = world_->step_count();
  world_->gather_state();  // after a step that left only the walls whole
  save_restart(out_dir_ / "restart.restart");
}

RunProgress SimpleShearTest::progress_made() const {
  switch (stage_) {
    case ShearStage::Empty: return RunProgress::Generating;
    case ShearStage::Generated: return consolidating_ ? RunProgress::Consolidating : RunProgress::Generated;
    case ShearStage::Consolidated: return RunProgress::Consolidated;
    case ShearStage::Shearing: return RunProgress::Shearing;
    case ShearStage::Done: return RunProgress::Done;
  }
  return RunProgress::Generating;
}

std::vector<std::string> SimpleShearTest::run_files() {
  return {"history.csv", "summary.json", "fabric.csv", "snapshots", "restart.restart", "consolidated.restart",
          "final.restart"};
}

void SimpleShearTest::record_configuration(const io::Config& resolved) { configuration_ = configuration_record(resolved); }

void SimpleShearTest::open_outputs(const OutputOptions& options) {
  require(!folder_, "open_outputs()", "called twice", "once per run");
  const bool own = !restart_folder_.empty() && same_folder(restart_folder_, out_dir_);
  io::OutputFolderPolicy policy;
  policy.replace = options.replace;
  policy.continues_own_run = own;
  policy.run_files = run_files();
  policy.run_files.insert(policy.run_files.end(), options.more_run_files.begin(), options.more_run_files.end());
  policy.replace_option = options.replace_option;
  policy.program = options.program;
  folder_ = std::make_unique<io::OutputFolder>(out_dir_, policy);
  for (const std::string& name : folder_->replaced()) log_ << "removed " << (out_dir_ / name).string() << " of the run the folder held\n";
  if (folder_->leftovers_removed() > 0)
    log_ << "removed " << folder_->leftovers_removed() << " temporary file(s) left by a killed run\n";
  if (restart_folder_.empty()) return;
  // A restart from another folder (a second shear of one consolidated specimen) brings the
  // outputs written up to it, which the restored protocol continues.
  if (!own) copy_run_files(restart_folder_, out_dir_);
  fabric_->resume(next_fabric_);
  snapshots_->resume(next_snapshot_);
}

void SimpleShearTest::apply_configuration_record(const std::vector<std::pair<std::string, std::string>>& file_record,
                                                 const std::filesystem::path& file, ResumeIntent intent) {
  if (file_record.empty() || configuration_.empty()) return;  // a file or a run without a record
  const std::vector<ResumeChange> changes = check_resume(file_record, configuration_, progress_made(),
                                                         intent == ResumeIntent::Reconsolidate, "restart file " + file.string());
  for (const ResumeChange& c : changes) {
    log_ << "applied " << c.key << " = " << c.new_value << " (the restart file had " << c.file_value << ")\n";
    resume_changes_.push_back({c.key, c.file_value, c.new_value});
  }
}

void SimpleShearTest::save_restart(const std::filesystem::path& file) const {
  io::save_checkpoint(file, *world_, protocol_state());
}

void SimpleShearTest::load_restart(const std::filesystem::path& file, ResumeIntent intent) {
  require(!folder_, "load_restart() after the output folder was opened", file.string(), "a restart loaded before any stage ran");
  require(restart_folder_.empty(), "load_restart() a second time", file.string(), "one restart file per test");
  // The walls, rings and contact models are as configured (the constructor's); the file supplies the state.
  const World as_configured = *world_;
  const std::string protocol = io::load_checkpoint(file, *world_);
  restart_folder_ = std::filesystem::absolute(file).parent_path();
  restore_protocol_state(protocol);
  apply_configuration_record(file_configuration_, file, intent);
  if (!generating_) require_configured_grading(*world_, config_, file);  // balls still growing are smaller than the grading's
  apply_restart_keys(*world_, as_configured, cell_, config_, file, log_);
  // A generation resumes with the friction it had reached; the contact lists and their history
  // stay as the file has them (no rebuild that the uninterrupted run did not do).
  if (generating_) set_contact_models(friction_now_, rolling_friction_now_, true, ModelChange::KeepContacts);
  if (stage_ >= ShearStage::Generated) release_rings(*world_, cell_);  // rings.vertical from this configuration
  log_ << "resumed from " << file.string() << " at step " << world_->step_count() << ", time step " << world_->time_step()
       << " s (" << to_string(progress_made()) << ", shear strain " << path_.strain() << ")\n";
}

void SimpleShearTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  const double d_max = config_.grading.largest();
  j["balls"] = ball_count_;
  j["porosity_generated"] = generated_porosity_;
  j["d_min_m"] = config_.grading.smallest();
  j["d_max_m"] = d_max;
  j["height_m"] = config_.specimen.height;
  j["consolidated_height_m"] = consolidated_height_;
  j["diameter_m"] = config_.specimen.diameter;
  const double h_over_d = config_.specimen.height / d_max, d_over_h = config_.specimen.diameter / config_.specimen.height;
  j["H_over_dmax"] = h_over_d;
  j["D_over_H"] = d_over_h;
  j["astm_d6528_H_over_dmax_above_10"] = h_over_d > 10.0;
  j["astm_d6528_D_over_H_above_2_5"] = d_over_h > 2.5;
  if (stage_ >= ShearStage::Consolidated) {
    j["shear_rate_per_s"] = shear_rate();
    j["inertial_number"] = inertial_number();
  }
  // Peak and final values from the history.
  const auto& rows = history_.table().rows();
  auto col = [&](const std::string& name) { return history_.table().column_index(name); };
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
                             "sigma_3", "principal_rotation_deg", "contacts", "mean_contact_force", "coordination_number", "k0"})
      f[name] = last[col(name)];
    j["final"] = f;
    io::Json c;
    const auto& first = rows.front();
    for (const char* name : {"vertical_stress", "lateral_stress", "k0", "contacts", "mean_contact_force", "porosity",
                             "coordination_number", "sigma_1", "sigma_3"})
      c[name] = first[col(name)];
    j["after_consolidation"] = c;
  }
  for (const auto& [name, state] : {std::pair{"specimen_generated", &generated_state_}, std::pair{"specimen_consolidated", &consolidated_state_}}) {
    if (stage_ < (state == &generated_state_ ? ShearStage::Generated : ShearStage::Consolidated)) continue;
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
  if (!rows.empty() && consolidated_height_ > 0) {
    const SpanUniformity span = span_uniformity(history_.table(), config_.measure.profile_bins, 0.2, 0.4,
                                                config_.output.every_strain, leg_direction(legs_.size() - 1));
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
  j["steps"] = world_->step_count();
  j["wall_clock_s"] = wall_seconds_;
  j["particle_steps_per_second"] =
      wall_seconds_ > 0 ? static_cast<double>(world_->step_count()) * static_cast<double>(world_->particles().size()) / wall_seconds_ : 0.0;
  j["threads"] = world_->threads();
  j["processes"] = world_->ranks();  // MPI ranks the simulation was spread over
  j["time_step_s"] = world_->time_step();
  // Where this process's steps spent their time (a resumed run: since it resumed).
  const StepTiming& t = world_->step_timing();
  j["step_timing_s"] = {{"rebuilds", t.rebuilds},       {"ball_ball", t.ball_ball},     {"ball_pebble", t.ball_pebble},
                        {"ball_facet", t.ball_facet},   {"force_sums", t.force_sums},   {"controllers", t.controllers},
                        {"integration", t.integration}, {"communication", t.communication}, {"total", t.total()}};
  j["configuration"] = io::Json::parse(resolved_config_json);
  if (!restart_folder_.empty()) {
    io::Json changed;
    for (const auto& [key, before, after] : resume_changes_) {
      io::Json c;
      c["restart_file"] = before;
      c["this_run"] = after;
      changed[key] = c;
    }
    j["resume_changed_keys"] = changed;
  }
  io::save_json(out_dir_ / "summary.json", j);
  if (h_over_d <= 10.0)
    log_ << "warning: H/d_max = " << h_over_d << " is not above 10 (ASTM D6528 as quoted by the study)\n";
  if (d_over_h <= 2.5) log_ << "warning: D/H = " << d_over_h << " is not above 2.5 (ASTM D6528)\n";
}

}  // namespace dem::lab
