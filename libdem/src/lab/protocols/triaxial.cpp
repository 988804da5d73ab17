// The drained triaxial test, as its method reads: balls on a jittered lattice inside six walls,
// compressed isotropically by the six servo walls to the confining stress with frictionless balls,
// then the sand's contact law and an axial compression at a constant strain rate while the four
// lateral walls hold the confining stress. Each stage goes on where a loaded restart file left it.
#include <dem/lab/protocols/triaxial.hpp>

#include <chrono>
#include <cmath>
#include <ostream>
#include <random>
#include <sstream>

#include <dem/boundary/wall.hpp>
#include <dem/core/errors.hpp>
#include <dem/geometry/mesh.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>
#include <dem/lab/toolkit/simple_shear_parts.hpp>

#include "../../io/json_file.hpp"
#include "../toolkit/run_summary.hpp"

namespace dem::lab {

namespace {

TriaxialConfig validated(TriaxialConfig c) {
  require(c.specimen.radius_min <= c.specimen.radius_max, "specimen.radius_min", c.specimen.radius_min,
          "<= specimen.radius_max = " + io::real_text(c.specimen.radius_max));
  require(2 * c.specimen.radius_max <= c.specimen.spacing, "specimen.spacing", c.specimen.spacing,
          ">= 2 x specimen.radius_max = " + io::real_text(2 * c.specimen.radius_max) + " m (no initial overlaps)");
  return c;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<std::string> TriaxialTest::run_files() {
  return {"history.csv", "summary.json", "restart.restart", "consolidated.restart", "final.restart"};
}

TriaxialTest::TriaxialTest(TriaxialConfig config, std::filesystem::path out_dir, std::ostream& log)
    : config_(validated(std::move(config))),
      run_(std::make_unique<World>(world_settings(config_.engine)), std::move(out_dir), {run_files(), {"history.csv"}}, log),
      history_(run_.folder() / "history.csv") {
  World& w = run_.world();
  // Six walls, wall 2 * axis + (side > 0), 40 % wider than the cube so that they overlap at the
  // edges and no ball escapes when lateral walls move out.
  const double size = config_.specimen.balls_per_side * config_.specimen.spacing;  // m
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 normal = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero(), centre = Vec3::Constant(size / 2);
      normal[axis] = side;
      u[(axis + 1) % 3] = 0.7 * size;
      v[(axis + 2) % 3] = 0.7 * size;
      centre[axis] = side > 0 ? size : 0.0;
      w.add_wall(make_facet_wall("wall", geometry::make_rectangle(centre, u, v), normal, size * size));
    }
  for (WallId k = 0; k < 6; ++k)
    servos_[k] = std::make_unique<ServoWall>(k, ServoSettings{.target_stress = config_.isotropic.confining_stress,
                                                              .max_speed = config_.isotropic.servo_max_speed});
  set_laws(false, false);
  w.add_controller([this](World& world) { control(world); });
  run_.set_restart_every(config_.output.restart_every_steps);
  run_.set_progress_every(config_.output.progress_seconds);
  add_columns();
  run_.keep("stage", [this] { return static_cast<double>(stage_); }, [this](double v) {
    require(v >= 0 && v <= 4 && v == std::floor(v), "restart file: stage", v, "0 to 4");
    stage_ = static_cast<Stage>(static_cast<int>(v));
  });
  run_.keep("stage_start_step", stage_start_step_);
  run_.keep("height0", height0_);
  run_.keep("volume0", volume0_);
  run_.keep("next_row_strain", next_row_strain_);
  run_.keep("peak_ratio", peak_ratio_);
  run_.keep("peak_strain", peak_strain_);
  for (WallId k = 0; k < 6; ++k)
    run_.keep("servo_" + std::to_string(k) + "_steps_on_target", [this, k] { return static_cast<double>(servos_[k]->steps_on_target()); },
              [this, k](double v) { servos_[k]->resume_steps_on_target(static_cast<std::int64_t>(std::max(0.0, v))); });
  run_.keep("history_rows", [this] { return static_cast<double>(history_.rows()); },
            [this](double rows) { history_.resume(run_.loaded_folder() / "history.csv", static_cast<std::size_t>(rows)); });
}

double TriaxialTest::gap(int axis) const {
  const World& w = run_.world();
  return w.wall(2 * axis + 1).reference_point[axis] - w.wall(2 * axis).reference_point[axis];
}

// Frictionless walls; the isotropic stage's ball-ball friction, then the sand's law.
void TriaxialTest::set_laws(bool sand, bool keep_contacts) {
  World& w = run_.world();
  const ContactTypeConfig& b = config_.ball_ball;
  auto ball_ball = sand ? b.model("ball_ball") : b.model_with_friction(config_.isotropic.friction, 0.0, "ball_ball");
  if (keep_contacts) w.retune_contact_model(ContactKind::BallBall, std::move(ball_ball));
  else w.set_contact_model(ContactKind::BallBall, std::move(ball_ball));
  if (!keep_contacts) w.set_contact_model(ContactKind::BallFacet, config_.ball_wall.model("ball_wall"));
}

// Every step: the loaded faces from the walls' positions, the lateral servos, and the axial walls
// by their servos (isotropic) or at the axial rate.
void TriaxialTest::control(World& w) {
  for (int axis = 0; axis < 3; ++axis) w.wall(2 * axis).area = w.wall(2 * axis + 1).area = gap((axis + 1) % 3) * gap((axis + 2) % 3);
  for (int k = 0; k < 4; ++k) (*servos_[k])(w);
  const double axial_speed = 0.5 * config_.axial.strain_rate * height0_;  // m/s, each z wall towards the centre
  for (int k = 4; k < 6; ++k) {
    if (stage_ >= Stage::Axial) w.wall(k).velocity = -axial_speed * w.wall(k).outward_normal;
    else (*servos_[k])(w);
  }
}

void TriaxialTest::load_restart(const std::filesystem::path& file) {
  const ProtocolRecord& record = run_.load(file);
  const RunProgress progress = stage_ == Stage::Empty ? RunProgress::Generating : stage_ == Stage::Isotropic ? RunProgress::Consolidating
                               : stage_ == Stage::Consolidated ? RunProgress::Consolidated : stage_ == Stage::Axial ? RunProgress::Shearing
                                                                                                                    : RunProgress::Done;
  if (!record.configuration.empty() && !run_.configuration().empty())
    for (const ResumeChange& c : check_resume(run_.schema(), record.configuration, run_.configuration(), progress, false, "restart file " + file.string()))
      run_.note_change(c.key, c.file_value, c.new_value);
  if (stage_ >= Stage::Axial) set_laws(true, true);  // the contact lists and their history as the file has them
  run_.log() << "resumed from " << file.string() << " at step " << run_.world().step_count() << " (" << to_string(progress) << ")\n";
}

void TriaxialTest::run() {
  run_.claim_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  World& w = run_.world();
  std::ostream& log = run_.log();
  if (stage_ == Stage::Empty) {  // balls of uniform random radius on a jittered lattice, no overlaps
    const CubeSpecimenConfig& s = config_.specimen;
    std::mt19937_64 rng(s.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int n = s.balls_per_side;
    for (int k = 0; k < n * n * n; ++k) {
      BallSpec ball;
      ball.radius = s.radius_min + (s.radius_max - s.radius_min) * unit(rng);
      ball.density = s.density;
      const Vec3 jitter = (Vec3(unit(rng), unit(rng), unit(rng)) - Vec3::Constant(0.5)) * (s.spacing - 2 * ball.radius);
      ball.position = (Vec3(k % n, k / n % n, k / (n * n)) + Vec3::Constant(0.5)) * s.spacing + jitter;
      w.add_ball(ball);
    }
    stage_ = Stage::Isotropic;
    stage_start_step_ = w.step_count();
  }
  if (stage_ == Stage::Isotropic) {
    // Until every wall is on target and the packing is nearly static.
    const auto settled = [&] {
      for (const auto& s : servos_)
        if (!s->settled()) return false;
      return w.unbalanced_force_ratio() < config_.isotropic.equilibrium_ratio;
    };
    while (!settled()) {
      if (w.step_count() - stage_start_step_ >= config_.isotropic.max_steps) {
        log << "warning: the isotropic stage did not settle within isotropic.max_steps = " << config_.isotropic.max_steps << "\n";
        break;
      }
      run_.step(100);
      std::ostringstream detail;
      detail << "step " << w.step_count() << ", wall stresses " << w.wall(0).normal_stress() / 1e3 << ", " << w.wall(2).normal_stress() / 1e3
             << ", " << w.wall(4).normal_stress() / 1e3 << " kPa, unbalanced ratio " << w.unbalanced_force_ratio();
      run_.progress("isotropic", detail.str());
    }
    stage_ = Stage::Consolidated;
    height0_ = gap(2);
    volume0_ = gap(0) * gap(1) * gap(2);
    log << "isotropic stage done at step " << w.step_count() << ": " << w.particles().size() << " balls, box " << gap(0) * 1e3
        << " x " << gap(1) * 1e3 << " x " << gap(2) * 1e3 << " mm, time step " << w.time_step() << " s\n";
    history_.record();  // axial strain 0
    next_row_strain_ = config_.axial.every_strain;
    run_.save(run_.folder() / "consolidated.restart");
  }
  if (stage_ == Stage::Consolidated) {
    set_laws(true, false);
    stage_ = Stage::Axial;
  }
  if (stage_ == Stage::Axial) {
    const double target = config_.axial.target_strain;
    double strain = 1 - gap(2) / height0_;
    while (strain < target) {
      w.step(10);
      strain = 1 - gap(2) / height0_;
      if (strain >= next_row_strain_ - 1e-12 || strain >= target) {
        history_.record();
        while (next_row_strain_ <= strain + 1e-12) next_row_strain_ += config_.axial.every_strain;
        const double ratio = history_.last("stress_ratio");
        if (ratio > peak_ratio_) peak_ratio_ = ratio, peak_strain_ = strain;
        std::ostringstream detail;
        detail << "axial strain " << strain << " of " << target << ", q " << history_.last("deviator_stress") / 1e3 << " kPa, p "
               << history_.last("mean_stress") / 1e3 << " kPa";
        run_.progress("axial", detail.str(), strain, target);
      }
      run_.save_if_due();  // after the chunk's row: a resume goes on with the next chunk
    }
    stage_ = Stage::Done;
    run_.add_wall_seconds(seconds_since(t0));
    run_.save(run_.folder() / "final.restart");
    log << "axial stage done at step " << w.step_count() << ": peak q/p " << peak_ratio_ << " at axial strain " << peak_strain_ << "\n";
  }
}

void TriaxialTest::add_columns() {
  const World& w = run_.world();
  HistoryLog& h = history_;
  const auto axial = [this] { return 0.5 * (run_.world().wall(4).normal_stress() + run_.world().wall(5).normal_stress()); };
  const auto radial = [this] {
    double lateral = 0.0;
    for (WallId k = 0; k < 4; ++k) lateral += 0.25 * run_.world().wall(k).normal_stress();
    return lateral;
  };
  h.add("time", [&w] { return w.time(); });
  h.add("step", [&w] { return static_cast<double>(w.step_count()); });
  h.add("stage", [this] { return static_cast<double>(stage_); });
  h.add("axial_strain", [this] { return 1 - gap(2) / height0_; });
  h.add("volumetric_strain", [this] { return 1 - gap(0) * gap(1) * gap(2) / volume0_; });  // compression positive
  h.add("sigma_axial", axial);
  h.add("sigma_radial", radial);
  h.add("mean_stress", [axial, radial] { return (axial() + 2 * radial()) / 3; });
  h.add("deviator_stress", [axial, radial] { return axial() - radial(); });
  h.add("stress_ratio", [axial, radial] { return (axial() - radial()) / ((axial() + 2 * radial()) / 3); });
  h.add("width_x", [this] { return gap(0); });
  h.add("width_y", [this] { return gap(1); });
  h.add("height", [this] { return gap(2); });
  h.add("coordination_number", [&w] {
    return 2.0 * static_cast<double>(w.contact_count(ContactKind::BallBall)) / static_cast<double>(std::max<std::size_t>(1, w.particles().size()));
  });
  h.add("kinetic_energy", [&w] { return w.kinetic_energy(); });
}

void TriaxialTest::write_summary(const std::string& resolved_config_json) const {
  io::Json j;
  j["balls"] = run_.world().particles().size();
  j["height_after_isotropic_m"] = height0_;
  j["volume_after_isotropic_m3"] = volume0_;
  j["peak"] = {{"stress_ratio", peak_ratio_}, {"axial_strain", peak_strain_}};
  if (history_.rows() > 0) {
    io::Json f;
    for (const char* name : {"axial_strain", "volumetric_strain", "mean_stress", "deviator_stress", "stress_ratio", "coordination_number"})
      f[name] = history_.last(name);
    j["final"] = f;
  }
  save_summary(run_, j, resolved_config_json, run_.wall_seconds());
}

}  // namespace dem::lab
