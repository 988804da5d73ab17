// World: building, the step loop, the clock and the time step. The broad phase is BroadPhase
// (broad_phase.cpp), the threads' shares StepPlan (step_plan.cpp), the subdomains of a World spread
// over processes parallel::Subdomains (world_domains.cpp delegates); forces are in world_forces.cpp,
// integration and stability checks in world_integrate.cpp, queries in world_query.cpp; restart
// files in io/world_state.cpp.
#include <dem/core/world.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <omp.h>

#include <dem/base/errors.hpp>

namespace dem {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

World::World(WorldSettings settings) {
  require_non_negative("time_step", settings.time_step);
  require(settings.time_step_safety > 0.0 && settings.time_step_safety <= 1.0, "time_step_safety",
          settings.time_step_safety, "in (0, 1]");
  require(settings.local_damping >= 0.0 && settings.local_damping < 1.0, "local_damping", settings.local_damping,
          "in [0, 1)");
  require(settings.gravity.allFinite(), "gravity", "(non-finite)", "finite");
  require_non_negative("skin", settings.skin);
  require_non_negative("near_skin", settings.near_skin);
  require(settings.threads >= 0, "threads", settings.threads, ">= 0 (0: OMP_NUM_THREADS)");
  require_positive("max_overlap_ratio", settings.max_overlap_ratio);
  require_positive("max_step_travel_ratio", settings.max_step_travel_ratio);
  state_.settings = settings;
  team_ = ThreadTeam(settings.threads > 0 ? settings.threads : omp_get_max_threads(), settings.adapt_threads);
  threads_ = team_.size();
  state_.clock.dt = settings.time_step;
}

ParticleId World::add_ball(const BallSpec& spec) {
  state_.rebuild.need_rebuild = true;
  pebble_layout_stale_ = true;
  return state_.particles.add(spec);
}

ClumpId World::add_clump(const ClumpSpec& spec) {
  require(!state_.cell, "a clump in a World with a periodic cell", "refused",
          "none: clumps are not supported in a periodic cell yet (their pebbles would wrap one by one)");
  const ClumpId cid = static_cast<ClumpId>(state_.clumps.size());
  spec.validate("clump " + std::to_string(cid));
  Clump c;
  c.mass = spec.mass;
  c.x = spec.centre_of_mass;
  c.v = spec.velocity;
  c.w = spec.angular_velocity;
  c.inertia_body = spec.inertia;
  c.inv_inertia_body = spec.inertia.inverse();
  c.fixed = spec.fixed;
  for (const PebbleSpec& p : spec.pebbles) {
    BallSpec b;
    b.position = p.position;
    b.radius = p.radius;
    b.group = spec.group;
    b.fixed = dof_all;  // pebbles are moved by their clump, never integrated on their own
    const ParticleId pid = state_.particles.add(b, cid);
    const std::size_t i = state_.particles.index_of(pid);
    state_.particles.inv_mass[i] = 1.0 / spec.mass;
    c.pebbles.push_back(pid);
    c.pebble_offsets.push_back(p.position - spec.centre_of_mass);
  }
  state_.clumps.push_back(std::move(c));
  pebble_layout_stale_ = true;
  update_pebbles();
  state_.rebuild.need_rebuild = true;
  return cid;
}

WallId World::add_wall(Wall wall) {
  require(!state_.cell, "wall '" + wall.name + "' in a World with a periodic cell", "refused",
          "none: the cell is periodic on every axis (x y z), and a wall would cut the tiling; walls across "
          "a non-periodic axis are not supported yet");
  state_.walls.push_back(std::move(wall));
  state_.rebuild.need_rebuild = true;
  return static_cast<WallId>(state_.walls.size() - 1);
}

void World::set_periodic_cell(const PeriodicCell& cell) {
  require(cell.periodic_axes() == std::array<bool, 3>{true, true, true}, "periodic cell axes",
          axis_names(cell.periodic_axes()), "x y z (periodic on all three axes: the only cell supported for now)");
  require(state_.walls.empty(), "periodic cell with walls", std::to_string(state_.walls.size()) + " walls",
          "no walls: the cell is periodic on every axis (x y z), and a wall would cut the tiling");
  require(state_.clumps.empty(), "periodic cell with clumps", std::to_string(state_.clumps.size()) + " clumps",
          "no clumps: clumps are not supported in a periodic cell yet (their pebbles would wrap one by one)");
  require(ranks() <= 1, "periodic cell in a World spread over processes", std::to_string(ranks()) + " processes",
          "one process: the subdomains do not wrap across the cell's faces yet");
  state_.cell = cell;
  state_.rebuild.need_rebuild = true;
}

void World::set_velocity_gradient(const Mat3& velocity_gradient) {
  require(state_.cell.has_value(), "velocity gradient", "set", "set on a World with a periodic cell (set_periodic_cell first)");
  state_.cell->set_velocity_gradient(velocity_gradient);
}

void World::set_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model) {
  require(model != nullptr, std::string("contact model for ") + to_string(kind), "null", "a model");
  models_[static_cast<std::size_t>(kind)] = std::move(model);
  state_.rebuild.need_rebuild = true;  // states are re-created for the new law at the next rebuild
}

void World::retune_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model) {
  require(model != nullptr, std::string("contact model for ") + to_string(kind), "null", "a model");
  const ContactModel* now = models_[static_cast<std::size_t>(kind)].get();
  require(now != nullptr && std::string(now->law_name()) == model->law_name(),
          std::string("retuned contact model for ") + to_string(kind), model->law_name(),
          std::string("the law in use, ") + (now ? now->law_name() : "(none)"));
  models_[static_cast<std::size_t>(kind)] = std::move(model);
}

void World::set_time_step(double dt) {
  require_positive("time_step", dt);
  state_.settings.time_step = dt;
  state_.clock.dt = dt;
}

void World::set_local_damping(double alpha) {
  require(alpha >= 0.0 && alpha < 1.0, "local_damping", alpha, "in [0, 1)");
  state_.settings.local_damping = alpha;
}

void World::set_damping_frame(const DampingFrame& frame) {
  require(frame.velocity.allFinite() && std::isfinite(frame.height) && frame.velocity_gradient.allFinite(),
          "damping frame", "a non-finite value", "finite velocity, height and velocity gradient");
  damping_frame_ = frame;
}

void World::set_max_overlap_ratio(double ratio) {
  require(std::isfinite(ratio) && ratio > 0.0, "max_overlap_ratio", ratio, "finite and > 0");
  state_.settings.max_overlap_ratio = ratio;
}

void World::add_controller(std::function<void(World&)> controller) { controllers_.push_back(std::move(controller)); }

void World::add_callback(std::int64_t every, std::function<void(World&)> callback) {
  require(every > 0, "callback interval", every, "> 0 steps");
  callbacks_.emplace_back(every, std::move(callback));
}

void World::step(std::int64_t n, StepEnd end) {
  for (std::int64_t s = 0; s < n; ++s) {
    auto t0 = std::chrono::steady_clock::now();
    const auto step_start = t0;
    if (team_.size() != threads_) {  // the team changed size: share the loops out again
      threads_ = team_.size();
      plan_.forget_shares();
    }
    if (BroadPhase::needs_rebuild(state_)) {
      synchronise();  // spread over processes: each makes the same lists from the whole state
      synchronise_history();
      timing_.communication += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      rebuild(state_.settings.sort_every > 0 && state_.rebuild.rebuilds % state_.settings.sort_every == 0);
    }
    plan_domains();
    if (broad_phase_.near_stale(state_)) {
      broad_phase_.refresh_near(state_, plan_, threads_);
      keep_local_near();
    }
    if (state_.clock.dt <= 0.0) update_time_step();
    timing_.rebuilds += seconds_since(t0);
    copies_go_stale();
    // A callback after this step, or the caller after the last one, sees the whole state on every
    // process and may read the contacts' records.
    bool due = false;
    for (const auto& [every, callback] : callbacks_) due = due || (state_.clock.steps + 1) % every == 0;
    const bool readable = due || s + 1 == n;
    compute_forces(readable || contact_records_ == ContactRecords::EveryStep);  // times its own parts
    const auto t1 = std::chrono::steady_clock::now();
    for (auto& controller : controllers_) controller(*this);
    const auto t2 = std::chrono::steady_clock::now();
    timing_.controllers += std::chrono::duration<double>(t2 - t1).count();
    integrate();
    const auto t3 = std::chrono::steady_clock::now();
    timing_.integration += std::chrono::duration<double>(t3 - t2).count();
    share_ghosts();  // spread over processes: the partners of the next step's contacts
    state_.clock.time += state_.clock.dt;
    ++state_.clock.steps;
    if (due || (s + 1 == n && end == StepEnd::Whole)) synchronise();
    timing_.communication += seconds_since(t3);
    team_.step_took(seconds_since(step_start));
    for (auto& [every, callback] : callbacks_)
      if (state_.clock.steps % every == 0) callback(*this);
  }
}

bool World::run_until(const std::function<bool(const World&)>& done, std::int64_t check_every, std::int64_t max_steps) {
  require(check_every > 0, "check interval", check_every, "> 0 steps");
  std::int64_t taken = 0;
  while (taken < max_steps) {
    const std::int64_t n = std::min(check_every, max_steps - taken);
    step(n);
    taken += n;
    if (done(*this)) return true;
  }
  return false;
}

void World::rebuild_now(bool resort) {
  synchronise();
  synchronise_history();
  rebuild(resort);
}

void World::rebuild(bool resort) {
  broad_phase_.rebuild(state_, models_, threads_, resort);
  pebble_layout_stale_ = pebble_layout_stale_ || resort;  // a re-sort moves particles in storage
  plan_.forget_shares();
  forget_domains();
  if (state_.settings.time_step <= 0.0 && state_.clock.dt > 0.0) update_time_step();
}

void World::restore(WorldState state) {
  if (state.cell) {  // what set_periodic_cell refuses, a state cannot bring in either
    require(ranks() <= 1, "a restored periodic cell in a World spread over processes", std::to_string(ranks()) + " processes",
            "one process: the subdomains do not wrap across the cell's faces yet");
    require(state.walls.empty() && state.clumps.empty(), "a restored periodic cell with walls or clumps",
            std::to_string(state.walls.size()) + " walls, " + std::to_string(state.clumps.size()) + " clumps",
            "none: they are not supported in a periodic cell yet");
  }
  require(state.bonds.empty() || ranks() <= 1, "restored bonds in a World spread over processes",
          std::to_string(ranks()) + " processes", "one process: bonds do not cross subdomains yet");
  state_ = std::move(state);
  pebble_layout_stale_ = true;
  pair_records_current_ = true;  // a restart file holds the records of its last step
  plan_.forget_shares();  // the restored contact lists are not those the plan was made for
  forget_domains();
  broad_phase_.invalidate_near();
  // The file's time step belongs to the stiffness it was written with. Contact models that are
  // stiffer (another E*) need a shorter one; the same models keep the file's (the estimate moves by
  // far less than the margin between rebuilds), so a resumed run stays the same run.
  const WorldSettings& s = state_.settings;
  if (s.time_step <= 0.0 && state_.clock.dt > 0.0 && state_.clock.dt > 1.1 * s.time_step_safety * critical_time_step())
    update_time_step();
}

void World::update_time_step() {
  if (state_.settings.time_step > 0.0) {
    state_.clock.dt = state_.settings.time_step;
    return;
  }
  const double critical = critical_time_step();
  require(std::isfinite(critical) && critical > 0.0, "critical time step estimate", critical,
          "finite and > 0 (are contact models set for every contact type present?)");
  state_.clock.dt = state_.settings.time_step_safety * critical;
}

}  // namespace dem
