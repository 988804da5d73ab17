// World state to and from a binary stream, for restart files. Doubles are written as their bytes,
// so a resumed run continues exactly. The framing (format version, checksum, atomic write) is
// io/checkpoint.cpp's job.
#include <cstring>
#include <istream>
#include <ostream>

#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>

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

struct Reader {
  std::istream& in;
  template <class T>
  T pod() {
    T v{};
    in.read(reinterpret_cast<char*>(&v), sizeof(T));
    if (!in) throw InputError("checkpoint: truncated data (stream ended early)");
    return v;
  }
  std::uint64_t count(std::uint64_t limit = (1ULL << 34)) {
    const auto n = pod<std::uint64_t>();
    if (n > limit) throw InputError("checkpoint: corrupt data (array of " + std::to_string(n) + " entries)");
    return n;
  }
  template <class T>
  std::vector<T> vec() {
    std::vector<T> v(count());
    if constexpr (std::is_same_v<T, Vec3>) {
      for (Vec3& x : v) x = vec3();
    } else {
      in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
      if (!in) throw InputError("checkpoint: truncated data (stream ended early)");
    }
    return v;
  }
  Vec3 vec3() {
    const double x = pod<double>(), y = pod<double>(), z = pod<double>();
    return Vec3(x, y, z);
  }
  std::string text() {
    std::string s(count(1 << 20), '\0');
    in.read(s.data(), static_cast<std::streamsize>(s.size()));
    if (!in) throw InputError("checkpoint: truncated data (stream ended early)");
    return s;
  }
};

void write_states(Writer& w, const StateBuffer& b) {
  w.pod<std::uint64_t>(b.stride);
  w.pod<std::uint64_t>(b.count);
  w.out.write(reinterpret_cast<const char*>(b.bytes.data()), static_cast<std::streamsize>(b.bytes.size()));
}

void read_states(Reader& r, const ContactModel* model, StateBuffer& b, const char* what) {
  const auto stride = r.pod<std::uint64_t>();
  const auto count = r.count();
  if (model == nullptr) {
    if (count != 0) throw InputError(std::string("checkpoint has ") + what + " contacts but no contact model is set for them");
    b = StateBuffer{};
    return;
  }
  model->reset_states(b, count);  // typed construction; the saved bytes then restore the values
  if (count > 0 && b.stride != stride)
    throw InputError(std::string("checkpoint: ") + what + " contact history was written by another contact law");
  r.in.read(reinterpret_cast<char*>(b.bytes.data()), static_cast<std::streamsize>(b.bytes.size()));
  if (!r.in) throw InputError("checkpoint: truncated data (stream ended early)");
}

void write_pairs(Writer& w, const PairContacts& c) {
  w.vec(c.first);
  w.vec(c.second);
  w.vec(c.force);
  w.vec(c.torque_first);
  w.vec(c.torque_second);
  w.vec(c.normal_force);
  write_states(w, c.state);
}

void read_pairs(Reader& r, const ContactModel* model, PairContacts& c, const char* what) {
  c.first = r.vec<std::int32_t>();
  c.second = r.vec<std::int32_t>();
  c.force = r.vec<Vec3>();
  c.torque_first = r.vec<Vec3>();
  c.torque_second = r.vec<Vec3>();
  c.normal_force = r.vec<double>();
  read_states(r, model, c.state, what);
}

}  // namespace

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
  Reader r{in};
  for (int k = 0; k < contact_kind_count; ++k) {
    const std::string saved = r.text();
    const std::string now = models_[static_cast<std::size_t>(k)] ? models_[static_cast<std::size_t>(k)]->law_name() : "";
    if (saved != now)
      throw InputError(std::string("checkpoint: ") + to_string(static_cast<ContactKind>(k)) + " law = '" + saved +
                       "' in the file but '" + now + "' is set: must be the same law");
  }
  time_ = r.pod<double>();
  steps_ = r.pod<std::int64_t>();
  dt_ = r.pod<double>();
  settings_.time_step = r.pod<double>();
  settings_.time_step_safety = r.pod<double>();
  settings_.local_damping = r.pod<double>();
  settings_.gravity = r.vec3();
  settings_.skin = r.pod<double>();
  settings_.sort_every = r.pod<int>();
  settings_.max_overlap_ratio = r.pod<double>();
  settings_.max_step_travel_ratio = r.pod<double>();
  settings_.pebble_pebble_contacts = r.pod<bool>();
  ParticleStore p;
  p.x = r.vec<Vec3>(), p.v = r.vec<Vec3>(), p.w = r.vec<Vec3>(), p.f = r.vec<Vec3>(), p.t = r.vec<Vec3>();
  p.radius = r.vec<double>(), p.mass = r.vec<double>(), p.inv_mass = r.vec<double>(), p.inv_inertia = r.vec<double>();
  p.id = r.vec<ParticleId>(), p.group = r.vec<int>(), p.clump = r.vec<std::int32_t>(), p.fixed = r.vec<std::uint8_t>();
  const std::size_t n = p.x.size();
  for (std::size_t size : {p.v.size(), p.w.size(), p.radius.size(), p.id.size(), p.clump.size(), p.fixed.size()})
    if (size != n) throw InputError("checkpoint: corrupt particle arrays (sizes differ)");
  p.restore_index();
  std::vector<Clump> clumps(r.count());
  for (Clump& c : clumps) {
    c.mass = r.pod<double>();
    c.x = r.vec3(), c.v = r.vec3(), c.w = r.vec3();
    const double qw = r.pod<double>(), qx = r.pod<double>(), qy = r.pod<double>(), qz = r.pod<double>();
    c.orientation = Quat(qw, qx, qy, qz);
    for (int i = 0; i < 9; ++i) c.inertia_body.data()[i] = r.pod<double>();
    c.inv_inertia_body = c.inertia_body.inverse();
    c.fixed = r.pod<std::uint8_t>();
    c.pebbles = r.vec<ParticleId>();
    c.pebble_offsets = r.vec<Vec3>();
    c.force = r.vec3(), c.torque = r.vec3(), c.applied_force = r.vec3(), c.applied_torque = r.vec3();
    c.displacement = r.vec3();
  }
  std::vector<FacetWall> walls(r.count());
  for (FacetWall& wall : walls) {
    wall.name = r.text();
    wall.mesh.vertices = r.vec<Vec3>();
    wall.mesh.triangles = r.vec<std::array<int, 3>>();
    wall.velocity = r.vec3(), wall.displacement = r.vec3(), wall.reference_point = r.vec3(), wall.outward_normal = r.vec3();
    wall.area = r.pod<double>();
    wall.force = r.vec3(), wall.moment = r.vec3();
    wall.contact_count = r.pod<int>();
    wall.stiffness_sum = r.pod<double>();
  }
  PairContacts bb, bp;
  bb.kind = ContactKind::BallBall;
  bp.kind = ContactKind::BallPebble;
  read_pairs(r, contact_model(ContactKind::BallBall), bb, "ball-ball");
  read_pairs(r, contact_model(ContactKind::BallPebble), bp, "ball-pebble");
  WallContacts wc;
  wc.ball = r.vec<std::int32_t>(), wc.wall = r.vec<std::int32_t>();
  wc.triangle_begin = r.vec<std::int32_t>(), wc.triangle_end = r.vec<std::int32_t>(), wc.triangles = r.vec<std::int32_t>();
  wc.force = r.vec<Vec3>(), wc.torque_ball = r.vec<Vec3>(), wc.point = r.vec<Vec3>(), wc.moment = r.vec<Vec3>();
  wc.normal_force = r.vec<double>(), wc.normal_stiffness = r.vec<double>();
  read_states(r, contact_model(ContactKind::BallFacet), wc.state, "ball-facet");
  bb_offsets_ = r.vec<std::int32_t>(), bb_entries_ = r.vec<std::int32_t>();
  bp_offsets_ = r.vec<std::int32_t>(), bp_entries_ = r.vec<std::int32_t>();
  x_at_rebuild_ = r.vec<Vec3>(), wall_disp_at_rebuild_ = r.vec<Vec3>();
  need_rebuild_ = r.pod<bool>();
  rebuilds_ = r.pod<std::int64_t>();
  max_travel_sq_ = r.pod<double>();
  max_wall_travel_ = r.pod<double>();
  skin_ = r.pod<double>();
  // Indices must point inside the arrays, or a corrupted file would crash the next step.
  auto check_index = [&](const std::vector<std::int32_t>& v, std::size_t limit, const char* what) {
    for (std::int32_t i : v)
      if (i < 0 || static_cast<std::size_t>(i) >= limit)
        throw InputError(std::string("checkpoint: corrupt ") + what + " index " + std::to_string(i));
  };
  check_index(bb.first, n, "contact"), check_index(bb.second, n, "contact");
  check_index(bp.first, n, "contact"), check_index(bp.second, n, "contact");
  check_index(wc.ball, n, "contact"), check_index(wc.wall, walls.size(), "wall");
  if (bb_offsets_.size() != n + 1 || bp_offsets_.size() != n + 1 || x_at_rebuild_.size() != n)
    throw InputError("checkpoint: corrupt neighbour lists");
  check_index(bb_entries_, 2 * bb.size(), "incidence"), check_index(bp_entries_, 2 * bp.size(), "incidence");
  for (std::size_t k = 0; k < wc.size(); ++k)
    if (wc.triangle_begin.size() != wc.size() || wc.triangle_end.size() != wc.size() || wc.triangle_begin[k] < 0 ||
        wc.triangle_end[k] < wc.triangle_begin[k] || static_cast<std::size_t>(wc.triangle_end[k]) > wc.triangles.size())
      throw InputError("checkpoint: corrupt wall contact list");
  for (std::size_t k = 0; k < wc.size(); ++k)
    for (std::int32_t t = wc.triangle_begin[k]; t < wc.triangle_end[k]; ++t)
      check_index({wc.triangles[static_cast<std::size_t>(t)]}, walls[static_cast<std::size_t>(wc.wall[k])].mesh.triangles.size(), "triangle");
  particles_ = std::move(p);
  clumps_ = std::move(clumps);
  walls_ = std::move(walls);
  ball_ball_ = std::move(bb);
  ball_pebble_ = std::move(bp);
  wall_contacts_ = std::move(wc);
}

}  // namespace dem
