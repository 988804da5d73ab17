// Measurements, outputs and restart files of the simple-shear protocol.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/io/json.hpp>
#include <dem/lab/fabric_log.hpp>
#include <dem/lab/simple_shear.hpp>
#include <dem/lab/snapshots.hpp>

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

bool same_folder(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  const bool same = std::filesystem::equivalent(a, b, error);
  return !error && same;
}

}  // namespace

ShearState SimpleShearTest::measure() const {
  const World& w = *world_;
  const FacetWall& top = w.wall(top_);
  const FacetWall& bottom = w.wall(bottom_);
  ShearState s;
  s.time = w.time();
  s.height = (config_.height + top.displacement.z()) - bottom.displacement.z();
  const double reference = consolidated_height_ > 0 ? consolidated_height_ : s.height;
  Vec3 relative = bottom.displacement - top.displacement;
  relative.z() = 0.0;
  s.shear_strain_x = relative.x() / reference;
  s.shear_strain_y = relative.y() / reference;
  s.shear_strain = relative.norm() / reference;
  // The sand, dragged along the shear by the bottom plate, pushes the top plate the same way.
  s.shear_stress_x = top.force.x() / area_;
  s.shear_stress_y = top.force.y() / area_;
  s.shear_stress = std::hypot(s.shear_stress_x, s.shear_stress_y);
  const Vec3 along = s.shear_stress > 0 ? Vec3(Vec3(s.shear_stress_x, s.shear_stress_y, 0) / s.shear_stress) : Vec3(Vec3::UnitX());
  s.shear_stress_bottom = -bottom.force.dot(along) / area_;
  s.vertical_stress = top.normal_stress();
  s.vertical_stress_bottom = bottom.normal_stress();
  const double dilation = consolidated_height_ > 0 ? (s.height - consolidated_height_) / consolidated_height_ : 0.0;
  s.volumetric_strain = config_.dilation_positive ? dilation : -dilation;

  // Radial push of the sand on the rings, over the lateral surface.
  double radial = 0.0, mean_force = 0.0;
  std::size_t contacts = 0;
  const ParticleStore& p = w.particles();
  w.for_each_contact([&](const ContactView& c) {
    if (c.kind == ContactKind::BallPebble) {
      const auto j = static_cast<std::size_t>(c.second);
      const Vec3& centre = w.clumps()[static_cast<std::size_t>(p.clump[j])].x;
      Vec3 outward = c.point - centre;
      outward.z() = 0.0;
      if (outward.norm() > 0) radial += c.force.dot(outward.normalized());
    } else if (c.kind == ContactKind::BallBall) {
      mean_force += c.normal_force;
      ++contacts;
    }
  });
  s.lateral_stress = radial / (2 * pi * (config_.diameter / 2) * s.height);
  s.contacts = contacts;
  s.mean_contact_force = contacts > 0 ? mean_force / static_cast<double>(contacts) : 0.0;
  s.kinetic_energy = w.kinetic_energy();

  // The probe sits at mid-height and follows the specimen's mean horizontal displacement.
  MeasurementSphere sphere;
  sphere.centre = 0.5 * (bottom.displacement + top.displacement);
  sphere.centre.z() = bottom.displacement.z() + 0.5 * s.height;
  sphere.radius = config_.probe_radius_ratio * 0.5 * s.height;
  s.sphere = dem::measure::measure(w, sphere);
  const Vec3 d = (stage_ >= ShearStage::Shearing && leg_ < config_.legs.size()) ? leg_direction(leg_)
                 : leg_direction(std::min(leg_, config_.legs.size() - 1));
  const Mat3 compression = -s.sphere.stress;
  const double s_dd = d.dot(compression * d), s_dz = d.dot(compression * Vec3::UnitZ());
  const double s_zz = compression(2, 2);
  // Angle of the major compression from vertical towards +d (docs/model.md 6.3); with the bottom
  // moving along +d it tilts towards +d, so it grows positive with shear.
  s.principal_rotation_deg = 0.5 * std::atan2(2 * s_dz, s_zz - s_dd) * 180.0 / pi;
  return s;
}

void SimpleShearTest::record_history() {
  const ShearState s = measure();
  const Mat3 c = -s.sphere.stress;  // compression positive
  const Vec3 d = leg_direction(std::min(leg_, config_.legs.size() - 1));
  history_.add_row({s.time, static_cast<double>(world_->step_count()), static_cast<double>(stage_), s.shear_strain_x,
                    s.shear_strain_y, s.shear_strain, s.shear_stress_x, s.shear_stress_y, s.shear_stress,
                    s.shear_stress_bottom, s.vertical_stress, s.vertical_stress_bottom, s.height, s.volumetric_strain,
                    s.lateral_stress, s.vertical_stress > 0 ? s.lateral_stress / s.vertical_stress : 0.0,
                    s.sphere.principal.sigma_1, s.sphere.principal.sigma_2, s.sphere.principal.sigma_3,
                    s.principal_rotation_deg, c(0, 0), c(1, 1), c(2, 2), c(0, 1), c(0, 2), c(1, 2),
                    d.dot(c * Vec3::UnitZ()), s.sphere.coordination_number, static_cast<double>(s.contacts),
                    s.mean_contact_force, s.sphere.porosity, s.kinetic_energy, stage_ >= ShearStage::Consolidated ? inertial_number() : 0.0});
  history_.save(out_dir_ / "history.csv");
}

void SimpleShearTest::record_outputs(bool force) {
  if (force || path_strain_ >= next_output_strain_ - 1e-12) {
    record_history();
    while (next_output_strain_ <= path_strain_ + 1e-12) next_output_strain_ += config_.output_every_strain;
  }
  const double strain = path_strain_;
  while (next_fabric_ < config_.fabric_strains.size() && strain >= config_.fabric_strains[next_fabric_] - 1e-12) {
    fabric_->record(*world_, label_for(config_.fabric_strains[next_fabric_]), strain);
    ++next_fabric_;
  }
  while (next_snapshot_ < config_.snapshot_strains.size() && strain >= config_.snapshot_strains[next_snapshot_] - 1e-12) {
    snapshots_->write(*world_, label_for(config_.snapshot_strains[next_snapshot_]), world_->time(), strain);
    ++next_snapshot_;
  }
}

void SimpleShearTest::maybe_save_restart() {
  if (world_->step_count() - last_restart_step_ < config_.restart_every_steps) return;
  last_restart_step_ = world_->step_count();
  save_restart(out_dir_ / "restart.restart");
}

std::string SimpleShearTest::protocol_state() const {
  std::ostringstream out;
  out.precision(17);
  out << "stage " << static_cast<int>(stage_) << "\nball_count " << ball_count_ << "\ngenerated_porosity "
      << generated_porosity_ << "\nconsolidated_height " << consolidated_height_ << "\nleg " << leg_
      << "\nleg_start_strain " << leg_start_strain_ << "\npath_strain " << path_strain_ << "\nnext_output_strain "
      << next_output_strain_ << "\nnext_fabric " << next_fabric_ << "\nnext_snapshot " << next_snapshot_
      << "\nlast_restart_step " << last_restart_step_ << "\nprevious_relative_x " << previous_relative_.x()
      << "\nprevious_relative_y " << previous_relative_.y() << "\nwall_seconds " << wall_seconds_
      << "\nsteps_at_shear_start " << steps_at_shear_start_ << "\nhistory_rows " << history_.rows().size()
      << "\nservo " << (servo_ ? 1 : 0) << "\nservo_holding " << (servo_ && servo_->holding_position() ? 1 : 0) << "\n";
  return out.str();
}

void SimpleShearTest::restore_protocol_state(const std::string& text) {
  std::map<std::string, double> v;
  std::istringstream in(text);
  std::string key;
  double value;
  while (in >> key >> value) v[key] = value;
  auto get = [&](const std::string& k) {
    const auto it = v.find(k);
    if (it == v.end()) throw InputError("restart file: protocol state has no '" + k + "'");
    return it->second;
  };
  stage_ = static_cast<ShearStage>(static_cast<int>(get("stage")));
  ball_count_ = static_cast<std::size_t>(get("ball_count"));
  generated_porosity_ = get("generated_porosity");
  consolidated_height_ = get("consolidated_height");
  leg_ = static_cast<std::size_t>(get("leg"));
  leg_start_strain_ = get("leg_start_strain");
  path_strain_ = get("path_strain");
  next_output_strain_ = get("next_output_strain");
  next_fabric_ = static_cast<std::size_t>(get("next_fabric"));
  next_snapshot_ = static_cast<std::size_t>(get("next_snapshot"));
  last_restart_step_ = static_cast<std::int64_t>(get("last_restart_step"));
  previous_relative_ = Vec3(get("previous_relative_x"), get("previous_relative_y"), 0.0);
  wall_seconds_ = get("wall_seconds");
  steps_at_shear_start_ = static_cast<std::int64_t>(get("steps_at_shear_start"));
  const auto rows = static_cast<std::size_t>(get("history_rows"));
  // Keep the history written up to the restart point; later rows belong to the run that stopped.
  history_ = io::CsvTable(history_.columns());
  if (rows > 0) {
    const io::CsvData old = io::read_csv(out_dir_ / "history.csv");
    require(old.rows.size() >= rows, "history.csv rows", old.rows.size(), ">= " + std::to_string(rows) + " (as in the restart file)");
    for (std::size_t r = 0; r < rows; ++r) history_.add_row(old.rows[r]);
  }
  fabric_->resume(next_fabric_);
  snapshots_->resume(next_snapshot_);
  if (get("servo") > 0) {
    servo_ = add_servo_wall(*world_, top_, servo_settings());
    servo_->hold_position(get("servo_holding") > 0);
  }
}

void SimpleShearTest::save_restart(const std::filesystem::path& file) const {
  io::save_checkpoint(file, *world_, protocol_state());
}

// A specimen resumed under another configuration would run with that configuration's contact
// parameters and rings without a word (a 2D specimen under the 4D defaults softens and collapses).
// Its ball sizes tell a different grading or size scale for certain.
void SimpleShearTest::require_configured_grading(const std::filesystem::path& file) const {
  const ParticleStore& p = world_->particles();
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i)) continue;
    smallest = std::min(smallest, 2 * p.radius[i]);
    largest = std::max(largest, 2 * p.radius[i]);
  }
  if (largest == 0.0) return;  // no balls yet
  const double tolerance = 1e-9;  // relative: the generation draws diameters inside the grading's range
  const double low = config_.grading.smallest(), high = config_.grading.largest();
  std::ostringstream found, allowed;
  found << smallest * 1e3 << "-" << largest * 1e3 << " mm";
  allowed << "within this run's grading, " << low * 1e3 << "-" << high * 1e3 << " mm (grading.scale = "
          << config_.grading.scale << "): resume with the configuration the specimen was made with (the same --preset "
          << "and --config)";
  require(smallest >= low * (1 - tolerance) && largest <= high * (1 + tolerance),
          "restart file " + file.string() + ": ball diameters", found.str(), allowed.str());
}

void SimpleShearTest::load_restart(const std::filesystem::path& file) {
  build_world();  // walls, rings and contact models as configured; the file supplies the state
  servo_.reset();
  const std::string protocol = io::load_checkpoint(file, *world_);
  require_configured_grading(file);  // before anything is copied into this run's folder
  // A restart from another folder (a second shear of one consolidated specimen) brings the
  // outputs written up to it, which the restored protocol continues.
  const std::filesystem::path source = std::filesystem::absolute(file).parent_path();
  if (!same_folder(source, out_dir_)) copy_run_files(source, out_dir_);
  restore_protocol_state(protocol);
  // The configuration's limit, not the one of the run that wrote the file (older files hold 0.5).
  world_->set_max_overlap_ratio(config_.max_overlap_ratio);
  log_ << "resumed from " << file.string() << " at step " << world_->step_count() << ", time step " << world_->time_step()
       << " s (stage " << static_cast<int>(stage_) << ", shear strain " << path_strain_ << ")\n";
}

void SimpleShearTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  const double d_max = config_.grading.largest();
  j["balls"] = static_cast<double>(ball_count_);
  j["porosity_generated"] = generated_porosity_;
  j["d_min_m"] = config_.grading.smallest();
  j["d_max_m"] = d_max;
  j["height_m"] = config_.height;
  j["consolidated_height_m"] = consolidated_height_;
  j["diameter_m"] = config_.diameter;
  const double h_over_d = config_.height / d_max, d_over_h = config_.diameter / config_.height;
  j["H_over_dmax"] = h_over_d;
  j["D_over_H"] = d_over_h;
  j["astm_d6528_H_over_dmax_above_10"] = h_over_d > 10.0;
  j["astm_d6528_D_over_H_above_2_5"] = d_over_h > 2.5;
  if (stage_ >= ShearStage::Consolidated) {
    j["shear_rate_per_s"] = shear_rate();
    j["inertial_number"] = inertial_number();
  }
  // Peak and final values from the history.
  const auto& rows = history_.rows();
  auto col = [&](const char* name) { return history_.column_index(name); };
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
  j["steps"] = static_cast<double>(world_->step_count());
  j["wall_clock_s"] = wall_seconds_;
  j["particle_steps_per_second"] =
      wall_seconds_ > 0 ? static_cast<double>(world_->step_count()) * static_cast<double>(world_->particles().size()) / wall_seconds_ : 0.0;
  j["threads"] = world_->threads();
  j["time_step_s"] = world_->time_step();
  j["configuration"] = io::Json::parse(resolved_config_json);
  j.save(out_dir_ / "summary.json");
  if (h_over_d <= 10.0)
    log_ << "warning: H/d_max = " << h_over_d << " is not above 10 (ASTM D6528 as quoted by the study)\n";
  if (d_over_h <= 2.5) log_ << "warning: D/H = " << d_over_h << " is not above 2.5 (ASTM D6528)\n";
}

}  // namespace dem::lab
