// World: building, the step loop, the clock and the time step. The broad phase lives in
// world_rebuild.cpp, forces in world_forces.cpp, integration and stability checks in
// world_integrate.cpp, queries in world_query.cpp.
#include <dem/core/world.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <omp.h>

#include <dem/core/errors.hpp>

namespace dem {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

World::World(WorldSettings settings) : settings_(settings) {
  require_non_negative("time_step", settings_.time_step);
  require(settings_.time_step_safety > 0.0 && settings_.time_step_safety <= 1.0, "time_step_safety",
          settings_.time_step_safety, "in (0, 1]");
  require(settings_.local_damping >= 0.0 && settings_.local_damping < 1.0, "local_damping",
          settings_.local_damping, "in [0, 1)");
  require(settings_.gravity.allFinite(), "gravity", "(non-finite)", "finite");
  require_non_negative("skin", settings_.skin);
  require_non_negative("near_skin", settings_.near_skin);
  require(settings_.threads >= 0, "threads", settings_.threads, ">= 0 (0: OMP_NUM_THREADS)");
  require_positive("max_overlap_ratio", settings_.max_overlap_ratio);
  require_positive("max_step_travel_ratio", settings_.max_step_travel_ratio);
  threads_ = settings_.threads > 0 ? settings_.threads : omp_get_max_threads();
  dt_ = settings_.time_step;
  ball_ball_.kind = ContactKind::BallBall;
  ball_pebble_.kind = ContactKind::BallPebble;
}

ParticleId World::add_ball(const BallSpec& spec) {
  need_rebuild_ = true;
  return particles_.add(spec);
}

ClumpId World::add_clump(const ClumpSpec& spec) {
  const ClumpId cid = static_cast<ClumpId>(clumps_.size());
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
    const ParticleId pid = particles_.add(b, cid);
    const std::size_t i = particles_.index_of(pid);
    particles_.inv_mass[i] = 1.0 / spec.mass;
    c.pebbles.push_back(pid);
    c.pebble_offsets.push_back(p.position - spec.centre_of_mass);
  }
  clumps_.push_back(std::move(c));
  update_pebbles();
  need_rebuild_ = true;
  return cid;
}

WallId World::add_wall(FacetWall wall) {
  walls_.push_back(std::move(wall));
  need_rebuild_ = true;
  return static_cast<WallId>(walls_.size() - 1);
}

void World::set_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model) {
  require(model != nullptr, std::string("contact model for ") + to_string(kind), "null", "a model");
  models_[static_cast<int>(kind)] = std::move(model);
  need_rebuild_ = true;  // states are re-created for the new law at the next rebuild
}

void World::retune_contact_model(ContactKind kind, std::shared_ptr<const ContactModel> model) {
  require(model != nullptr, std::string("contact model for ") + to_string(kind), "null", "a model");
  const ContactModel* now = models_[static_cast<int>(kind)].get();
  require(now != nullptr && std::string(now->law_name()) == model->law_name(),
          std::string("retuned contact model for ") + to_string(kind), model->law_name(),
          std::string("the law in use, ") + (now ? now->law_name() : "(none)"));
  models_[static_cast<int>(kind)] = std::move(model);
}

void World::set_time_step(double dt) {
  require_positive("time_step", dt);
  settings_.time_step = dt;
  dt_ = dt;
}

void World::set_local_damping(double alpha) {
  require(alpha >= 0.0 && alpha < 1.0, "local_damping", alpha, "in [0, 1)");
  settings_.local_damping = alpha;
}

void World::set_damping_frame(const DampingFrame& frame) {
  require(frame.velocity.allFinite() && std::isfinite(frame.height) && frame.velocity_gradient.allFinite(),
          "damping frame", "a non-finite value", "finite velocity, height and velocity gradient");
  damping_frame_ = frame;
}

void World::set_max_overlap_ratio(double ratio) {
  require(std::isfinite(ratio) && ratio > 0.0, "max_overlap_ratio", ratio, "finite and > 0");
  settings_.max_overlap_ratio = ratio;
}

void World::add_controller(std::function<void(World&)> controller) { controllers_.push_back(std::move(controller)); }

void World::add_callback(std::int64_t every, std::function<void(World&)> callback) {
  require(every > 0, "callback interval", every, "> 0 steps");
  callbacks_.emplace_back(every, std::move(callback));
}

void World::step(std::int64_t n) {
  for (std::int64_t s = 0; s < n; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    if (need_rebuild_ || needs_rebuild()) rebuild(settings_.sort_every > 0 && rebuilds_ % settings_.sort_every == 0);
    if (near_stale_ || 2.0 * std::sqrt(max_near_travel_sq_) > near_skin_) refresh_near();
    if (dt_ <= 0.0) update_time_step();
    timing_.rebuilds += seconds_since(t0);
    compute_forces();  // times its own parts
    const auto t1 = std::chrono::steady_clock::now();
    for (auto& controller : controllers_) controller(*this);
    const auto t2 = std::chrono::steady_clock::now();
    timing_.controllers += std::chrono::duration<double>(t2 - t1).count();
    integrate();
    timing_.integration += seconds_since(t2);
    time_ += dt_;
    ++steps_;
    for (auto& [every, callback] : callbacks_)
      if (steps_ % every == 0) callback(*this);
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

double World::resolved_skin() const {
  if (settings_.skin > 0.0) return settings_.skin;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles_.size(); ++i)
    if (!particles_.is_pebble(i)) smallest = std::min(smallest, particles_.radius[i]);
  // Half the smallest radius: rebuilds every few tens of steps in quasi-static runs, and few
  // extra candidate pairs (the peers' benchmark inputs use the same, a quarter diameter).
  return std::isfinite(smallest) ? 0.5 * smallest : 1e-3;
}

void World::update_time_step() {
  if (settings_.time_step > 0.0) {
    dt_ = settings_.time_step;
    return;
  }
  const double critical = critical_time_step();
  require(std::isfinite(critical) && critical > 0.0, "critical time step estimate", critical,
          "finite and > 0 (are contact models set for every contact type present?)");
  dt_ = settings_.time_step_safety * critical;
}

}  // namespace dem
