// The simple-shear protocol: world set-up, generation, consolidation and shear. Measurements,
// outputs and restart files are in simple_shear_outputs.cpp.
#include <dem/lab/simple_shear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <random>

#include <dem/core/errors.hpp>
#include <dem/lab/consolidation.hpp>
#include <dem/lab/fabric_log.hpp>
#include <dem/lab/friction_schedule.hpp>
#include <dem/lab/simple_shear_parts.hpp>
#include <dem/lab/snapshots.hpp>

namespace dem::lab {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The ids of the balls (not pebbles), ascending: the order they were added in.
std::vector<ParticleId> ball_ids(const ParticleStore& p) {
  std::vector<ParticleId> ids;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) ids.push_back(p.id[i]);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace

SimpleShearTest::SimpleShearTest(SimpleShearConfig config, std::filesystem::path out_dir, std::ostream& log)
    : config_(std::move(config)), out_dir_(std::move(out_dir)), log_(log), history_(out_dir_ / "history.csv") {
  config_.validate();
  legs_ = config_.shear.legs();
  require(config_.shear.total_strain() > 0.0, "shear strain", config_.shear.total_strain(), "> 0");
  fabric_ = std::make_unique<FabricLog>(out_dir_ / "fabric.csv");
  snapshots_ = std::make_unique<SnapshotWriter>(out_dir_ / "snapshots");
  build_world();
  add_history_columns();
}

SimpleShearTest::~SimpleShearTest() = default;

void SimpleShearTest::build_world() {
  world_ = std::make_unique<World>(world_settings(config_));
  cell_ = build_shear_cell(*world_, shear_cell_spec(config_));
  set_contact_models(config_.ball_ball.friction(), config_.ball_ball.rolling_friction(), false);
  servo_.reset();
  world_->add_controller([this](World& w) { control(w); });
}

void SimpleShearTest::set_contact_models(double friction, double rolling_friction, bool growing, ModelChange change) {
  friction_now_ = friction;
  rolling_friction_now_ = rolling_friction;
  set_contact_laws(*world_, config_, friction, rolling_friction, growing, change);
}

void SimpleShearTest::control(World& w) {
  if (servo_) (*servo_)(w);
  if (generation_floor_) keep_plate_gap(w, cell_, config_.specimen.height);  // the radii grow in the cavity
  move_rings(w, cell_, stage_ >= ShearStage::Generated);
  w.set_damping_frame(stage_ == ShearStage::Shearing ? shear_damping_frame(config_, w, cell_) : DampingFrame{});
}

void SimpleShearTest::generate() {
  require(stage_ == ShearStage::Empty, "generate() stage", static_cast<int>(stage_), "0 (empty world)");
  open_outputs_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  const double radius = config_.specimen.diameter / 2, height = config_.specimen.height;
  const double cavity = pi * radius * radius * height;
  std::mt19937_64 rng(config_.specimen.seed);  // the diameters, then the positions
  const std::vector<double> diameters = specimen_diameters(config_, rng);
  double solid = 0.0;
  for (double d : diameters) solid += pi / 6 * d * d * d;
  RadiusExpansion expansion;
  if (generating_) {  // resumed from a restart file written during the generation
    require(diameters.size() == ball_count_, "grading and specimen.seed", std::to_string(diameters.size()) + " balls",
            "the " + std::to_string(ball_count_) + " balls of the restart file's generation");
    expansion.balls = ball_ids(world_->particles());  // in the order they were added
    expansion.diameters = diameters;
    expansion.stages = config_.generation.stages;
  } else {
    generated_porosity_ = 1.0 - solid / cavity;
    ball_count_ = diameters.size();
    log_ << "generation: " << ball_count_ << " balls, d = " << config_.grading.smallest() * 1e3 << "-"
         << config_.grading.largest() * 1e3 << " mm, porosity " << generated_porosity_ << ", H/d_max = "
         << height / config_.grading.largest() << "\n";
    expansion = add_expanding_balls(*world_, Cylinder{radius, height}, diameters, config_.specimen.density,
                                    config_.generation.stages, rng);
    // Expansion to full size in stages, with the generation friction on the ball-ball contacts
    // (plates and rings frictionless), cycling towards equilibrium in between. With the servo
    // plate the specimen grows against a low stress instead of a closed cavity.
    set_contact_models(config_.generation_friction(), config_.generation_rolling_friction(), true);
    if (config_.generation.plate == GenerationPlate::Servo) {
      servo_ = std::make_shared<ServoWall>(cell_.top, generation_servo(config_));
      generation_floor_ = true;
    }
    generating_ = true;
    generation_ = {};
  }
  expand_radii(expansion);
  if (config_.generation.plate == GenerationPlate::Servo) friction_schedule();
  generating_ = false;
  generation_ = {};  // as a run resumed after the generation has it
  generation_floor_ = false;
  generated_state_ = specimen_state();
  release_rings(*world_, cell_);
  set_contact_models(config_.ball_ball.friction(), config_.ball_ball.rolling_friction(), false);
  stage_ = ShearStage::Generated;
  wall_seconds_ += seconds_since(t0);
  log_ << "generation done in " << seconds_since(t0) << " s, " << world_->step_count() << " steps: porosity "
       << generated_state_.porosity << " (target " << config_.specimen.porosity << "), coordination "
       << generated_state_.coordination_number << ", K0 " << generated_state_.k0 << ", vertical stress "
       << generated_state_.vertical_stress / 1e3 << " kPa, height " << generated_state_.height * 1e3 << " mm\n";
  require_no_escape();
}

// Each stage grows the radii in small increments, then cycles towards equilibrium. The loop
// counters live in generation_, so that a restart file written between any two chunks resumes the
// generation where it was.
void SimpleShearTest::expand_radii(const RadiusExpansion& expansion) {
  GenerationProgress& g = generation_;
  for (; g.phase <= GenerationProgress::Settling && g.stage <= expansion.stages;
       ++g.stage, g.increment = 0, g.phase = GenerationProgress::Expanding) {
    while (g.phase == GenerationProgress::Expanding && g.increment < expansion.increments) {
      ++g.increment;
      set_radii(*world_, expansion, expansion.factor(g.stage, g.increment));
      world_->step(expansion.steps_per_increment);
      if (g.increment == expansion.increments) g.phase = GenerationProgress::Settling, g.settled_steps = 0;
      maybe_save_restart();
    }
    settle_generation([&] { return world_->unbalanced_force_ratio() < config_.generation.equilibrium_ratio; });
    std::ostringstream detail;
    detail << "stage " << g.stage << "/" << expansion.stages << ", radius x" << expansion.factor(g.stage, g.increment) << ", unbalanced ratio "
           << world_->unbalanced_force_ratio() << ", top plate " << world_->wall(cell_.top).normal_stress() / 1e3
           << " kPa, porosity " << specimen_state().porosity << ", step " << world_->step_count();
    log_ << "[generation] " << detail.str() << std::endl;
  }
  if (g.phase <= GenerationProgress::Settling) g.phase = GenerationProgress::FirstSettle, g.settled_steps = 0;
}

void SimpleShearTest::settle_generation(const std::function<bool()>& done) {
  // Checked after each chunk, before a restart may be written: a resumed settle goes on exactly
  // when the uninterrupted one did.
  while (generation_.settled_steps < config_.generation.steps_per_stage) {
    world_->step(100);
    if (done()) break;
    generation_.settled_steps += 100;
    maybe_save_restart();
  }
  generation_.settled_steps = 0;
}

// A frictional packing grown against a low stress is looser than the target when its friction
// holds it open; lowering the friction step by step lets the servo plate settle it, until the
// porosity is within the tolerance of the target (docs/model.md 7.1). The plate cannot sink below
// the specimen height, so the porosity never falls below the target's.
void SimpleShearTest::friction_schedule() {
  // A few kPa on a loose packing fluctuates by more than the consolidation tolerance, so settled
  // here means in equilibrium with the plate stress within 10 % of its target.
  auto settled = [&] {
    return world_->unbalanced_force_ratio() < config_.generation.equilibrium_ratio &&
           std::abs(servo_->achieved_stress() - config_.generation.stress) <= 0.1 * config_.generation.stress;
  };
  GenerationProgress& g = generation_;
  if (g.phase == GenerationProgress::FirstSettle) {
    settle_generation(settled);
    g.phase = GenerationProgress::Reducing;
  }
  const FrictionSchedule schedule = generation_friction_schedule(config_);
  while (true) {
    if (g.phase == GenerationProgress::Reducing) {
      const std::optional<Friction> next = next_friction(schedule, specimen_state().porosity, {friction_now_, rolling_friction_now_});
      if (!next) break;
      set_contact_models(next->sliding, next->rolling, true);
      g.phase = GenerationProgress::ScheduleSettle;
      g.settled_steps = 0;
    }
    settle_generation(settled);
    g.phase = GenerationProgress::Reducing;
    log_ << "[generation] friction schedule: mu " << friction_now_ << ", mu_r " << rolling_friction_now_ << ", porosity "
         << specimen_state().porosity << ", top plate " << world_->wall(cell_.top).normal_stress() / 1e3 << " kPa, step "
         << world_->step_count() << std::endl;
  }
  const SpecimenState state = specimen_state();
  const double porosity = state.porosity;
  if (state.height <= config_.specimen.height * (1 + 1e-9) && servo_->achieved_stress() < 0.9 * config_.generation.stress)
    log_ << "note: the specimen settled onto the top plate's lowest position (specimen.height = " << config_.specimen.height
         << " m) at porosity " << porosity << ", ball-ball friction " << friction_now_ << ": the plate holds it at "
         << servo_->achieved_stress() << " Pa, not generation.stress = " << config_.generation.stress
         << " Pa: specimen.porosity is looser than the balls settle to at this friction\n";
  if (porosity > config_.specimen.porosity + config_.generation.porosity_tolerance)
    log_ << "note: the friction schedule reached zero friction at porosity " << porosity << ", above specimen.porosity = "
         << config_.specimen.porosity << " + " << config_.generation.porosity_tolerance << ": spheres of this grading settle no denser "
         << "at generation.stress = " << config_.generation.stress << " Pa within generation.steps_per_stage = "
         << config_.generation.steps_per_stage << " steps per schedule step; consolidation densifies the specimen further\n";
}

void SimpleShearTest::consolidate() {
  require(stage_ == ShearStage::Generated, "consolidate() stage", static_cast<int>(stage_), "1 (generated)");
  open_outputs_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  const ConsolidationTarget target = consolidation_target(config_, chunk_steps);
  if (!consolidating_) {
    if (!servo_) servo_ = std::make_shared<ServoWall>(cell_.top, servo_settings());
    start_consolidation(*servo_, target);
    consolidation_start_step_ = world_->step_count();
    consolidating_ = true;
  }
  const ConsolidationReport report = lab::consolidate(*world_, *servo_, target, consolidation_start_step_, [&] {
    maybe_save_restart();
    std::ostringstream detail;
    detail << "step " << world_->step_count() << ", vertical stress " << servo_->achieved_stress() / 1e3 << " kPa (target "
           << target.stress / 1e3 << "), unbalanced ratio " << world_->unbalanced_force_ratio();
    progress("consolidation", detail.str());
  });
  consolidating_ = false;
  if (!report.settled)
    log_ << "warning: consolidation did not settle within consolidation.max_steps = " << config_.consolidation.max_steps
         << " (stress " << servo_->achieved_stress() << " Pa, target " << config_.consolidation.vertical_stress << " Pa)\n";
  const Wall& top = world_->wall(cell_.top);
  consolidated_height_ = cell_.plate_gap(*world_);
  consolidated_state_ = specimen_state();
  stage_ = ShearStage::Consolidated;
  wall_seconds_ += seconds_since(t0);
  log_ << "consolidation done in " << seconds_since(t0) << " s: H_c = " << consolidated_height_ * 1e3
       << " mm, vertical stress " << top.normal_stress() / 1e3 << " kPa, porosity " << consolidated_state_.porosity
       << ", coordination " << consolidated_state_.coordination_number << ", K0 " << consolidated_state_.k0 << "\n";
  require_no_escape();
  next_output_strain_ = 0.0;
  record_outputs(true);
  save_restart(out_dir_ / "consolidated.restart");
}

void SimpleShearTest::reconsolidate() {
  require(stage_ == ShearStage::Consolidated, "reconsolidate() stage", static_cast<int>(stage_), "2 (consolidated)");
  world_->update_time_step();  // the restart's step belongs to the stiffness it was written with
  stage_ = ShearStage::Generated;
  if (servo_) {
    servo_->hold_position(false);
    servo_->set_max_speed(config_.consolidation.servo_max_speed);  // the consolidation's cap, not the shear's
  }
  consolidate();
}

ServoSettings SimpleShearTest::servo_settings() const {
  ServoSettings servo = consolidation_servo(config_);
  if (stage_ >= ShearStage::Consolidated) servo.max_speed = shear_servo_speed();
  return servo;
}

double SimpleShearTest::shear_servo_speed() const {
  return lab::shear_servo_speed(config_, shear_rate(), consolidated_height_);
}

Vec3 SimpleShearTest::leg_direction(std::size_t leg) const {
  return horizontal_direction(legs_.at(leg).direction_deg);
}

double SimpleShearTest::shear_rate() const { return shear_strain_rate(config_, *world_); }

double SimpleShearTest::inertial_number() const {
  return shear_rate() * mean_ball_diameter(*world_, config_.grading.largest()) * std::sqrt(config_.specimen.density / config_.consolidation.vertical_stress);
}

void SimpleShearTest::start_leg() {
  start_shear_leg(*world_, cell_, *servo_, shear_leg_motion(config_, legs_.at(leg_).direction_deg, shear_rate(), consolidated_height_));
}

void SimpleShearTest::shear() {
  require(stage_ == ShearStage::Consolidated || stage_ == ShearStage::Shearing, "shear() stage", static_cast<int>(stage_),
          "2 (consolidated) or 3 (shearing)");
  open_outputs_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  if (stage_ == ShearStage::Consolidated) {
    stage_ = ShearStage::Shearing;
    leg_ = 0;
    leg_start_strain_ = 0.0;
    steps_at_shear_start_ = world_->step_count();
    path_ = ShearPath(*world_, cell_, consolidated_height_);
    // The row at zero strain was written after consolidation; the interval is this run's (a
    // specimen consolidated by another run may have used another one).
    next_output_strain_ = config_.output.every_strain;
    start_leg();
    log_ << "shear: rate " << shear_rate() << " 1/s, inertial number " << inertial_number() << ", "
         << ((config_.shear.mode == ShearMode::ConstantVolume) ? "constant volume" : "drained") << ", " << legs_.size() << " leg(s) to "
         << config_.shear.total_strain() << "\n";
    if (inertial_number() > 1e-3 * 1.0001) log_ << "warning: inertial number above 1e-3: not quasi-static\n";
  }
  const std::int64_t steps_before = world_->step_count();
  const double strain_before = path_.strain();  // a resumed run has done part of the path already
  const auto particles = static_cast<double>(world_->particles().size());
  while (leg_ < legs_.size()) {
    // The strain check reads the plates only: a World spread over processes gathers its whole
    // state for the outputs and restart files alone (record_outputs, maybe_save_restart).
    world_->step(chunk_steps, World::StepEnd::WallsAndClumps);
    path_.advance(*world_, cell_);
    const bool leg_done = path_.strain() - leg_start_strain_ >= legs_[leg_].strain * (1 - 1e-12);
    if (leg_done) {
      leg_start_strain_ += legs_[leg_].strain;
      ++leg_;
      if (leg_ < legs_.size()) start_leg();
    }
    record_outputs(leg_ == legs_.size());
    maybe_save_restart();
    const double elapsed = seconds_since(t0);
    // Time left from this run's own pace, over the strain still to go.
    const double strain_done = path_.strain() - strain_before;
    const double strain_left = std::max(0.0, config_.shear.total_strain() - path_.strain());
    std::ostringstream detail;
    detail.precision(4);
    const std::int64_t steps = world_->step_count() - steps_before;
    detail << "strain " << path_.strain() << " of " << config_.shear.total_strain() << ", tau "
           << history_.last("shear_stress") / 1e3
           << " kPa, sigma_v " << world_->wall(cell_.top).normal_stress() / 1e3 << " kPa, "
           << static_cast<double>(steps) * particles / std::max(elapsed, 1e-9)
           << " particle-steps/s, " << (strain_done > 0 ? elapsed * strain_left / strain_done : 0.0) << " s left";
    progress("shear", detail.str());
  }
  stage_ = ShearStage::Done;
  stop_shear(*world_, cell_);
  wall_seconds_ += seconds_since(t0);
  save_restart(out_dir_ / "final.restart");
  log_ << "shear done in " << seconds_since(t0) << " s, " << world_->step_count() - steps_at_shear_start_ << " steps\n";
}

void SimpleShearTest::run() {
  if (stage_ == ShearStage::Empty) generate();
  if (stage_ == ShearStage::Generated) consolidate();
  if (stage_ == ShearStage::Consolidated || stage_ == ShearStage::Shearing) shear();
}

void SimpleShearTest::progress(const std::string& stage, const std::string& detail) const {
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (now - last_progress_ < config_.output.progress_seconds) return;
  last_progress_ = now;
  log_ << "[" << stage << "] " << detail << std::endl;
}

}  // namespace dem::lab
