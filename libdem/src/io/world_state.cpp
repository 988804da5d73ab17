// The World's state (WorldState) to and from a binary stream, for restart files. Doubles are
// written as their bytes, so a resumed run continues exactly. The framing (format version,
// checksum, atomic write) is checkpoint.cpp's job. The reader (world_state_reader.cpp) checks
// every count, index and value a later step trusts: the checksum only stops random damage, not a
// file written wrong with a matching checksum.
#include <dem/io/world_state.hpp>

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
#include "world_state_reader.hpp"

namespace dem::io {

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

void write_wall_contacts(Writer& w, const WallContacts& c) {
  w.vec(c.ball), w.vec(c.wall), w.vec(c.triangle_begin), w.vec(c.triangle_end), w.vec(c.triangles);
  w.vec(c.force), w.vec(c.torque_ball), w.vec(c.point), w.vec(c.moment), w.vec(c.normal_force), w.vec(c.normal_stiffness);
  write_states(w, c.state);
}

}  // namespace

using namespace checkpoint;

namespace {

Mat3 read_matrix(Reader& r, const std::string& field) {
  Mat3 m;
  for (int i = 0; i < 9; ++i) m.data()[i] = r.number(at(field, static_cast<std::size_t>(i)));
  return m;
}

/// The periodic cell of format 3 into `s` (after its contacts), checked.
void read_periodic_cell(Reader& r, WorldState& s) {
  const Vec3 origin = r.vec3("periodic cell origin");
  const Mat3 h = read_matrix(r, "periodic cell matrix");
  if (!(h.determinant() > 0.0)) refuse("periodic cell matrix determinant", h.determinant(), "> 0 m^3");
  PeriodicCell cell(h, origin);
  cell.set_velocity_gradient(read_matrix(r, "periodic cell velocity gradient"));
  std::array<bool, 3> axes{};
  for (std::size_t a = 0; a < 3; ++a) axes[a] = r.flag(at("periodic cell axes", a));
  cell.set_periodic_axes(axes);
  cell.set_tilt_remap(r.flag("periodic cell tilt re-map"));
  s.rebuild.cell_at_rebuild = read_matrix(r, "periodic cell matrix at the last rebuild");
  s.contacts.for_each_pair_set([&](PairContacts& c) {
    const std::string field = std::string(to_string(c.kind)) + " images";
    c.image = r.vec<std::uint8_t>(field);
    if (!s.rebuild.need_rebuild) check_length(c.image.size(), c.size(), field, "one per candidate while need_rebuild = 0");
    for (std::size_t k = 0; k < c.image.size(); ++k)
      if (c.image[k] >= image_count) refuse(at(field, k), static_cast<int>(c.image[k]), "an image code 0 to 26");
  });
  s.cell = cell;
}

}  // namespace

void write_world_state(std::ostream& out, const World& world) {
  Writer w{out};
  const WorldState& state = world.state();
  for (int k = 0; k < contact_kind_count; ++k) {
    const ContactModel* model = world.contact_model(static_cast<ContactKind>(k));
    w.text(model ? model->law_name() : "");
  }
  w.pod(state.clock.time);
  w.pod(state.clock.steps);
  w.pod(state.clock.dt);
  // Every setting that shapes the trajectory (threads do not: results are thread-count independent).
  const WorldSettings& settings = state.settings;
  w.pod(settings.time_step), w.pod(settings.time_step_safety), w.pod(settings.local_damping);
  w.vec3(settings.gravity);
  w.pod(settings.skin), w.pod(settings.sort_every), w.pod(settings.max_overlap_ratio);
  w.pod(settings.max_step_travel_ratio), w.pod(settings.pebble_pebble_contacts);
  const ParticleStore& p = state.particles;
  w.vec(p.x), w.vec(p.v), w.vec(p.w), w.vec(p.f), w.vec(p.t);
  w.vec(p.radius), w.vec(p.mass), w.vec(p.inv_mass), w.vec(p.inv_inertia);
  w.vec(p.id), w.vec(p.group), w.vec(p.clump), w.vec(p.fixed);
  w.pod<std::uint64_t>(state.clumps.size());
  for (const Clump& c : state.clumps) {
    w.pod(c.mass);
    w.vec3(c.x), w.vec3(c.v), w.vec3(c.w);
    w.pod(c.orientation.w()), w.pod(c.orientation.x()), w.pod(c.orientation.y()), w.pod(c.orientation.z());
    for (int i = 0; i < 9; ++i) w.pod(c.inertia_body.data()[i]);
    w.pod(c.fixed);
    w.vec(c.pebbles);
    w.vec(c.pebble_offsets);
    w.vec3(c.force), w.vec3(c.torque), w.vec3(c.applied_force), w.vec3(c.applied_torque), w.vec3(c.displacement);
  }
  w.pod<std::uint64_t>(state.walls.size());
  for (const Wall& wall : state.walls) {
    w.text(wall.name);
    w.vec(wall.mesh.vertices);
    w.vec(wall.mesh.triangles);
    w.vec3(wall.velocity), w.vec3(wall.displacement), w.vec3(wall.reference_point), w.vec3(wall.outward_normal);
    w.pod(wall.area);
    w.vec3(wall.force), w.vec3(wall.moment);
    w.pod(wall.contact_count), w.pod(wall.stiffness_sum);
  }
  const WorldContacts& contacts = state.contacts;
  write_pairs(w, contacts.ball_ball);
  write_pairs(w, contacts.ball_pebble);
  write_wall_contacts(w, contacts.ball_facet);
  w.vec(contacts.ball_ball.incidence_offsets), w.vec(contacts.ball_ball.incidence_entries);
  w.vec(contacts.ball_pebble.incidence_offsets), w.vec(contacts.ball_pebble.incidence_entries);
  const RebuildRecord& record = state.rebuild;
  w.vec(record.x_at_rebuild), w.vec(record.wall_disp_at_rebuild);
  w.pod(record.need_rebuild), w.pod(record.rebuilds), w.pod(record.max_travel_sq), w.pod(record.max_wall_travel);
  w.pod(record.skin);
  // Since format 2: the walls' analytic surfaces and the ball-surface contacts.
  for (const Wall& wall : state.walls) {
    w.pod(static_cast<std::uint8_t>(wall.surface.shape));
    w.vec3(wall.surface.point), w.vec3(wall.surface.axis);
    w.pod(wall.surface.radius);
  }
  write_wall_contacts(w, contacts.ball_surface);
  // Since format 3: the periodic cell, if any.
  w.pod(state.cell.has_value());
  if (state.cell) {
    const PeriodicCell& cell = *state.cell;
    w.vec3(cell.origin());
    for (int i = 0; i < 9; ++i) w.pod(cell.matrix().data()[i]);
    for (int i = 0; i < 9; ++i) w.pod(cell.velocity_gradient().data()[i]);
    for (const bool periodic : cell.periodic_axes()) w.pod(periodic);
    w.pod(cell.tilt_remap());
    for (int i = 0; i < 9; ++i) w.pod(record.cell_at_rebuild.data()[i]);
    w.vec(contacts.ball_ball.image);
    w.vec(contacts.ball_pebble.image);
  }
  // Since format 4: the bonds (world_state_bonds.cpp reads them).
  const BondStore& b = state.bonds;
  w.vec(b.first), w.vec(b.second);
  w.vec(b.radius), w.vec(b.normal_stiffness), w.vec(b.shear_stiffness);
  w.vec(b.tensile_strength), w.vec(b.cohesion), w.vec(b.friction_angle);
  w.vec(b.normal_force), w.vec(b.shear_force), w.vec(b.twist_moment), w.vec(b.bend_moment);
  w.vec(b.status);
  if (!out) throw std::runtime_error("checkpoint: writing the world state failed");
}

void read_world_state(std::istream& in, World& world, std::uint32_t format) {
  const std::uint64_t size = bytes_left(in);
  if (size == unknown_size) {
    // Counts are bounded by the bytes that remain, so a stream that cannot tell its size is
    // read into memory first.
    std::ostringstream copy;
    copy << in.rdbuf();
    std::istringstream whole(copy.str());
    read_world_state(whole, world, format);
    return;
  }
  if (format < 1 || format > world_state_format)
    throw InputError("checkpoint: world state format " + std::to_string(format) + ": this libdem reads 1 to " +
                     std::to_string(world_state_format));
  Reader r{in, size};
  for (int k = 0; k < contact_kind_count; ++k) {
    const auto kind = static_cast<ContactKind>(k);
    const std::string saved = r.text(std::string(to_string(kind)) + " law");
    const ContactModel* model = world.contact_model(kind);
    const std::string now = model ? model->law_name() : "";
    if (saved != now)
      throw InputError(std::string("checkpoint: ") + to_string(kind) + " law = '" + saved + "' in the file but '" + now +
                       "' is set: must be the same law");
  }
  // Everything is read into a new state and checked; the World changes only once all of it is valid.
  WorldState s;
  s.clock.time = r.number("time");
  if (s.clock.time < 0.0) refuse("time", s.clock.time, ">= 0 s");
  s.clock.steps = r.counter("steps");
  s.clock.dt = r.number("dt");
  if (s.clock.dt < 0.0) refuse("dt", s.clock.dt, ">= 0 s (0: not yet estimated)");
  s.settings = read_settings(r, world.settings());
  s.particles = read_particles(r);
  s.clumps = read_clumps(r, s.particles);
  s.walls = read_walls(r);
  const ParticleStore& p = s.particles;
  const bool pebble_pebble = s.settings.pebble_pebble_contacts;
  WorldContacts& c = s.contacts;
  c.ball_ball = read_pairs(r, world.contact_model(ContactKind::BallBall), ContactKind::BallBall, p, pebble_pebble);
  c.ball_pebble = read_pairs(r, world.contact_model(ContactKind::BallPebble), ContactKind::BallPebble, p, pebble_pebble);
  c.ball_facet = read_wall_contacts(r, world.contact_model(ContactKind::BallFacet), p, s.walls, false);
  c.ball_ball.incidence_offsets = r.vec<std::int32_t>("ball-ball incidence offsets");
  c.ball_ball.incidence_entries = r.vec<std::int32_t>("ball-ball incidence entries");
  c.ball_pebble.incidence_offsets = r.vec<std::int32_t>("ball-pebble incidence offsets");
  c.ball_pebble.incidence_entries = r.vec<std::int32_t>("ball-pebble incidence entries");
  RebuildRecord& record = s.rebuild;
  record.x_at_rebuild = r.vec<Vec3>("x_at_rebuild");
  record.wall_disp_at_rebuild = r.vec<Vec3>("wall_disp_at_rebuild");
  record.need_rebuild = r.flag("need_rebuild");
  record.rebuilds = r.counter("rebuilds");
  record.max_travel_sq = r.number("max_travel_sq");
  if (record.max_travel_sq < 0.0) refuse("max_travel_sq", record.max_travel_sq, ">= 0 m^2");
  record.max_wall_travel = r.number("max_wall_travel");
  if (record.max_wall_travel < 0.0) refuse("max_wall_travel", record.max_wall_travel, ">= 0 m");
  record.skin = r.number("skin");
  if (record.skin < 0.0) refuse("skin", record.skin, ">= 0 m");
  // A pending rebuild replaces the lists below before anything reads them (a state saved after
  // adding particles or walls has stale ones); otherwise the next step trusts them as they are.
  if (!record.need_rebuild) {
    check_incidence(c.ball_ball, p.size(), c.ball_ball.incidence_offsets, c.ball_ball.incidence_entries, "ball-ball");
    check_incidence(c.ball_pebble, p.size(), c.ball_pebble.incidence_offsets, c.ball_pebble.incidence_entries,
                    "ball-pebble");
    check_length(record.x_at_rebuild.size(), p.size(), "x_at_rebuild", "one per particle while need_rebuild = 0");
    check_length(record.wall_disp_at_rebuild.size(), s.walls.size(), "wall_disp_at_rebuild",
                 "one per wall while need_rebuild = 0");
  }
  check_finite(record.x_at_rebuild, "x_at_rebuild");
  check_finite(record.wall_disp_at_rebuild, "wall_disp_at_rebuild");
  if (format >= 2) {
    read_surfaces(r, s.walls);
    c.ball_surface = read_wall_contacts(r, world.contact_model(ContactKind::BallFacet), p, s.walls, true);
  }
  if (format >= 3 && r.flag("periodic cell")) read_periodic_cell(r, s);
  if (format >= 4) s.bonds = read_bonds(r, s.particles);
  world.restore(std::move(s));
}

}  // namespace dem::io
