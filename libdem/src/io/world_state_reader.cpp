// The readers and checks of io::read_world_state (world_state_reader.hpp): every value a later step trusts.
#include "world_state_reader.hpp"

#include <algorithm>
#include <cstring>

namespace dem::checkpoint {

std::uint64_t bytes_left(std::istream& in) {
  const auto here = in.tellg();
  if (here < 0) return unknown_size;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  if (end < here || !in) return unknown_size;
  return static_cast<std::uint64_t>(end - here);
}

// --- checks shared by the parts of the state ---------------------------------------------------

void check_points(const std::vector<Vec3>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite() || v[k].cwiseAbs().maxCoeff() > max_length)
      refuse(at(field, k), Reader::show(v[k]), "finite, within +-1e100 m");
}

void check_finite(const std::vector<Vec3>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite()) refuse(at(field, k), Reader::show(v[k]), "finite");
}

void check_finite(const std::vector<double>& v, const std::string& field, double low) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!(std::isfinite(v[k]) && v[k] >= low)) refuse(at(field, k), v[k], "finite and >= " + std::to_string(low));
}

void check_index(const std::vector<std::int32_t>& v, std::size_t limit, const std::string& field,
                 const std::string& limit_name) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= limit)
      refuse(at(field, k), v[k], "in [0, " + std::to_string(limit) + ") (" + limit_name + ")");
}

void check_length(std::size_t size, std::size_t expected, const std::string& field, const std::string& why) {
  if (size != expected) refuse(field + " count", size, std::to_string(expected) + " (" + why + ")");
}

/// Per-contact results are saved empty when no step has computed them since the last rebuild;
/// otherwise they have one entry per contact. Empty ones are filled with the zeros the next
/// step starts from, so that every reader can index them by contact. Vector values are not
/// checked: a ball-facet contact point stays unset (any bits, NaN too) while the contact does
/// not touch, and the next step recomputes them all before the engine uses them.
template <class T>
void fill_results(std::vector<T>& v, std::size_t contacts, const std::string& field) {
  if (!v.empty() && v.size() != contacts)
    refuse(field + " count", v.size(), "0 or " + std::to_string(contacts) + " (one per contact)");
  if constexpr (std::is_same_v<T, Vec3>) {
    v.resize(contacts, Vec3::Zero());
  } else {
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k])) refuse(at(field, k), v[k], "finite");
    v.resize(contacts, 0.0);
  }
}

// --- settings and clock -------------------------------------------------------------------------

/// The same rules as the World constructor, so that a loaded World is one that could be built.
WorldSettings read_settings(Reader& r, WorldSettings s) {
  s.time_step = r.number("settings.time_step");
  if (s.time_step < 0.0) refuse("settings.time_step", s.time_step, ">= 0 s (0: automatic)");
  s.time_step_safety = r.number("settings.time_step_safety");
  if (!(s.time_step_safety > 0.0 && s.time_step_safety <= 1.0))
    refuse("settings.time_step_safety", s.time_step_safety, "in (0, 1]");
  s.local_damping = r.number("settings.local_damping");
  if (!(s.local_damping >= 0.0 && s.local_damping < 1.0)) refuse("settings.local_damping", s.local_damping, "in [0, 1)");
  s.gravity = r.finite3("settings.gravity");
  s.skin = r.number("settings.skin");
  if (!(s.skin >= 0.0 && s.skin <= max_length)) refuse("settings.skin", s.skin, "in [0, 1e100] m (0: automatic)");
  s.sort_every = r.pod<int>("settings.sort_every");  // any value: <= 0 means never
  s.max_overlap_ratio = r.number("settings.max_overlap_ratio");
  if (!(s.max_overlap_ratio > 0.0)) refuse("settings.max_overlap_ratio", s.max_overlap_ratio, "> 0");
  s.max_step_travel_ratio = r.number("settings.max_step_travel_ratio");
  if (!(s.max_step_travel_ratio > 0.0)) refuse("settings.max_step_travel_ratio", s.max_step_travel_ratio, "> 0");
  s.pebble_pebble_contacts = r.flag("settings.pebble_pebble_contacts");
  return s;
}

// --- particles and clumps -----------------------------------------------------------------------

void check_particle_arrays(const ParticleStore& p) {
  const std::size_t n = p.id.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<ParticleId>::max()))
    refuse("particles.id count", n, "<= 2147483647 (ids are 32-bit)");
  const std::string why = "one per particle, as particles.id";
  check_length(p.x.size(), n, "particles.x", why), check_length(p.v.size(), n, "particles.v", why);
  check_length(p.w.size(), n, "particles.w", why), check_length(p.f.size(), n, "particles.f", why);
  check_length(p.t.size(), n, "particles.t", why), check_length(p.radius.size(), n, "particles.radius", why);
  check_length(p.mass.size(), n, "particles.mass", why), check_length(p.inv_mass.size(), n, "particles.inv_mass", why);
  check_length(p.inv_inertia.size(), n, "particles.inv_inertia", why);
  check_length(p.group.size(), n, "particles.group", why), check_length(p.clump.size(), n, "particles.clump", why);
  check_length(p.fixed.size(), n, "particles.fixed", why);
}

void check_particle_values(const ParticleStore& p) {
  check_points(p.x, "particles.x");
  check_finite(p.v, "particles.v"), check_finite(p.w, "particles.w");
  check_finite(p.f, "particles.f"), check_finite(p.t, "particles.t");
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!(p.radius[i] > 0.0 && p.radius[i] <= max_length)) refuse(at("particles.radius", i), p.radius[i], "in (0, 1e100] m");
  check_finite(p.mass, "particles.mass", 0.0);
  check_finite(p.inv_mass, "particles.inv_mass", 0.0);
  check_finite(p.inv_inertia, "particles.inv_inertia", 0.0);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed[i] > dof_all) refuse(at("particles.fixed", i), static_cast<int>(p.fixed[i]), "Dof bits (0..63)");
  // Stable ids are a permutation of [0, n): the id -> index map and contact history rely on it.
  std::vector<bool> seen(p.size(), false);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const ParticleId pid = p.id[i];
    if (pid < 0 || static_cast<std::size_t>(pid) >= p.size())
      refuse(at("particles.id", i), pid, "in [0, " + std::to_string(p.size()) + ") (the particle count)");
    if (seen[static_cast<std::size_t>(pid)]) refuse(at("particles.id", i), pid, "unique (it appears twice)");
    seen[static_cast<std::size_t>(pid)] = true;
  }
}

ParticleStore read_particles(Reader& r) {
  ParticleStore p;
  p.x = r.vec<Vec3>("particles.x"), p.v = r.vec<Vec3>("particles.v"), p.w = r.vec<Vec3>("particles.w");
  p.f = r.vec<Vec3>("particles.f"), p.t = r.vec<Vec3>("particles.t");
  p.radius = r.vec<double>("particles.radius"), p.mass = r.vec<double>("particles.mass");
  p.inv_mass = r.vec<double>("particles.inv_mass"), p.inv_inertia = r.vec<double>("particles.inv_inertia");
  p.id = r.vec<ParticleId>("particles.id"), p.group = r.vec<int>("particles.group");
  p.clump = r.vec<std::int32_t>("particles.clump"), p.fixed = r.vec<std::uint8_t>("particles.fixed");
  check_particle_arrays(p);
  check_particle_values(p);
  p.restore_index();
  return p;
}

// The smallest a saved clump can be (no pebbles): mass, x, v, w, orientation, inertia, fixed,
// two counts, five vectors. Bounds the clump count by the bytes that remain.
constexpr std::uint64_t min_clump_bytes = 8 + 3 * 24 + 4 * 8 + 9 * 8 + 1 + 2 * 8 + 5 * 24;

Clump read_clump(Reader& r, const std::string& name) {
  Clump c;
  c.mass = r.number(name + ".mass");
  if (!(c.mass > 0.0)) refuse(name + ".mass", c.mass, "> 0 kg");
  c.x = r.finite3(name + ".x");
  if (c.x.cwiseAbs().maxCoeff() > max_length) refuse(name + ".x", Reader::show(c.x), "within +-1e100 m");
  c.v = r.finite3(name + ".v"), c.w = r.finite3(name + ".w");
  const double qw = r.number(name + ".orientation"), qx = r.number(name + ".orientation");
  const double qy = r.number(name + ".orientation"), qz = r.number(name + ".orientation");
  c.orientation = Quat(qw, qx, qy, qz);
  if (std::abs(c.orientation.norm() - 1.0) > 1e-6) refuse(name + ".orientation |q|", c.orientation.norm(), "1 (a unit quaternion)");
  for (int i = 0; i < 9; ++i) c.inertia_body.data()[i] = r.number(name + ".inertia_body");
  const Mat3& j = c.inertia_body;
  if (!((j - j.transpose()).norm() <= 1e-9 * j.norm() && j.ldlt().isPositive() && j.determinant() > 0.0))
    refuse(name + ".inertia_body", "(not symmetric positive definite)", "a symmetric positive definite tensor");
  c.inv_inertia_body = j.inverse();
  c.fixed = r.pod<std::uint8_t>(name + ".fixed");
  if (c.fixed > dof_all) refuse(name + ".fixed", static_cast<int>(c.fixed), "Dof bits (0..63)");
  c.pebbles = r.vec<ParticleId>(name + ".pebbles");
  if (c.pebbles.empty()) refuse(name + ".pebbles count", 0, "> 0 (a clump is made of pebbles)");
  c.pebble_offsets = r.vec<Vec3>(name + ".pebble_offsets");
  check_length(c.pebble_offsets.size(), c.pebbles.size(), name + ".pebble_offsets", "one per pebble");
  check_points(c.pebble_offsets, name + ".pebble_offsets");
  c.force = r.finite3(name + ".force"), c.torque = r.finite3(name + ".torque");
  c.applied_force = r.finite3(name + ".applied_force"), c.applied_torque = r.finite3(name + ".applied_torque");
  c.displacement = r.finite3(name + ".displacement");
  return c;
}

/// Clump membership both ways: particles.clump[i] = c exactly for the pebbles clump c lists.
void check_membership(const std::vector<Clump>& clumps, const ParticleStore& p) {
  const std::size_t n = p.size();
  std::vector<std::size_t> members(clumps.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t c = p.clump[i];
    if (c < -1 || (c >= 0 && static_cast<std::size_t>(c) >= clumps.size()))
      refuse(at("particles.clump", i), c, "-1 (a free ball) or in [0, " + std::to_string(clumps.size()) + ") (the clump count)");
    if (c >= 0) ++members[static_cast<std::size_t>(c)];
  }
  std::vector<bool> listed(n, false);
  for (std::size_t c = 0; c < clumps.size(); ++c) {
    const std::string name = at("clumps", c) + ".pebbles";
    const auto& pebbles = clumps[c].pebbles;
    for (std::size_t k = 0; k < pebbles.size(); ++k) {
      const ParticleId pid = pebbles[k];
      if (pid < 0 || static_cast<std::size_t>(pid) >= n)
        refuse(at(name, k), pid, "in [0, " + std::to_string(n) + ") (a particle id)");
      const std::size_t i = p.index_of(pid);
      if (p.clump[i] != static_cast<std::int32_t>(c))
        refuse(at(name, k), pid, "a pebble of this clump (that particle has particles.clump = " + std::to_string(p.clump[i]) + ")");
      if (listed[i]) refuse(at(name, k), pid, "listed once (it appears twice)");
      listed[i] = true;
    }
    if (pebbles.size() != members[c])
      refuse(name + " count", pebbles.size(), std::to_string(members[c]) + " (the particles with particles.clump = " + std::to_string(c) + ")");
  }
}

std::vector<Clump> read_clumps(Reader& r, const ParticleStore& p) {
  std::vector<Clump> clumps(r.count("clumps", min_clump_bytes));
  for (std::size_t c = 0; c < clumps.size(); ++c) clumps[c] = read_clump(r, at("clumps", c));
  check_membership(clumps, p);
  return clumps;
}

// --- walls ----------------------------------------------------------------------------------------

// name, vertices and triangles counts, four vectors, area, two vectors, contact count, stiffness.
constexpr std::uint64_t min_wall_bytes = 3 * 8 + 4 * 24 + 8 + 2 * 24 + 4 + 8;

Wall read_wall(Reader& r, const std::string& name) {
  Wall wall;
  wall.name = r.text(name + ".name");
  wall.mesh.vertices = r.vec<Vec3>(name + ".mesh.vertices");
  check_points(wall.mesh.vertices, name + ".mesh.vertices");
  wall.mesh.triangles = r.vec<std::array<int, 3>>(name + ".mesh.triangles");
  const std::size_t vertices = wall.mesh.vertices.size();
  for (std::size_t t = 0; t < wall.mesh.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = wall.mesh.triangles[t][k];
      if (v < 0 || static_cast<std::size_t>(v) >= vertices)
        refuse(at(name + ".mesh.triangles", t) + " vertex " + std::to_string(k), v,
               "in [0, " + std::to_string(vertices) + ") (the wall's vertex count)");
    }
  wall.velocity = r.finite3(name + ".velocity"), wall.displacement = r.finite3(name + ".displacement");
  wall.reference_point = r.finite3(name + ".reference_point"), wall.outward_normal = r.finite3(name + ".outward_normal");
  wall.area = r.number(name + ".area");
  if (wall.area < 0.0) refuse(name + ".area", wall.area, ">= 0 m^2");
  wall.force = r.finite3(name + ".force"), wall.moment = r.finite3(name + ".moment");
  wall.contact_count = r.pod<int>(name + ".contact_count");
  if (wall.contact_count < 0) refuse(name + ".contact_count", wall.contact_count, ">= 0");
  wall.stiffness_sum = r.number(name + ".stiffness_sum");
  if (wall.stiffness_sum < 0.0) refuse(name + ".stiffness_sum", wall.stiffness_sum, ">= 0 N/m");
  return wall;
}

std::vector<Wall> read_walls(Reader& r) {
  std::vector<Wall> walls(r.count("walls", min_wall_bytes));
  for (std::size_t w = 0; w < walls.size(); ++w) walls[w] = read_wall(r, at("walls", w));
  return walls;
}

void read_surfaces(Reader& r, std::vector<Wall>& walls) {
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const std::string name = at("walls", w) + ".surface";
    AnalyticSurface& surface = walls[w].surface;
    const auto shape = r.pod<std::uint8_t>(name + ".shape");
    if (shape > static_cast<std::uint8_t>(AnalyticSurface::Shape::Cylinder))
      refuse(name + ".shape", static_cast<int>(shape), "0 (none), 1 (plane) or 2 (cylinder)");
    surface.shape = static_cast<AnalyticSurface::Shape>(shape);
    surface.point = r.finite3(name + ".point");
    surface.axis = r.finite3(name + ".axis");
    surface.radius = r.number(name + ".radius");
    if (surface.shape == AnalyticSurface::Shape::None) continue;
    if (!walls[w].mesh.triangles.empty())
      refuse(name + ".shape", static_cast<int>(shape), "0 (none) for a wall with triangles");
    if (!(std::abs(surface.axis.norm() - 1.0) <= 1e-12))
      refuse(name + ".axis", Reader::show(surface.axis), "a unit vector");
    if (std::abs(surface.point.maxCoeff()) > max_length || std::abs(surface.point.minCoeff()) > max_length)
      refuse(name + ".point", Reader::show(surface.point), "within 1e100 m of the origin");
    if (surface.shape == AnalyticSurface::Shape::Cylinder && !(surface.radius > 0.0 && surface.radius <= max_length))
      refuse(name + ".radius", surface.radius, "in (0, 1e100] m");
  }
}

// --- contacts ---------------------------------------------------------------------------------------

/// The law history: `contacts` States of the model's size (none without a model).
void read_states(Reader& r, const ContactModel* model, StateBuffer& b, std::size_t contacts, const std::string& name) {
  const auto stride = r.pod<std::uint64_t>(name + ".state stride");
  if (model == nullptr) {
    const auto count = r.pod<std::uint64_t>(name + ".state count");
    if (count != 0) refuse(name + ".state count", count, "0 (no contact model is set for them)");
    b = StateBuffer{};
    return;
  }
  model->reset_states(b, 0);  // learns the law's State size
  const std::size_t size = b.stride;
  const auto count = r.count(name + ".state", size);
  if (count != contacts) refuse(name + ".state count", count, std::to_string(contacts) + " (one per contact)");
  if (count > 0 && stride != size)
    refuse(name + ".state stride", stride, std::to_string(size) + " bytes (this contact law's history; another law wrote it)");
  model->reset_states(b, count);  // typed construction; the saved bytes then restore the values
  r.take(b.bytes.data(), b.bytes.size(), name + ".state");
}

/// Pieces of each pair: in range, distinct, of the kinds the broad phase puts in this list.
void check_pair_pieces(const PairContacts& c, const ParticleStore& p, bool pebble_pebble, const std::string& name) {
  const std::size_t n = p.size();
  check_index(c.first, n, name + ".first", "the particle count");
  check_index(c.second, n, name + ".second", "the particle count");
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
    if (i == j) refuse(at(name + ".second", k), c.second[k], "another particle than first");
    if (c.kind == ContactKind::BallBall) {
      if (p.is_pebble(i) || p.is_pebble(j))
        refuse(at(name + ".first/second", k), std::to_string(c.first[k]) + "/" + std::to_string(c.second[k]), "two balls (not pebbles)");
    } else if (!p.is_pebble(j) || (p.is_pebble(i) && (!pebble_pebble || p.clump[i] == p.clump[j]))) {
      refuse(at(name + ".first/second", k), std::to_string(c.first[k]) + "/" + std::to_string(c.second[k]),
             "a ball (or, with pebble_pebble_contacts, a pebble of another clump) and a pebble");
    }
  }
}

PairContacts read_pairs(Reader& r, const ContactModel* model, ContactKind kind, const ParticleStore& p,
                        bool pebble_pebble) {
  const std::string name = std::string(to_string(kind)) + " contacts";
  PairContacts c;
  c.kind = kind;
  c.first = r.vec<std::int32_t>(name + ".first");
  c.second = r.vec<std::int32_t>(name + ".second");
  c.force = r.vec<Vec3>(name + ".force");
  std::vector<Vec3> torque_first = r.vec<Vec3>(name + ".torque_first");  // older files: checked, not kept
  std::vector<Vec3> torque_second = r.vec<Vec3>(name + ".torque_second");  // older files: checked, not kept
  c.normal_force = r.vec<double>(name + ".normal_force");
  const std::size_t count = c.size();
  check_length(c.second.size(), count, name + ".second", "one per contact, as first");
  check_pair_pieces(c, p, pebble_pebble, name);
  // The rebuild assigns normal forces to every candidate; the other results may still be empty.
  check_length(c.normal_force.size(), count, name + ".normal_force", "one per contact");
  fill_results(c.normal_force, count, name + ".normal_force");
  fill_results(c.force, count, name + ".force");
  fill_results(torque_first, count, name + ".torque_first");
  fill_results(torque_second, count, name + ".torque_second");
  read_states(r, model, c.state, count, name);
  mark_touching(c);
  return c;
}

/// Each (ball, wall) contact: a ball, a wall, and a range of that wall's triangles (none for the
/// contacts with walls' surfaces, whose walls must have one).
void check_wall_contacts(const WallContacts& c, const ParticleStore& p, const std::vector<Wall>& walls) {
  const std::string name = c.surfaces ? "ball-surface contacts" : "ball-facet contacts";
  const std::size_t count = c.size();
  check_length(c.wall.size(), count, name + ".wall", "one per contact, as ball");
  const std::size_t ranges = c.surfaces ? 0 : count;  // a surface has no triangles
  const char* why = c.surfaces ? "none (surfaces have no triangles)" : "one per contact";
  check_length(c.triangle_begin.size(), ranges, name + ".triangle_begin", why);
  check_length(c.triangle_end.size(), ranges, name + ".triangle_end", why);
  if (c.surfaces) check_length(c.triangles.size(), 0, name + ".triangles", why);
  check_index(c.ball, p.size(), name + ".ball", "the particle count");
  check_index(c.wall, walls.size(), name + ".wall", "the wall count");
  for (std::size_t k = 0; k < count; ++k) {
    if (p.is_pebble(static_cast<std::size_t>(c.ball[k]))) refuse(at(name + ".ball", k), c.ball[k], "a ball (not a pebble)");
    if (c.surfaces) {
      if (walls[static_cast<std::size_t>(c.wall[k])].surface.shape == AnalyticSurface::Shape::None)
        refuse(at(name + ".wall", k), c.wall[k], "a wall with an analytic surface");
      continue;
    }
    const std::int32_t begin = c.triangle_begin[k], end = c.triangle_end[k];
    if (begin < 0 || begin > end || static_cast<std::size_t>(end) > c.triangles.size())
      refuse(at(name + ".triangle_begin/end", k), std::to_string(begin) + "/" + std::to_string(end),
             "a range within [0, " + std::to_string(c.triangles.size()) + "] (the triangles list)");
    const std::size_t triangles = walls[static_cast<std::size_t>(c.wall[k])].mesh.triangles.size();
    for (std::int32_t t = begin; t < end; ++t) {
      const std::int32_t tri = c.triangles[static_cast<std::size_t>(t)];
      if (tri < 0 || static_cast<std::size_t>(tri) >= triangles)
        refuse(at(name + ".triangles", static_cast<std::size_t>(t)), tri,
               "in [0, " + std::to_string(triangles) + ") (the triangle count of wall " + std::to_string(c.wall[k]) + ")");
    }
  }
}

WallContacts read_wall_contacts(Reader& r, const ContactModel* model, const ParticleStore& p,
                                const std::vector<Wall>& walls, bool surfaces) {
  const std::string name = surfaces ? "ball-surface contacts" : "ball-facet contacts";
  WallContacts c;
  c.surfaces = surfaces;
  c.ball = r.vec<std::int32_t>(name + ".ball"), c.wall = r.vec<std::int32_t>(name + ".wall");
  c.triangle_begin = r.vec<std::int32_t>(name + ".triangle_begin");
  c.triangle_end = r.vec<std::int32_t>(name + ".triangle_end");
  c.triangles = r.vec<std::int32_t>(name + ".triangles");
  c.force = r.vec<Vec3>(name + ".force"), c.torque_ball = r.vec<Vec3>(name + ".torque_ball");
  c.point = r.vec<Vec3>(name + ".point"), c.moment = r.vec<Vec3>(name + ".moment");
  c.normal_force = r.vec<double>(name + ".normal_force"), c.normal_stiffness = r.vec<double>(name + ".normal_stiffness");
  check_wall_contacts(c, p, walls);
  const std::size_t count = c.size();
  check_length(c.normal_force.size(), count, name + ".normal_force", "one per contact");
  fill_results(c.normal_force, count, name + ".normal_force");
  fill_results(c.force, count, name + ".force"), fill_results(c.torque_ball, count, name + ".torque_ball");
  fill_results(c.point, count, name + ".point"), fill_results(c.moment, count, name + ".moment");
  fill_results(c.normal_stiffness, count, name + ".normal_stiffness");
  read_states(r, model, c.state, count, name);
  return c;
}

/// The per-particle incidence lists (CSR) that the broad phase builds from a contact list.
std::pair<std::vector<std::int32_t>, std::vector<std::int32_t>> incidence(const PairContacts& c, std::size_t particles) {
  std::vector<std::int32_t> offsets(particles + 1, 0), entries(2 * c.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    ++offsets[static_cast<std::size_t>(c.first[k]) + 1];
    ++offsets[static_cast<std::size_t>(c.second[k]) + 1];
  }
  for (std::size_t i = 0; i < particles; ++i) offsets[i + 1] += offsets[i];
  std::vector<std::int32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::size_t k = 0; k < c.size(); ++k) {
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.first[k])]++)] = static_cast<std::int32_t>(2 * k);
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.second[k])]++)] = static_cast<std::int32_t>(2 * k + 1);
  }
  return {std::move(offsets), std::move(entries)};
}

/// Without a pending rebuild the next step uses the incidence lists as they are: they must be
/// exactly those of the contact list, or the force gather reads outside its arrays.
void check_incidence(const PairContacts& c, std::size_t particles, const std::vector<std::int32_t>& offsets,
                     const std::vector<std::int32_t>& entries, const std::string& name) {
  const auto expected = incidence(c, particles);
  if (offsets != expected.first || entries != expected.second)
    refuse(name + " incidence lists", std::to_string(offsets.size()) + " offsets, " + std::to_string(entries.size()) + " entries",
           "those of the contact list (" + std::to_string(particles + 1) + " offsets, " +
               std::to_string(expected.second.size()) + " entries) while need_rebuild = 0");
}

}  // namespace dem::checkpoint
