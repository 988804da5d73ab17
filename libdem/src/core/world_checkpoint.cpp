// World state to and from a binary stream, for restart files. Doubles are written as their bytes,
// so a resumed run continues exactly. The framing (format version, checksum, atomic write) is
// io/checkpoint.cpp's job. The reader (checkpoint_reader.cpp) checks every count, index and value a
// later step trusts: the checksum only stops random damage, not a file written wrong with a
// matching checksum.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>
#include "checkpoint_reader.hpp"

namespace dem {

namespace {

struct Writer {
  std::ostream& out;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    if constexpr (std::is_same_v<T, Vec3>) {
      for (const Vec3& x : v) pod(x.x()), pod(x.y()), pod(x.z());
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
    }
  }
  void vec3(const Vec3& x) { pod(x.x()), pod(x.y()), pod(x.z()); }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    out.write(s.data(), static_cast<std::streamsize>(s.size()));
  }
};

void write_states(Writer& w, const StateBuffer& b) {
  w.pod<std::uint64_t>(b.stride);
  w.pod<std::uint64_t>(b.count);
  w.out.write(reinterpret_cast<const char*>(b.bytes.data()), static_cast<std::streamsize>(b.bytes.size()));
}

void write_pairs(Writer& w, const PairContacts& c) {
  w.vec(c.first);
  w.vec(c.second);
  w.vec(c.force);
  // The torques on piece 1 are scratch of the step that gathers: written before they are read,
  // and only for the contacts the current thread plan gathers. Saved, their other entries would
  // make the file depend on earlier plans, not on the state. The format keeps their place.
  w.vec(std::vector<Vec3>{});
  w.vec(std::vector<Vec3>{});  // torque_second: no longer stored (second_torque); the format keeps its place
  w.vec(c.normal_force);
  write_states(w, c.state);
}

}  // namespace

using namespace checkpoint;

void World::save_state(std::ostream& out) const {
  Writer w{out};
  for (const auto& m : models_) w.text(m ? m->law_name() : "");
  w.pod(time_);
  w.pod(steps_);
  w.pod(dt_);
  // Every setting that shapes the trajectory (threads do not: results are thread-count independent).
  w.pod(settings_.time_step), w.pod(settings_.time_step_safety), w.pod(settings_.local_damping);
  w.vec3(settings_.gravity);
  w.pod(settings_.skin), w.pod(settings_.sort_every), w.pod(settings_.max_overlap_ratio);
  w.pod(settings_.max_step_travel_ratio), w.pod(settings_.pebble_pebble_contacts);
  const ParticleStore& p = particles_;
  w.vec(p.x), w.vec(p.v), w.vec(p.w), w.vec(p.f), w.vec(p.t);
  w.vec(p.radius), w.vec(p.mass), w.vec(p.inv_mass), w.vec(p.inv_inertia);
  w.vec(p.id), w.vec(p.group), w.vec(p.clump), w.vec(p.fixed);
  w.pod<std::uint64_t>(clumps_.size());
  for (const Clump& c : clumps_) {
    w.pod(c.mass);
    w.vec3(c.x), w.vec3(c.v), w.vec3(c.w);
    w.pod(c.orientation.w()), w.pod(c.orientation.x()), w.pod(c.orientation.y()), w.pod(c.orientation.z());
    for (int i = 0; i < 9; ++i) w.pod(c.inertia_body.data()[i]);
    w.pod(c.fixed);
    w.vec(c.pebbles);
    w.vec(c.pebble_offsets);
    w.vec3(c.force), w.vec3(c.torque), w.vec3(c.applied_force), w.vec3(c.applied_torque), w.vec3(c.displacement);
  }
  w.pod<std::uint64_t>(walls_.size());
  for (const FacetWall& wall : walls_) {
    w.text(wall.name);
    w.vec(wall.mesh.vertices);
    w.vec(wall.mesh.triangles);
    w.vec3(wall.velocity), w.vec3(wall.displacement), w.vec3(wall.reference_point), w.vec3(wall.outward_normal);
    w.pod(wall.area);
    w.vec3(wall.force), w.vec3(wall.moment);
    w.pod(wall.contact_count), w.pod(wall.stiffness_sum);
  }
  write_pairs(w, ball_ball_);
  write_pairs(w, ball_pebble_);
  const WallContacts& c = wall_contacts_;
  w.vec(c.ball), w.vec(c.wall), w.vec(c.triangle_begin), w.vec(c.triangle_end), w.vec(c.triangles);
  w.vec(c.force), w.vec(c.torque_ball), w.vec(c.point), w.vec(c.moment), w.vec(c.normal_force), w.vec(c.normal_stiffness);
  write_states(w, c.state);
  w.vec(bb_offsets_), w.vec(bb_entries_), w.vec(bp_offsets_), w.vec(bp_entries_);
  w.vec(x_at_rebuild_), w.vec(wall_disp_at_rebuild_);
  w.pod(need_rebuild_), w.pod(rebuilds_), w.pod(max_travel_sq_), w.pod(max_wall_travel_), w.pod(skin_);
  if (!out) throw std::runtime_error("checkpoint: writing the world state failed");
}

void World::load_state(std::istream& in) {
  const std::uint64_t size = bytes_left(in);
  if (size == unknown_size) {
    // Counts are bounded by the bytes that remain, so a stream that cannot tell its size is
    // read into memory first.
    std::ostringstream copy;
    copy << in.rdbuf();
    std::istringstream whole(copy.str());
    load_state(whole);
    return;
  }
  Reader r{in, size};
  for (int k = 0; k < contact_kind_count; ++k) {
    const auto kind = static_cast<ContactKind>(k);
    const std::string saved = r.text(std::string(to_string(kind)) + " law");
    const std::string now = models_[static_cast<std::size_t>(k)] ? models_[static_cast<std::size_t>(k)]->law_name() : "";
    if (saved != now)
      throw InputError(std::string("checkpoint: ") + to_string(kind) + " law = '" + saved + "' in the file but '" + now +
                       "' is set: must be the same law");
  }
  // Everything is read into locals and checked; the World changes only once all of it is valid.
  const double time = r.number("time");
  if (time < 0.0) refuse("time", time, ">= 0 s");
  const std::int64_t steps = r.counter("steps");
  const double dt = r.number("dt");
  if (dt < 0.0) refuse("dt", dt, ">= 0 s (0: not yet estimated)");
  const WorldSettings settings = read_settings(r, settings_);
  ParticleStore p = read_particles(r);
  std::vector<Clump> clumps = read_clumps(r, p);
  std::vector<FacetWall> walls = read_walls(r);
  const bool pebble_pebble = settings.pebble_pebble_contacts;
  PairContacts bb = read_pairs(r, contact_model(ContactKind::BallBall), ContactKind::BallBall, p, pebble_pebble);
  PairContacts bp = read_pairs(r, contact_model(ContactKind::BallPebble), ContactKind::BallPebble, p, pebble_pebble);
  WallContacts wc = read_wall_contacts(r, contact_model(ContactKind::BallFacet), p, walls);
  auto bb_offsets = r.vec<std::int32_t>("ball-ball incidence offsets");
  auto bb_entries = r.vec<std::int32_t>("ball-ball incidence entries");
  auto bp_offsets = r.vec<std::int32_t>("ball-pebble incidence offsets");
  auto bp_entries = r.vec<std::int32_t>("ball-pebble incidence entries");
  auto x_at_rebuild = r.vec<Vec3>("x_at_rebuild");
  auto wall_disp_at_rebuild = r.vec<Vec3>("wall_disp_at_rebuild");
  const bool need_rebuild = r.flag("need_rebuild");
  const std::int64_t rebuilds = r.counter("rebuilds");
  const double max_travel_sq = r.number("max_travel_sq");
  if (max_travel_sq < 0.0) refuse("max_travel_sq", max_travel_sq, ">= 0 m^2");
  const double max_wall_travel = r.number("max_wall_travel");
  if (max_wall_travel < 0.0) refuse("max_wall_travel", max_wall_travel, ">= 0 m");
  const double skin = r.number("skin");
  if (skin < 0.0) refuse("skin", skin, ">= 0 m");
  // A pending rebuild replaces the lists below before anything reads them (a state saved after
  // adding particles or walls has stale ones); otherwise the next step trusts them as they are.
  if (!need_rebuild) {
    check_incidence(bb, p.size(), bb_offsets, bb_entries, "ball-ball");
    check_incidence(bp, p.size(), bp_offsets, bp_entries, "ball-pebble");
    check_length(x_at_rebuild.size(), p.size(), "x_at_rebuild", "one per particle while need_rebuild = 0");
    check_length(wall_disp_at_rebuild.size(), walls.size(), "wall_disp_at_rebuild", "one per wall while need_rebuild = 0");
  }
  check_finite(x_at_rebuild, "x_at_rebuild");
  check_finite(wall_disp_at_rebuild, "wall_disp_at_rebuild");

  time_ = time, steps_ = steps, dt_ = dt;
  settings_ = settings;
  particles_ = std::move(p);
  clumps_ = std::move(clumps);
  walls_ = std::move(walls);
  ball_ball_ = std::move(bb);
  ball_pebble_ = std::move(bp);
  wall_contacts_ = std::move(wc);
  bb_offsets_ = std::move(bb_offsets), bb_entries_ = std::move(bb_entries);
  bp_offsets_ = std::move(bp_offsets), bp_entries_ = std::move(bp_entries);
  x_at_rebuild_ = std::move(x_at_rebuild), wall_disp_at_rebuild_ = std::move(wall_disp_at_rebuild);
  need_rebuild_ = need_rebuild, rebuilds_ = rebuilds;
  max_travel_sq_ = max_travel_sq, max_wall_travel_ = max_wall_travel, skin_ = skin;
  gather_plan_stale_ = true;  // the loaded contact lists are not those the plan was made for
  near_stale_ = true;
  // The file's time step belongs to the stiffness it was written with. Contact models that are
  // stiffer (another E*) need a shorter one; the same models keep the file's (the estimate moves by
  // far less than the margin between rebuilds), so a resumed run stays the same run.
  if (settings_.time_step <= 0.0 && dt_ > 0.0 && dt_ > 1.1 * settings_.time_step_safety * critical_time_step())
    update_time_step();
}

}  // namespace dem
