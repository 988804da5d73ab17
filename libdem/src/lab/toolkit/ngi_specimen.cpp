#include <dem/lab/toolkit/ngi_specimen.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ostream>
#include <random>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/lab/toolkit/consolidation.hpp>
#include <dem/lab/toolkit/friction_schedule.hpp>
#include <dem/lab/toolkit/specimen_guards.hpp>

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

NgiSpecimen::NgiSpecimen(Run& run, const SimpleShearConfig& config)
    : run_(run), world_(run.world()), config_(config), cell_(build_shear_cell(world_, shear_cell_spec(config))) {
  set_contact_models(config_.ball_ball.friction(), config_.ball_ball.rolling_friction(), false);
  world_.add_controller([this](World& w) { control(w); });
  keep_state();
}

// The specimen's part of a restart file, under the keys files have always had.
void NgiSpecimen::keep_state() {
  Run& r = run_;
  r.keep("stage", [this] { return static_cast<double>(stage_); }, [this](double v) {
    require(v >= 0 && v <= 4 && v == std::floor(v), "restart file: stage", v, "0, 1, 2, 3 or 4");
    stage_ = static_cast<ShearStage>(static_cast<int>(v));
  });
  r.keep("ball_count", ball_count_);
  r.keep("generated_porosity", generated_porosity_);
  r.keep("consolidated_height", consolidated_height_);
  r.keep("servo", [this] { return servo_ ? 1.0 : 0.0; }, [this](double v) { servo_record_.present = v > 0; });
  r.keep("servo_holding", [this] { return servo_ && servo_->holding_position() ? 1.0 : 0.0; },
         [this](double v) { servo_record_.holding = v > 0; });
  const double none = std::numeric_limits<double>::quiet_NaN();
  r.keep("servo_target", [this, none] { return servo_ ? servo_->settings().target_stress : none; },
         [this](double v) { servo_record_.target = v; });
  r.keep("servo_max_speed", [this, none] { return servo_ ? servo_->settings().max_speed : none; },
         [this](double v) { servo_record_.max_speed = v; });
  r.keep("servo_steps_on_target", [this] { return servo_ ? static_cast<double>(servo_->steps_on_target()) : 0.0; },
         [this](double v) {
           require(v >= 0 && v <= 9e15, "restart file: servo_steps_on_target", v, "a count of steps >= 0");
           servo_record_.steps_on_target = static_cast<std::int64_t>(v);
         });
  r.keep("generating", generating_);
  r.keep("generation_floor", generation_floor_);
  r.keep("generation_phase", generation_.phase);
  r.keep("generation_stage", generation_.stage);
  r.keep("generation_increment", generation_.increment);
  r.keep("generation_settled_steps", [this] { return static_cast<double>(generation_.settled_steps); },
         [this](double v) { generation_.settled_steps = static_cast<long>(v); });
  // The friction a generation had reached (a finished one ends on the configured friction).
  r.keep("friction_now", [this] { return friction_now_; }, [this](double v) { if (generating_) friction_now_ = v; });
  r.keep("rolling_friction_now", [this] { return rolling_friction_now_; },
         [this](double v) { if (generating_) rolling_friction_now_ = v; });
  r.keep("consolidating", consolidating_);
  r.keep("consolidation_start_step", consolidation_start_step_);
  for (const auto& [name, state] : {std::pair{"specimen_generated", &generated_state_}, std::pair{"specimen_consolidated", &consolidated_state_}}) {
    const std::string n = name;
    r.keep(n + "_porosity", state->porosity);
    r.keep(n + "_sphere_porosity", state->sphere_porosity);
    r.keep(n + "_coordination", state->coordination_number);
    r.keep(n + "_mechanical_coordination", state->mechanical_coordination_number);
    r.keep(n + "_vertical_stress", state->vertical_stress);
    r.keep(n + "_k0", state->k0);
    r.keep(n + "_height", state->height);
    r.keep(n + "_friction", state->friction);
    r.keep(n + "_rolling_friction", state->rolling_friction);
  }
}

void NgiSpecimen::set_contact_models(double friction, double rolling_friction, bool growing, ModelChange change) {
  friction_now_ = friction;
  rolling_friction_now_ = rolling_friction;
  set_contact_laws(world_, config_, friction, rolling_friction, growing, change);
}

// The cell's one controller, every step: the servo, the generation floor of the top plate, then
// the ring kinematics (rings.vertical), which read the plate velocities just set.
void NgiSpecimen::control(World& w) {
  if (servo_) (*servo_)(w);
  if (generation_floor_) keep_plate_gap(w, cell_, config_.specimen.height);  // the radii grow in the cavity
  move_rings(w, cell_, stage_ >= ShearStage::Generated);
  w.set_damping_frame(stage_ == ShearStage::Shearing ? shear_damping_frame(config_, w, cell_) : DampingFrame{});
}

void NgiSpecimen::generate() {
  require(stage_ == ShearStage::Empty, "generate() stage", static_cast<int>(stage_), "0 (empty world)");
  const auto t0 = std::chrono::steady_clock::now();
  std::ostream& log = run_.log();
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
    expansion.balls = ball_ids(world_.particles());  // in the order they were added
    expansion.diameters = diameters;
    expansion.stages = config_.generation.stages;
  } else {
    generated_porosity_ = 1.0 - solid / cavity;
    ball_count_ = diameters.size();
    log << "generation: " << ball_count_ << " balls, d = " << config_.grading.smallest() * 1e3 << "-"
        << config_.grading.largest() * 1e3 << " mm, porosity " << generated_porosity_ << ", H/d_max = "
        << height / config_.grading.largest() << "\n";
    expansion = add_expanding_balls(world_, Cylinder{radius, height}, diameters, config_.specimen.density,
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
  generated_state_ = state();
  release_rings(world_, cell_);
  set_contact_models(config_.ball_ball.friction(), config_.ball_ball.rolling_friction(), false);
  cement(CementAfter::Generation);
  stage_ = ShearStage::Generated;
  run_.add_wall_seconds(seconds_since(t0));
  log << "generation done in " << seconds_since(t0) << " s, " << world_.step_count() << " steps: porosity "
      << generated_state_.porosity << " (target " << config_.specimen.porosity << "), coordination "
      << generated_state_.coordination_number << ", K0 " << generated_state_.k0 << ", vertical stress "
      << generated_state_.vertical_stress / 1e3 << " kPa, height " << generated_state_.height * 1e3 << " mm\n";
  require_no_escape(0.0);
}

// Each stage grows the radii in small increments, then cycles towards equilibrium. The loop
// counters live in generation_, so that a restart file written between any two chunks resumes the
// generation where it was.
void NgiSpecimen::expand_radii(const RadiusExpansion& expansion) {
  GenerationProgress& g = generation_;
  for (; g.phase <= GenerationProgress::Settling && g.stage <= expansion.stages;
       ++g.stage, g.increment = 0, g.phase = GenerationProgress::Expanding) {
    while (g.phase == GenerationProgress::Expanding && g.increment < expansion.increments) {
      ++g.increment;
      set_radii(world_, expansion, expansion.factor(g.stage, g.increment));
      world_.step(expansion.steps_per_increment);
      if (g.increment == expansion.increments) g.phase = GenerationProgress::Settling, g.settled_steps = 0;
      run_.save_if_due();
    }
    settle_generation([&] { return world_.unbalanced_force_ratio() < config_.generation.equilibrium_ratio; });
    run_.log() << "[generation] stage " << g.stage << "/" << expansion.stages << ", radius x"
               << expansion.factor(g.stage, g.increment) << ", unbalanced ratio " << world_.unbalanced_force_ratio()
               << ", top plate " << world_.wall(cell_.top).normal_stress() / 1e3 << " kPa, porosity " << state().porosity
               << ", step " << world_.step_count() << std::endl;
  }
  if (g.phase <= GenerationProgress::Settling) g.phase = GenerationProgress::FirstSettle, g.settled_steps = 0;
}

void NgiSpecimen::settle_generation(const std::function<bool()>& done) {
  // Checked after each chunk, before a restart may be written: a resumed settle goes on exactly
  // when the uninterrupted one did.
  while (generation_.settled_steps < config_.generation.steps_per_stage) {
    world_.step(100);
    if (done()) break;
    generation_.settled_steps += 100;
    run_.save_if_due();
  }
  generation_.settled_steps = 0;
}

// A frictional packing grown against a low stress is looser than the target when its friction
// holds it open; lowering the friction step by step lets the servo plate settle it, until the
// porosity is within the tolerance of the target (docs/model.md 7.1). The plate cannot sink below
// the specimen height, so the porosity never falls below the target's.
void NgiSpecimen::friction_schedule() {
  const GenerationConfig& g_config = config_.generation;
  // A few kPa on a loose packing fluctuates by more than the consolidation tolerance, so settled
  // here means in equilibrium with the plate stress within 10 % of its target.
  auto settled = [&] {
    return world_.unbalanced_force_ratio() < g_config.equilibrium_ratio &&
           std::abs(servo_->achieved_stress() - g_config.stress) <= 0.1 * g_config.stress;
  };
  GenerationProgress& g = generation_;
  if (g.phase == GenerationProgress::FirstSettle) {
    settle_generation(settled);
    g.phase = GenerationProgress::Reducing;
  }
  const FrictionSchedule schedule = generation_friction_schedule(config_);
  while (true) {
    if (g.phase == GenerationProgress::Reducing) {
      const std::optional<Friction> next = next_friction(schedule, state().porosity, {friction_now_, rolling_friction_now_});
      if (!next) break;
      set_contact_models(next->sliding, next->rolling, true);
      g.phase = GenerationProgress::ScheduleSettle;
      g.settled_steps = 0;
    }
    settle_generation(settled);
    g.phase = GenerationProgress::Reducing;
    run_.log() << "[generation] friction schedule: mu " << friction_now_ << ", mu_r " << rolling_friction_now_ << ", porosity "
               << state().porosity << ", top plate " << world_.wall(cell_.top).normal_stress() / 1e3 << " kPa, step "
               << world_.step_count() << std::endl;
  }
  const SpecimenState now = state();
  std::ostream& log = run_.log();
  if (now.height <= config_.specimen.height * (1 + 1e-9) && servo_->achieved_stress() < 0.9 * g_config.stress)
    log << "note: the specimen settled onto the top plate's lowest position (specimen.height = " << config_.specimen.height
        << " m) at porosity " << now.porosity << ", ball-ball friction " << friction_now_ << ": the plate holds it at "
        << servo_->achieved_stress() << " Pa, not generation.stress = " << g_config.stress
        << " Pa: specimen.porosity is looser than the balls settle to at this friction\n";
  if (now.porosity > config_.specimen.porosity + g_config.porosity_tolerance)
    log << "note: the friction schedule reached zero friction at porosity " << now.porosity << ", above specimen.porosity = "
        << config_.specimen.porosity << " + " << g_config.porosity_tolerance << ": spheres of this grading settle no denser "
        << "at generation.stress = " << g_config.stress << " Pa within generation.steps_per_stage = "
        << g_config.steps_per_stage << " steps per schedule step; consolidation densifies the specimen further\n";
}

std::size_t NgiSpecimen::cement(CementAfter moment) {
  const CementationConfig& c = config_.cementation;
  if (c.after != moment) return 0;
  const std::size_t made = lab::cement(world_, bond_material(c, config_.specimen.seed), c.gap_ratio, c.fraction);
  world_.update_time_step();  // the bonds' stiffness counts in an automatic one
  const auto balls = static_cast<double>(std::max<std::size_t>(1, ball_count_));
  run_.log() << "cemented at step " << world_.step_count() << ": " << made << " bonds (" << 2.0 * static_cast<double>(made) / balls
             << " per ball), time step " << world_.time_step() << " s\n";
  return made;
}

void NgiSpecimen::consolidate() {
  require(stage_ == ShearStage::Generated, "consolidate() stage", static_cast<int>(stage_), "1 (generated)");
  const auto t0 = std::chrono::steady_clock::now();
  const ConsolidationTarget target = consolidation_target(config_, 10);
  if (!consolidating_) {
    if (!servo_) servo_ = std::make_shared<ServoWall>(cell_.top, servo_settings());
    start_consolidation(*servo_, target);
    consolidation_start_step_ = world_.step_count();
    consolidating_ = true;
  }
  const ConsolidationReport report = lab::consolidate(world_, *servo_, target, consolidation_start_step_, [&] {
    run_.save_if_due();
    std::ostringstream detail;
    detail << "step " << world_.step_count() << ", vertical stress " << servo_->achieved_stress() / 1e3 << " kPa (target "
           << target.vertical_stress / 1e3 << "), unbalanced ratio " << world_.unbalanced_force_ratio();
    run_.progress("consolidation", detail.str());
  });
  consolidating_ = false;
  std::ostream& log = run_.log();
  if (!report.settled)
    log << "warning: consolidation did not settle within consolidation.max_steps = " << config_.consolidation.max_steps
        << " (stress " << servo_->achieved_stress() << " Pa, target " << config_.consolidation.vertical_stress << " Pa)\n";
  consolidated_height_ = cell_.plate_gap(world_);
  consolidated_state_ = state();
  stage_ = ShearStage::Consolidated;
  run_.add_wall_seconds(seconds_since(t0));
  log << "consolidation done in " << seconds_since(t0) << " s: H_c = " << consolidated_height_ * 1e3
      << " mm, vertical stress " << world_.wall(cell_.top).normal_stress() / 1e3 << " kPa, porosity "
      << consolidated_state_.porosity << ", coordination " << consolidated_state_.coordination_number << ", K0 "
      << consolidated_state_.k0 << "\n";
  require_no_escape(0.0);
}

void NgiSpecimen::reconsolidate() {
  require(stage_ == ShearStage::Consolidated, "reconsolidate() stage", static_cast<int>(stage_), "2 (consolidated)");
  world_.update_time_step();  // the restart's step belongs to the stiffness it was written with
  stage_ = ShearStage::Generated;
  if (servo_) {
    servo_->hold_position(false);
    servo_->set_max_speed(config_.consolidation.servo_max_speed);  // the consolidation's cap, not the shear's
  }
  consolidate();
}

void NgiSpecimen::load(const std::filesystem::path& file, ResumeIntent intent) {
  // The walls, rings and contact models are as configured (the constructor's); the file supplies the state.
  const World as_configured = world_;
  const ProtocolRecord& record = run_.load(file);
  if (!record.has("specimen_generated_porosity"))  // files written before the states were kept
    for (SpecimenState* s : {&generated_state_, &consolidated_state_}) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      *s = {nan, nan, nan, nan, nan, nan, nan, nan, nan};
    }
  if (servo_record_.present) {
    ServoSettings servo = servo_settings();
    if (record.has("servo_target")) servo.target_stress = servo_record_.target, servo.max_speed = servo_record_.max_speed;
    servo_ = std::make_shared<ServoWall>(cell_.top, servo);
    servo_->hold_position(servo_record_.holding);
    if (record.has("servo_steps_on_target")) servo_->resume_steps_on_target(servo_record_.steps_on_target);
  }
  if (generating_) {
    const GenerationProgress& g = generation_;
    require(g.phase >= GenerationProgress::Expanding && g.phase <= GenerationProgress::ScheduleSettle,
            "restart file: generation_phase", g.phase, "0 to 4");
    require(g.stage >= 1 && g.increment >= 0 && g.increment <= 10 && g.settled_steps >= 0,
            "restart file: generation_stage, generation_increment, generation_settled_steps",
            std::to_string(g.stage) + ", " + std::to_string(g.increment) + ", " + std::to_string(g.settled_steps),
            "a stage >= 1, an increment in 0..10 and a step count >= 0");
  }
  if (!record.configuration.empty() && !run_.configuration().empty()) {  // a file or a run without a record
    const std::vector<ResumeChange> changes = check_resume(run_.schema(), record.configuration, run_.configuration(), progress(),
                                                           intent == ResumeIntent::Reconsolidate, "restart file " + file.string(), true);
    for (const ResumeChange& c : changes) run_.note_change(c.key, c.file_value, c.new_value);
  }
  if (!generating_) require_configured_grading(world_, config_, file);  // balls still growing are smaller than the grading's
  apply_restart_keys(world_, as_configured, cell_, config_, file, run_.log());
  // A generation resumes with the friction it had reached; the contact lists and their history
  // stay as the file has them (no rebuild that the uninterrupted run did not do).
  if (generating_) set_contact_models(friction_now_, rolling_friction_now_, true, ModelChange::KeepContacts);
  if (stage_ >= ShearStage::Generated) release_rings(world_, cell_);  // rings.vertical from this configuration
}

RunProgress NgiSpecimen::progress() const {
  if (stage_ == ShearStage::Consolidated && beyond_consolidation_ && beyond_consolidation_()) return RunProgress::Shearing;
  switch (stage_) {
    case ShearStage::Empty: return RunProgress::Generating;
    case ShearStage::Generated: return consolidating_ ? RunProgress::Consolidating : RunProgress::Generated;
    case ShearStage::Consolidated: return RunProgress::Consolidated;
    case ShearStage::Shearing: return RunProgress::Shearing;
    case ShearStage::Done: return RunProgress::Done;
  }
  return RunProgress::Generating;
}

ServoSettings NgiSpecimen::servo_settings() const {
  ServoSettings servo = consolidation_servo(config_);
  if (stage_ >= ShearStage::Consolidated) servo.max_speed = shear_servo_speed();
  return servo;
}

double NgiSpecimen::shear_rate() const { return shear_strain_rate(config_, world_); }

double NgiSpecimen::inertial_number() const {
  return shear_rate() * mean_ball_diameter(world_, config_.grading.largest()) *
         std::sqrt(config_.specimen.density / config_.consolidation.vertical_stress);
}

double NgiSpecimen::shear_servo_speed() const { return lab::shear_servo_speed(config_, shear_rate(), consolidated_height_); }

void NgiSpecimen::require_no_escape(double shear_strain) const { lab::require_no_escape(world_, cell_, shear_strain); }

}  // namespace dem::lab
