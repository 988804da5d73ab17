// The simple-shear protocol: world set-up, generation, consolidation and shear. Measurements,
// outputs and restart files are in simple_shear_outputs.cpp.
#include <dem/lab/simple_shear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <random>
#include <unordered_map>

#include <dem/boundary/clump_ring.hpp>
#include <dem/contact/linear_law.hpp>
#include <dem/core/errors.hpp>
#include <dem/geometry/mesh.hpp>
#include <dem/lab/fabric_log.hpp>
#include <dem/lab/snapshots.hpp>

namespace dem::lab {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

RollingLinearLaw::Params law_params(const ContactTypeConfig& c, double friction, double rolling_friction) {
  auto p = RollingLinearLaw::Params::deformable(c.effective_modulus, c.stiffness_ratio, friction, rolling_friction);
  p.normal_damping_ratio = c.normal_damping_ratio;
  p.shear_damping_ratio = c.shear_damping_ratio;
  return p;
}

std::vector<std::string> history_columns(std::size_t rings, int bins) {
  std::vector<std::string> c = {
      "time", "step", "stage", "shear_strain_x", "shear_strain_y", "shear_strain", "shear_stress_x", "shear_stress_y",
      "shear_stress", "shear_stress_bottom", "vertical_stress", "vertical_stress_bottom", "height",
      "volumetric_strain", "lateral_stress", "k0", "sigma_1", "sigma_2", "sigma_3", "principal_rotation_deg",
      "ms_sxx", "ms_syy", "ms_szz", "ms_sxy", "ms_sxz", "ms_syz", "ms_shear_stress", "coordination_number",
      "contacts", "mean_contact_force", "porosity", "kinetic_energy", "inertial_number",
      // uniformity and the study's non-coaxiality (docs/model.md 8.1)
      "specimen_porosity", "balls_outside", "contacts_within_detection", "mechanical_coordination_number",
      "strain_rate_direction_deg", "non_coaxiality_deg", "profile_r2", "strain_bottom_third", "strain_middle_third",
      "strain_top_third", "top_bottom_strain_ratio", "bottom_dx", "bottom_dy", "top_dx", "top_dy"};
  for (const char* layer : {"bottom", "middle", "top"})
    for (const char* what : {"stress_ratio", "porosity"}) c.push_back(std::string("layer_") + layer + "_" + what);
  for (int b = 0; b < bins; ++b) c.push_back("profile_u_" + std::to_string(b + 1));
  for (int b = 0; b < bins; ++b) c.push_back("profile_porosity_" + std::to_string(b + 1));
  for (std::size_t k = 0; k < rings; ++k)
    for (const char* axis : {"dx", "dy"}) c.push_back("ring_" + std::to_string(k + 1) + "_" + axis);
  return c;
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
    : config_(std::move(config)), out_dir_(std::move(out_dir)), log_(log), history_(std::vector<std::string>{"time"}) {
  config_.validate();
  legs_ = config_.shear.legs();
  require(config_.shear.total_strain() > 0.0, "shear strain", config_.shear.total_strain(), "> 0");
  fabric_ = std::make_unique<FabricLog>(out_dir_ / "fabric.csv");
  snapshots_ = std::make_unique<SnapshotWriter>(out_dir_ / "snapshots");
  build_world();
  history_ = io::CsvTable(history_columns(world_->clumps().size(), config_.measure.profile_bins), io::Missing::Allowed);
}

SimpleShearTest::~SimpleShearTest() = default;

void SimpleShearTest::build_world() {
  WorldSettings s;
  s.local_damping = config_.engine.local_damping;
  s.time_step = config_.engine.time_step;
  s.time_step_safety = config_.engine.time_step_safety;
  s.max_overlap_ratio = config_.engine.max_overlap_ratio;
  s.threads = config_.engine.threads;
  world_ = std::make_unique<World>(s);
  const double radius = config_.specimen.diameter / 2, height = config_.specimen.height;
  area_ = pi * radius * radius;
  const double pebble_d = config_.rings.pebble_diameter > 0 ? config_.rings.pebble_diameter : config_.grading.smallest();

  // Plates: discs reaching under the rings, loaded over the specimen's cross-section.
  const double plate_radius = radius + 2.0 * pebble_d;
  bottom_ = world_->add_wall(make_facet_wall("bottom", geometry::make_disc(Vec3::Zero(), plate_radius, -Vec3::UnitZ(), 24),
                                             -Vec3::UnitZ(), area_));
  top_ = world_->add_wall(make_facet_wall("top", geometry::make_disc(Vec3(0, 0, height), plate_radius, Vec3::UnitZ(), 24),
                                          Vec3::UnitZ(), area_));
  RingStackSpec rings;
  rings.inner_radius = radius;
  // Fixed rings cannot follow a dilating specimen: their stack is built with room above it.
  rings.height = config_.rings.stack_height > 0 ? config_.rings.stack_height
                 : config_.rings.vertical == RingVertical::Fixed ? 1.1 * height : height;
  rings.ring_height = pebble_d;
  rings.pebble_radius = pebble_d / 2;
  rings.gap = config_.rings.gap > 0 ? config_.rings.gap : 0.05 * pebble_d;
  rings.ring_density = config_.rings.density;
  rings.max_opening = config_.grading.smallest();
  rings.fixed = dof_all;  // held while the specimen is generated; released afterwards
  pebble_radius_ = rings.pebble_radius;
  for (const ClumpSpec& ring : make_ring_stack(rings)) world_->add_clump(ring);
  set_contact_models(config_.ball_ball.friction, config_.ball_ball.rolling_friction, false);
  servo_.reset();
  world_->add_controller([this](World& w) { control(w); });
}

void SimpleShearTest::set_contact_models(double friction, double rolling_friction, bool growing, ModelChange change) {
  friction_now_ = friction;
  rolling_friction_now_ = rolling_friction;
  auto set = [&](ContactKind kind, std::shared_ptr<const ContactModel> model) {
    if (change == ModelChange::KeepContacts) world_->retune_contact_model(kind, std::move(model));
    else world_->set_contact_model(kind, std::move(model));
  };
  set(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(law_params(config_.ball_ball, friction, rolling_friction), "ball_ball"));
  auto boundary = [&](const ContactTypeConfig& c) {
    return growing ? law_params(c, 0.0, 0.0) : law_params(c, c.friction, c.rolling_friction);
  };
  set(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(boundary(config_.ball_facet), "ball_facet"));
  set(ContactKind::BallPebble, make_contact_model<RollingLinearLaw>(boundary(config_.ball_pebble), "ball_pebble"));
}

double SimpleShearTest::plate_gap() const {
  return (config_.specimen.height + world_->wall(top_).displacement.z()) - world_->wall(bottom_).displacement.z();
}

void SimpleShearTest::control(World& w) {
  if (servo_) (*servo_)(w);
  if (generation_floor_) {
    // While the radii grow, the servo may lift the plate but never lower it below the specimen
    // height: a plate that chased the stress into the loose half-size balls would pack them at
    // the bottom of the cavity.
    FacetWall& top = w.wall(top_);
    const double room = plate_gap() - config_.specimen.height;  // m, >= 0
    top.velocity.z() = std::max(top.velocity.z(), -room / w.time_step());
  }
  move_rings(w);
}

// docs/model.md 4: with rings.vertical = follow, ring k keeps its fraction s_k = (z_k - z_b) / H
// of the height between the plates: v_k,z = v_b,z + s_k (v_t,z - v_b,z), so z_k - z_b - s_k H is
// invariant under the step (both move by v dt). Prescribed rings also interpolate horizontally.
void SimpleShearTest::move_rings(World& w) const {
  if (config_.rings.vertical == RingVertical::Fixed) return;
  // Free rings follow the plates only while the specimen is made; then the sand carries them.
  if (config_.rings.vertical == RingVertical::Free && stage_ >= ShearStage::Generated) return;
  const FacetWall& top = w.wall(top_);
  const FacetWall& bottom = w.wall(bottom_);
  const double z_bottom = bottom.displacement.z(), gap = plate_gap();
  const bool prescribed = config_.rings.vertical == RingVertical::Prescribed && stage_ >= ShearStage::Generated;
  // Sand rings: the mean vertical velocity of the balls touching each ring (the interpolation
  // while the specimen is made, or for a ring that touches none).
  std::vector<double> sand_vz, touching;
  if (config_.rings.vertical == RingVertical::Sand && stage_ >= ShearStage::Generated) {
    sand_vz.assign(w.clumps().size(), 0.0);
    touching.assign(w.clumps().size(), 0.0);
    const PairContacts& pebbles = w.pair_contacts(ContactKind::BallPebble);
    const ParticleStore& p = w.particles();
    for (std::size_t k = 0; k < pebbles.size(); ++k) {
      if (!pebbles.touching[k]) continue;
      const auto ring = static_cast<std::size_t>(p.clump[static_cast<std::size_t>(pebbles.second[k])]);
      sand_vz[ring] += p.v[static_cast<std::size_t>(pebbles.first[k])].z();
      touching[ring] += 1.0;
    }
  }
  for (std::size_t k = 0; k < w.clumps().size(); ++k) {
    Clump& ring = w.clumps()[k];
    const double s = (ring.x.z() - z_bottom) / gap;
    const Vec3 v = bottom.velocity + s * (top.velocity - bottom.velocity);
    ring.v.z() = !touching.empty() && touching[k] > 0 ? sand_vz[k] / touching[k] : v.z();
    if (prescribed) ring.v.x() = v.x(), ring.v.y() = v.y();
  }
}

void SimpleShearTest::release_rings() {
  const std::uint8_t fixed = config_.rings.vertical == RingVertical::Prescribed ? dof_all
                             : config_.rings.vertical == RingVertical::Free     ? dof_rotation
                                                                               : dof_z | dof_rotation;
  for (Clump& ring : world_->clumps()) {
    ring.fixed = fixed;
    if (config_.rings.vertical == RingVertical::Fixed) ring.v.z() = 0.0;
  }
}

std::vector<double> SimpleShearTest::target_diameters(std::mt19937_64& rng) const {
  const double radius = config_.specimen.diameter / 2;
  return sample_diameters(config_.grading, (1.0 - config_.specimen.porosity) * pi * radius * radius * config_.specimen.height, rng);
}

void SimpleShearTest::generate() {
  require(stage_ == ShearStage::Empty, "generate() stage", static_cast<int>(stage_), "0 (empty world)");
  open_outputs_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  const double radius = config_.specimen.diameter / 2, height = config_.specimen.height;
  const double cavity = pi * radius * radius * height;
  std::mt19937_64 rng(config_.specimen.seed);  // the diameters, then the positions
  const std::vector<double> diameters = target_diameters(rng);
  double solid = 0.0;
  for (double d : diameters) solid += pi / 6 * d * d * d;
  if (generating_) {  // resumed from a restart file written during the generation
    require(diameters.size() == ball_count_, "grading and specimen.seed", std::to_string(diameters.size()) + " balls",
            "the " + std::to_string(ball_count_) + " balls of the restart file's generation");
  } else {
    generated_porosity_ = 1.0 - solid / cavity;
    ball_count_ = diameters.size();
    log_ << "generation: " << ball_count_ << " balls, d = " << config_.grading.smallest() * 1e3 << "-"
         << config_.grading.largest() * 1e3 << " mm, porosity " << generated_porosity_ << ", H/d_max = "
         << height / config_.grading.largest() << "\n";
    place_half_size_balls(diameters, rng);
    // Expansion to full size in stages, with the generation friction on the ball-ball contacts
    // (plates and rings frictionless), cycling towards equilibrium in between. With the servo
    // plate the specimen grows against a low stress instead of a closed cavity.
    set_contact_models(config_.generation_friction(), config_.generation_rolling_friction(), true);
    if (config_.generation.plate == GenerationPlate::Servo) {
      ServoSettings servo = servo_settings();
      servo.target_stress = config_.generation.stress;
      servo.max_speed = config_.generation.servo_max_speed;
      servo_ = std::make_shared<ServoWall>(top_, servo);
      generation_floor_ = true;
    }
    generating_ = true;
    generation_ = {};
  }
  expand_radii(diameters);
  if (config_.generation.plate == GenerationPlate::Servo) friction_schedule();
  generating_ = false;
  generation_ = {};  // as a run resumed after the generation has it
  generation_floor_ = false;
  generated_state_ = specimen_state();
  release_rings();
  set_contact_models(config_.ball_ball.friction, config_.ball_ball.rolling_friction, false);
  stage_ = ShearStage::Generated;
  wall_seconds_ += seconds_since(t0);
  log_ << "generation done in " << seconds_since(t0) << " s, " << world_->step_count() << " steps: porosity "
       << generated_state_.porosity << " (target " << config_.specimen.porosity << "), coordination "
       << generated_state_.coordination_number << ", K0 " << generated_state_.k0 << ", vertical stress "
       << generated_state_.vertical_stress / 1e3 << " kPa, height " << generated_state_.height * 1e3 << " mm\n";
  require_no_escape();
}

void SimpleShearTest::place_half_size_balls(const std::vector<double>& diameters, std::mt19937_64& rng) {
  // Half-size balls at random, without overlap (solid fraction (1 - n)/8 ~ 0.08: few rejections).
  const double radius = config_.specimen.diameter / 2, height = config_.specimen.height;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double cell = config_.grading.largest() / 2;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;
  auto key = [&](int i, int j, int k) {
    return (static_cast<std::int64_t>(i) * 4096 + j) * 4096 + k;
  };
  std::vector<Vec3> placed;
  std::vector<double> placed_r;
  for (std::size_t n = 0; n < diameters.size(); ++n) {
    const double r = diameters[n] / 4;  // half the target radius
    for (int attempt = 0;; ++attempt) {
      require(attempt < 100000, "generation", "(no room)", "a cavity large enough for the balls at half size");
      const Vec3 x((2 * unit(rng) - 1) * (radius - r), (2 * unit(rng) - 1) * (radius - r), r + unit(rng) * (height - 2 * r));
      if (x.head<2>().norm() > radius - r) continue;
      const int ci = static_cast<int>(std::floor(x.x() / cell)) + 2048, cj = static_cast<int>(std::floor(x.y() / cell)) + 2048,
                ck = static_cast<int>(std::floor(x.z() / cell));
      bool clear = true;
      for (int a = -1; a <= 1 && clear; ++a)
        for (int b = -1; b <= 1 && clear; ++b)
          for (int c = -1; c <= 1 && clear; ++c) {
            const auto it = cells.find(key(ci + a, cj + b, ck + c));
            if (it == cells.end()) continue;
            for (std::size_t other : it->second)
              if ((placed[other] - x).norm() < placed_r[other] + r) clear = false;
          }
      if (!clear) continue;
      cells[key(ci, cj, ck)].push_back(placed.size());
      placed.push_back(x);
      placed_r.push_back(r);
      break;
    }
  }
  for (std::size_t n = 0; n < placed.size(); ++n) {
    BallSpec b;
    b.position = placed[n];
    b.radius = placed_r[n];
    b.density = config_.specimen.density;
    world_->add_ball(b);
  }
}

// Each stage grows the radii in small increments (a jump would overlap neighbours by a large
// fraction of a radius and trip the instability check), then cycles towards equilibrium. The
// loop counters live in generation_, so that a restart file written between any two chunks
// resumes the generation where it was.
void SimpleShearTest::expand_radii(const std::vector<double>& diameters) {
  constexpr int increments = 10;
  constexpr std::int64_t steps_per_increment = 50;
  // The balls' ids in the order they were added, the order of `diameters` (store indices change
  // when the store sorts itself, ids do not).
  const std::vector<ParticleId> ids = ball_ids(world_->particles());
  require(ids.size() == diameters.size(), "generation: balls in the world", ids.size(),
          std::to_string(diameters.size()) + ", one per target diameter");
  GenerationProgress& g = generation_;
  auto factor = [&] { return 0.5 + 0.5 * ((g.stage - 1) + static_cast<double>(g.increment) / increments) / config_.generation.stages; };
  for (; g.phase <= GenerationProgress::Settling && g.stage <= config_.generation.stages;
       ++g.stage, g.increment = 0, g.phase = GenerationProgress::Expanding) {
    while (g.phase == GenerationProgress::Expanding && g.increment < increments) {
      ++g.increment;
      ParticleStore& p = world_->particles();
      for (std::size_t n = 0; n < ids.size(); ++n) p.set_radius(p.index_of(ids[n]), factor() * diameters[n] / 2);
      world_->invalidate_contacts();
      world_->update_time_step();
      world_->step(steps_per_increment);
      if (g.increment == increments) g.phase = GenerationProgress::Settling, g.settled_steps = 0;
      maybe_save_restart();
    }
    settle_generation([&] { return world_->unbalanced_force_ratio() < config_.generation.equilibrium_ratio; });
    std::ostringstream detail;
    detail << "stage " << g.stage << "/" << config_.generation.stages << ", radius x" << factor() << ", unbalanced ratio "
           << world_->unbalanced_force_ratio() << ", top plate " << world_->wall(top_).normal_stress() / 1e3
           << " kPa, porosity " << specimen_state().porosity;
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
  const double smallest = 1e-2 * std::max(config_.generation_friction(), config_.generation_rolling_friction());
  while (true) {
    if (g.phase == GenerationProgress::Reducing) {
      double mu = friction_now_, mu_r = rolling_friction_now_;
      if (!(specimen_state().porosity > config_.specimen.porosity + config_.generation.porosity_tolerance && (mu > 0 || mu_r > 0))) break;
      mu *= config_.generation.friction_reduction;
      mu_r *= config_.generation.friction_reduction;
      if (std::max(mu, mu_r) < smallest) mu = mu_r = 0.0;
      set_contact_models(mu, mu_r, true);
      g.phase = GenerationProgress::ScheduleSettle;
      g.settled_steps = 0;
    }
    settle_generation(settled);
    g.phase = GenerationProgress::Reducing;
    log_ << "[generation] friction schedule: mu " << friction_now_ << ", mu_r " << rolling_friction_now_ << ", porosity "
         << specimen_state().porosity << ", top plate " << world_->wall(top_).normal_stress() / 1e3 << " kPa" << std::endl;
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
  if (!consolidating_) {
    if (!servo_) servo_ = std::make_shared<ServoWall>(top_, servo_settings());
    servo_->set_target(config_.consolidation.vertical_stress);
    servo_->set_max_speed(config_.consolidation.servo_max_speed);
    consolidation_start_step_ = world_->step_count();
    consolidating_ = true;
  }
  bool settled = false;
  while (world_->step_count() - consolidation_start_step_ < config_.consolidation.max_steps) {
    world_->step(chunk_steps);
    settled = servo_->settled() && world_->unbalanced_force_ratio() < config_.generation.equilibrium_ratio;
    if (settled) break;
    maybe_save_restart();
    std::ostringstream detail;
    detail << "step " << world_->step_count() << ", vertical stress " << servo_->achieved_stress() / 1e3 << " kPa (target "
           << config_.consolidation.vertical_stress / 1e3 << "), unbalanced ratio " << world_->unbalanced_force_ratio();
    progress("consolidation", detail.str());
  }
  consolidating_ = false;
  if (!settled)
    log_ << "warning: consolidation did not settle within consolidation.max_steps = " << config_.consolidation.max_steps
         << " (stress " << servo_->achieved_stress() << " Pa, target " << config_.consolidation.vertical_stress << " Pa)\n";
  const FacetWall& top = world_->wall(top_);
  const FacetWall& bottom = world_->wall(bottom_);
  consolidated_height_ = (config_.specimen.height + top.displacement.z()) - bottom.displacement.z();
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
  ServoSettings servo;
  servo.target_stress = config_.consolidation.vertical_stress;
  servo.relaxation = config_.consolidation.servo_relaxation;
  servo.max_speed = stage_ >= ShearStage::Consolidated ? shear_servo_speed() : config_.consolidation.servo_max_speed;
  servo.settle_tolerance = config_.consolidation.tolerance;
  servo.settle_steps = static_cast<int>(config_.consolidation.settle_steps);
  return servo;
}

double SimpleShearTest::shear_servo_speed() const {
  if (config_.shear.servo_max_speed > 0.0) return config_.shear.servo_max_speed;
  return std::max(config_.consolidation.servo_max_speed, shear_rate() * consolidated_height_);
}

double SimpleShearTest::mean_diameter() const {
  const ParticleStore& p = world_->particles();
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) sum += 2 * p.radius[i], ++n;
  return n > 0 ? sum / static_cast<double>(n) : config_.grading.largest();
}

Vec3 SimpleShearTest::leg_direction(std::size_t leg) const {
  const double a = legs_.at(leg).direction_deg * pi / 180.0;
  return Vec3(std::cos(a), std::sin(a), 0.0);
}

double SimpleShearTest::shear_rate() const {
  if (config_.shear.strain_rate > 0.0) return config_.shear.strain_rate;
  // I = gamma_dot d_mean sqrt(rho / p) (docs/model.md 3.4)
  return config_.shear.inertial_number / (mean_diameter() * std::sqrt(config_.specimen.density / config_.consolidation.vertical_stress));
}

double SimpleShearTest::inertial_number() const {
  return shear_rate() * mean_diameter() * std::sqrt(config_.specimen.density / config_.consolidation.vertical_stress);
}

void SimpleShearTest::start_leg() {
  const double speed = shear_rate() * consolidated_height_;  // m/s of the bottom plate relative to the top
  const double share = (config_.shear.moving_plate == MovingPlate::Both) ? 0.5 : 1.0;
  FacetWall& bottom = world_->wall(bottom_);
  bottom.velocity = share * speed * leg_direction(leg_);
  FacetWall& top = world_->wall(top_);
  const Vec3 top_horizontal = (share - 1.0) * speed * leg_direction(leg_);
  top.velocity.x() = top_horizontal.x();
  top.velocity.y() = top_horizontal.y();
  servo_->hold_position(config_.shear.mode == ShearMode::ConstantVolume);
  servo_->set_max_speed(shear_servo_speed());
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
    path_strain_ = 0.0;
    steps_at_shear_start_ = world_->step_count();
    const FacetWall& top = world_->wall(top_);
    const FacetWall& bottom = world_->wall(bottom_);
    previous_relative_ = bottom.displacement - top.displacement;
    previous_relative_.z() = 0.0;
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
  const double strain_before = path_strain_;  // a resumed run has done part of the path already
  while (leg_ < legs_.size()) {
    world_->step(chunk_steps);
    const FacetWall& top = world_->wall(top_);
    const FacetWall& bottom = world_->wall(bottom_);
    Vec3 relative = bottom.displacement - top.displacement;
    relative.z() = 0.0;
    path_strain_ += (relative - previous_relative_).norm() / consolidated_height_;
    previous_relative_ = relative;
    const bool leg_done = path_strain_ - leg_start_strain_ >= legs_[leg_].strain * (1 - 1e-12);
    if (leg_done) {
      leg_start_strain_ += legs_[leg_].strain;
      ++leg_;
      if (leg_ < legs_.size()) start_leg();
    }
    record_outputs(leg_ == legs_.size());
    maybe_save_restart();
    const double elapsed = seconds_since(t0);
    // Time left from this run's own pace, over the strain still to go.
    const double strain_done = path_strain_ - strain_before;
    const double strain_left = std::max(0.0, config_.shear.total_strain() - path_strain_);
    std::ostringstream detail;
    detail.precision(4);
    const std::int64_t steps = world_->step_count() - steps_before;
    detail << "strain " << path_strain_ << " of " << config_.shear.total_strain() << ", tau "
           << (history_.rows().empty() ? 0.0 : history_.rows().back()[history_.column_index("shear_stress")]) / 1e3
           << " kPa, sigma_v " << world_->wall(top_).normal_stress() / 1e3 << " kPa, "
           << static_cast<double>(steps) * static_cast<double>(world_->particles().size()) / std::max(elapsed, 1e-9)
           << " particle-steps/s, " << (strain_done > 0 ? elapsed * strain_left / strain_done : 0.0) << " s left";
    progress("shear", detail.str());
  }
  stage_ = ShearStage::Done;
  world_->wall(bottom_).velocity.setZero();
  world_->wall(top_).velocity.x() = world_->wall(top_).velocity.y() = 0.0;
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
