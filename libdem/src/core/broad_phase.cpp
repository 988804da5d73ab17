// The broad phase (broad_phase.hpp): Verlet lists with contact history carried over by stable
// particle ids, the per-particle incidence lists for the fixed-order force gather, and the near
// lists that the contact loops run over.
#include <dem/core/broad_phase.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include <dem/base/errors.hpp>
#include <dem/base/threads.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/geometry/triangle.hpp>

namespace dem {

namespace {

using Key = std::uint64_t;

Key pair_key(ParticleId a, ParticleId b) {
  return (static_cast<Key>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// Runs `part(t, begin, end)` for `team` contiguous ranges of [0, count), one per thread (a team of
/// threads_for(count, threads), so that a small loop runs on one). A caller that joins the parts'
/// outputs in range order gets the serial result for any team.
template <class Part>
void in_ranges(std::int64_t count, int team, const Part& part) {
#pragma omp parallel for schedule(static) num_threads(open_team(team))
  for (int t = 0; t < team; ++t) part(t, count * t / team, count * (t + 1) / team);
}

/// Appends the parts' vectors `member` in order (the one part's is moved).
template <class Part, class T>
void join(std::vector<Part>& parts, std::vector<T> Part::*member, std::vector<T>& out) {
  if (parts.size() == 1) {
    out = std::move(parts.front().*member);
    return;
  }
  std::size_t total = 0;
  for (const Part& part : parts) total += (part.*member).size();
  out.clear();
  out.reserve(total);
  for (Part& part : parts) {
    out.insert(out.end(), (part.*member).begin(), (part.*member).end());
    std::vector<T>().swap(part.*member);
  }
}

/// The contacts touching in the last step, found again by their particles after a re-sort: each
/// is filed under the lower of its two storage indices, with the other one. The pair search emits
/// its candidates in order of that lower index, so the lookups walk these lists front to back
/// (a binary search over all contacts' keys missed the cache at every level; a third of a rebuild).
class TouchingPairs {
 public:
  /// Notes the touching contacts of `c` by their particles' stable ids (before a re-sort). By
  /// `touching`, which every step writes, not by the force records, which only some steps do.
  TouchingPairs(const PairContacts& c, const ParticleStore& p, int threads) {
    struct Part {
      std::vector<ParticleId> id_first, id_second;
      std::vector<std::int64_t> contact;
    };
    const auto count = static_cast<std::int64_t>(std::min(c.touching.size(), c.size()));
    const int team = threads_for(count, threads);
    std::vector<Part> parts(static_cast<std::size_t>(team));
    in_ranges(count, team, [&](int t, std::int64_t begin, std::int64_t end) {
      Part& out = parts[static_cast<std::size_t>(t)];
      for (std::int64_t k = begin; k < end; ++k)
        if (c.touching[static_cast<std::size_t>(k)] != 0) {
          out.id_first.push_back(p.id[static_cast<std::size_t>(c.first[static_cast<std::size_t>(k)])]);
          out.id_second.push_back(p.id[static_cast<std::size_t>(c.second[static_cast<std::size_t>(k)])]);
          out.contact.push_back(k);
        }
    });
    join(parts, &Part::id_first, id_first_);
    join(parts, &Part::id_second, id_second_);
    join(parts, &Part::contact, contact_);
  }

  /// Files them by the particles' storage indices now (after any re-sort).
  void index(const ParticleStore& p, int threads) {
    const std::size_t n = contact_.size();
    std::vector<std::int32_t> lower(n), upper(n);
    const auto count = static_cast<std::int64_t>(n);
    in_ranges(count, threads_for(count, threads), [&](int, std::int64_t begin, std::int64_t end) {
      for (auto m = static_cast<std::size_t>(begin); m < static_cast<std::size_t>(end); ++m) {
        const auto a = static_cast<std::int32_t>(p.index_of(id_first_[m]));
        const auto b = static_cast<std::int32_t>(p.index_of(id_second_[m]));
        lower[m] = std::min(a, b);
        upper[m] = std::max(a, b);
      }
    });
    offsets_.assign(p.size() + 1, 0);
    for (std::size_t m = 0; m < n; ++m) ++offsets_[static_cast<std::size_t>(lower[m]) + 1];
    for (std::size_t i = 0; i < p.size(); ++i) offsets_[i + 1] += offsets_[i];
    upper_.resize(n);
    contact_by_lower_.resize(n);
    std::vector<std::int32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t m = 0; m < n; ++m) {
      const auto slot = static_cast<std::size_t>(fill[static_cast<std::size_t>(lower[m])]++);
      upper_[slot] = upper[m];
      contact_by_lower_[slot] = contact_[m];
    }
    std::vector<ParticleId>().swap(id_first_);
    std::vector<ParticleId>().swap(id_second_);
    std::vector<std::int64_t>().swap(contact_);
  }

  /// The old index of the contact between storage indices i < j, or -1.
  std::int64_t find(std::int32_t i, std::int32_t j) const {
    for (auto s = offsets_[static_cast<std::size_t>(i)]; s < offsets_[static_cast<std::size_t>(i) + 1]; ++s)
      if (upper_[static_cast<std::size_t>(s)] == j) return contact_by_lower_[static_cast<std::size_t>(s)];
    return -1;
  }

 private:
  std::vector<ParticleId> id_first_, id_second_;
  std::vector<std::int64_t> contact_;
  std::vector<std::int32_t> offsets_, upper_;  // per lower index: the upper indices
  std::vector<std::int64_t> contact_by_lower_;  // and the old contact indices
};

/// `touching` of a new pair list: the contacts carried over are those that touched (TouchingPairs).
void mark_carried(PairContacts& fresh, const std::vector<std::int64_t>& source_of, int threads) {
  const auto count = static_cast<std::int64_t>(source_of.size());
  fresh.touching.resize(source_of.size());
  in_ranges(count, threads_for(count, threads), [&](int, std::int64_t begin, std::int64_t end) {
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k)
      fresh.touching[k] = source_of[k] >= 0 ? 1 : 0;
  });
}

/// The old index of `key` among the sorted (key, old index) pairs of the ball-facet contacts, or -1.
std::int64_t lookup(const std::vector<std::pair<Key, std::int64_t>>& keys, Key key) {
  const auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(key, std::int64_t{-1}));
  return (it != keys.end() && it->first == key) ? it->second : -1;
}

/// Moves the history and last normal forces of `old` onto the new candidate list.
template <class Contacts>
void carry_history(const ContactModel* model, Contacts& fresh, const Contacts& old,
                   const std::vector<std::int64_t>& source_of, int threads) {
  const auto count = static_cast<std::int64_t>(source_of.size());
  fresh.normal_force.resize(source_of.size());
  in_ranges(count, threads_for(count, threads), [&](int, std::int64_t begin, std::int64_t end) {
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k)
      fresh.normal_force[k] = source_of[k] >= 0 ? old.normal_force[static_cast<std::size_t>(source_of[k])] : 0.0;
  });
  if (model != nullptr) model->remap_states(old.state, source_of, fresh.state, threads);
}

/// The touching contacts of `c` as sorted (ball id, wall) keys with their index.
std::vector<std::pair<Key, std::int64_t>> touching_wall_keys(const WallContacts& c, const ParticleStore& p) {
  std::vector<std::pair<Key, std::int64_t>> keys;
  for (std::size_t k = 0; k < c.size() && k < c.normal_force.size(); ++k)
    if (c.normal_force[k] > 0.0)
      keys.emplace_back(pair_key(p.id[static_cast<std::size_t>(c.ball[k])], c.wall[k]), static_cast<std::int64_t>(k));
  std::sort(keys.begin(), keys.end());
  return keys;
}

/// Ball-surface candidates: every ball within its radius plus the skin of an analytic wall's
/// surface, in (ball, wall) order. One formula per ball and surface wall, as LAMMPS's wall/gran.
void find_surface_contacts(WorldState& state, const std::vector<std::pair<Key, std::int64_t>>& old_keys,
                           const ContactModel* model, double skin, int threads) {
  const ParticleStore& p = state.particles;
  std::vector<std::size_t> surface_walls;
  for (std::size_t w = 0; w < state.walls.size(); ++w)
    if (state.walls[w].surface.shape != AnalyticSurface::Shape::None) surface_walls.push_back(w);
  WallContacts fresh;
  fresh.surfaces = true;
  std::vector<std::int64_t> source;
  if (!surface_walls.empty()) {
    struct Part {
      std::vector<std::int32_t> ball, wall;
      std::vector<std::int64_t> source;
    };
    const auto count = static_cast<std::int64_t>(p.size());
    const int team = threads_for(count, threads);
    std::vector<Part> parts(static_cast<std::size_t>(team));
    in_ranges(count, team, [&](int t, std::int64_t begin, std::int64_t end) {
      Part& out = parts[static_cast<std::size_t>(t)];
      for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
        if (p.is_pebble(i)) continue;
        const double reach = p.radius[i] + skin;
        for (const std::size_t w : surface_walls)
          if ((state.walls[w].surface.closest_point(p.x[i]) - p.x[i]).squaredNorm() < reach * reach) {
            out.ball.push_back(static_cast<std::int32_t>(i));
            out.wall.push_back(static_cast<std::int32_t>(w));
            out.source.push_back(lookup(old_keys, pair_key(p.id[i], static_cast<std::int32_t>(w))));
          }
      }
    });
    join(parts, &Part::ball, fresh.ball);
    join(parts, &Part::wall, fresh.wall);
    join(parts, &Part::source, source);
  }
  WallContacts& now = state.contacts.ball_surface;
  carry_history(model, fresh, now, source, threads);
  now = std::move(fresh);
}

/// CSR incidence: for each particle, entries (contact * 2 + side) in contact order. Each thread
/// counts and then files a contiguous range of the contacts, after the earlier ranges' entries of
/// each particle: the lists are the same for any thread count.
void build_incidence(PairContacts& c, std::size_t particles, int threads) {
  std::vector<std::int32_t>& offsets = c.incidence_offsets;
  std::vector<std::int32_t>& entries = c.incidence_entries;
  const auto count = static_cast<std::int64_t>(c.size());
  const int team = threads_for(count, threads);
  // per range: how many entries each particle has in it, then where its next entry goes
  std::vector<std::vector<std::int32_t>> slot(static_cast<std::size_t>(team));
  in_ranges(count, team, [&](int t, std::int64_t begin, std::int64_t end) {
    std::vector<std::int32_t>& mine = slot[static_cast<std::size_t>(t)];
    mine.assign(particles, 0);
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      ++mine[static_cast<std::size_t>(c.first[k])];
      ++mine[static_cast<std::size_t>(c.second[k])];
    }
  });
  offsets.assign(particles + 1, 0);
  for (std::size_t i = 0; i < particles; ++i) {
    std::int32_t at = offsets[i];
    for (auto& mine : slot) {
      const std::int32_t n = mine[i];
      mine[i] = at;
      at += n;
    }
    offsets[i + 1] = at;
  }
  entries.resize(2 * c.size());
  in_ranges(count, team, [&](int t, std::int64_t begin, std::int64_t end) {
    std::vector<std::int32_t>& fill = slot[static_cast<std::size_t>(t)];
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.first[k])]++)] = static_cast<std::int32_t>(2 * k);
      entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.second[k])]++)] = static_cast<std::int32_t>(2 * k + 1);
    }
  });
}

}  // namespace

bool BroadPhase::needs_rebuild(const WorldState& state) {
  const RebuildRecord& record = state.rebuild;
  if (record.need_rebuild) return true;
  const double travel = std::sqrt(record.max_travel_sq);
  // Two particles, one of them seen through an image that moved with the cell's edges.
  if (state.cell) return 2.0 * travel + state.cell->image_travel_since(record.cell_at_rebuild) > record.skin;
  return 2.0 * travel > record.skin || travel + record.max_wall_travel > record.skin;
}

void BroadPhase::find_periodic_candidates(WorldState& state, int threads, bool resort, std::vector<std::int32_t>& first,
                                          std::vector<std::int32_t>& second, std::vector<std::uint8_t>& image) {
  ParticleStore& p = state.particles;
  state.cell->remap_tilt();  // a cell sheared far: an equivalent, less skewed one (same images)
  const PeriodicCell& cell = *state.cell;
  // A particle that has left the cell comes back through the opposite face as its own image:
  // x - h m, moving at v - L h m (in a deforming cell the image's velocity differs by the flow's).
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(open_team(threads_for(n, threads)))
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const std::array<int, 3> m = cell.cells_out(p.x[i]);
    if (m[0] == 0 && m[1] == 0 && m[2] == 0) continue;
    p.x[i] -= cell.image_shift(m);
    p.v[i] -= cell.image_velocity_shift(m);
  }
  double max_radius = 0.0;
  for (double r : p.radius) max_radius = std::max(max_radius, r);
  const double search = 2.0 * max_radius + state.rebuild.skin;
  const std::array<int, 3> dims = PeriodicGrid::dims_for(cell.widths(), search);
  if (std::min({dims[0], dims[1], dims[2]}) < 3) {
    std::ostringstream widths;
    widths << "(" << cell.widths().transpose() << ") m";
    require(false, "periodic cell widths (distances between opposite faces)", widths.str(),
            "at least 3 x (largest diameter + skin) = " + std::to_string(3.0 * search) +
                " m on every axis, so that a particle reaches at most one image of another: make the cell larger");
  }
  periodic_grid_.build(p.x, cell.inverse(), cell.origin(), dims, threads);
  if (resort && p.size() > 1) {
    p.permute(periodic_grid_.cell_order(), threads);
    periodic_grid_.renumber_in_cell_order();
  }
  find_periodic_pairs_in(periodic_grid_, p.x, cell.matrix(), p.radius, state.rebuild.skin, threads, first, second, image);
  state.rebuild.cell_at_rebuild = cell.matrix();
}

double resolved_skin(const WorldState& state) {
  if (state.settings.skin > 0.0) return state.settings.skin;
  const ParticleStore& p = state.particles;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) smallest = std::min(smallest, p.radius[i]);
  // Half the smallest radius: rebuilds every few tens of steps in quasi-static runs, and few
  // extra candidate pairs (the peers' benchmark inputs use the same, a quarter diameter).
  return std::isfinite(smallest) ? 0.5 * smallest : 1e-3;
}

void BroadPhase::rebuild(WorldState& state, const ContactModelTable& models, int threads, bool resort) {
  ParticleStore& p = state.particles;
  PairContacts& ball_ball = state.contacts.ball_ball;
  PairContacts& ball_pebble = state.contacts.ball_pebble;
  WallContacts& ball_facet = state.contacts.ball_facet;
  const std::vector<Wall>& walls = state.walls;
  RebuildRecord& record = state.rebuild;
  const double skin = resolved_skin(state);
  record.skin = skin;

  // History of the last step, keyed by stable ids (storage indices change when re-sorting).
  TouchingPairs old_bb(ball_ball, p, threads), old_bp(ball_pebble, p, threads);
  const auto old_wall_keys = touching_wall_keys(ball_facet, p);
  const auto old_surface_keys = touching_wall_keys(state.contacts.ball_surface, p);

  // Cells of at least the largest diameter plus the skin. After a re-sort the particles are in
  // the grid's own order: the grid of the new storage follows without binning them again.
  // In a periodic cell, the particles wrapped into it and its own grid (find_periodic_candidates).
  std::vector<std::int32_t> first, second;
  std::vector<std::uint8_t> image;  // per candidate, in a periodic cell
  if (state.cell) {
    find_periodic_candidates(state, threads, resort, first, second, image);
  } else {
    double max_radius = 0.0;
    for (double r : p.radius) max_radius = std::max(max_radius, r);
    grid_.build(p.x, 2.0 * max_radius + skin, 0.0, threads);
    if (resort && p.size() > 1) {
      p.permute(grid_.cell_order(), threads);
      grid_.renumber_in_cell_order();
    }
  }
  old_bb.index(p, threads);
  old_bp.index(p, threads);

  // Candidate pairs, split by contact type; piece 1 is always a ball. Each thread splits a
  // contiguous range of the candidates, and the ranges are joined in order.
  if (!state.cell) find_pairs_in(grid_, p.x, p.radius, skin, threads, first, second);
  const bool periodic = state.cell.has_value();
  struct Split {
    std::vector<std::int32_t> bb_first, bb_second, bp_first, bp_second;
    std::vector<std::int64_t> bb_source, bp_source;
    std::vector<std::uint8_t> bb_image;
  };
  const auto candidates = static_cast<std::int64_t>(first.size());
  const int team = threads_for(candidates, threads);
  std::vector<Split> parts(static_cast<std::size_t>(team));
  const bool pebble_pebble = state.settings.pebble_pebble_contacts;
  in_ranges(candidates, team, [&](int t, std::int64_t begin, std::int64_t end) {
    Split& out = parts[static_cast<std::size_t>(t)];
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      std::int32_t a = first[k], b = second[k];  // a < b, in order of a
      const bool a_pebble = p.is_pebble(static_cast<std::size_t>(a));
      const bool b_pebble = p.is_pebble(static_cast<std::size_t>(b));
      if (!a_pebble && !b_pebble) {
        // Orient by stable id, so that re-sorting never flips a contact (its history is directional).
        const bool flip = p.id[static_cast<std::size_t>(a)] > p.id[static_cast<std::size_t>(b)];
        if (flip) std::swap(a, b);
        if (periodic) out.bb_image.push_back(flip ? opposite_image(image[k]) : image[k]);  // as seen from a
        out.bb_source.push_back(old_bb.find(first[k], second[k]));
        out.bb_first.push_back(a);
        out.bb_second.push_back(b);
        continue;
      }
      if (a_pebble && b_pebble) {
        if (!pebble_pebble || p.clump[static_cast<std::size_t>(a)] == p.clump[static_cast<std::size_t>(b)]) continue;
        if (p.id[static_cast<std::size_t>(a)] > p.id[static_cast<std::size_t>(b)]) std::swap(a, b);
      } else if (a_pebble) {
        std::swap(a, b);
      }
      out.bp_source.push_back(old_bp.find(first[k], second[k]));
      out.bp_first.push_back(a);
      out.bp_second.push_back(b);
    }
  });
  std::vector<std::int32_t>().swap(first);  // split: free them before the histories are copied
  std::vector<std::int32_t>().swap(second);
  PairContacts bb, bp;
  bb.kind = ContactKind::BallBall;
  bp.kind = ContactKind::BallPebble;
  std::vector<std::int64_t> bb_source, bp_source;
  join(parts, &Split::bb_first, bb.first);
  join(parts, &Split::bb_second, bb.second);
  join(parts, &Split::bb_source, bb_source);
  join(parts, &Split::bb_image, bb.image);
  join(parts, &Split::bp_first, bp.first);
  join(parts, &Split::bp_second, bp.second);
  join(parts, &Split::bp_source, bp_source);
  const auto model = [&models](ContactKind kind) { return models[static_cast<std::size_t>(kind)].get(); };
  carry_history(model(ContactKind::BallBall), bb, ball_ball, bb_source, threads);
  carry_history(model(ContactKind::BallPebble), bp, ball_pebble, bp_source, threads);
  mark_carried(bb, bb_source, threads);
  mark_carried(bp, bp_source, threads);
  // The incidence lists are remade below: into the old ones' memory, not freshly touched pages.
  bb.incidence_offsets = std::move(ball_ball.incidence_offsets), bb.incidence_entries = std::move(ball_ball.incidence_entries);
  bp.incidence_offsets = std::move(ball_pebble.incidence_offsets), bp.incidence_entries = std::move(ball_pebble.incidence_entries);
  ball_ball = std::move(bb);
  ball_pebble = std::move(bp);
  build_incidence(ball_ball, p.size(), threads);
  build_incidence(ball_pebble, p.size(), threads);

  // Ball-facet candidates: balls within (radius + skin) of a triangle, grouped per (ball, wall).
  struct Candidate {
    std::int32_t ball, wall, triangle;
  };
  std::vector<Candidate> found;
  double max_ball_radius = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) max_ball_radius = std::max(max_ball_radius, p.radius[i]);
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const auto& mesh = walls[w].mesh;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
      const Vec3& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
      const Vec3 pad = Vec3::Constant(max_ball_radius + skin);
      const auto lo = grid_.cell_of(a.cwiseMin(b).cwiseMin(c) - pad);
      const auto hi = grid_.cell_of(a.cwiseMax(b).cwiseMax(c) + pad);
      for (int iz = lo[2]; iz <= hi[2]; ++iz)
        for (int iy = lo[1]; iy <= hi[1]; ++iy)
          for (int ix = lo[0]; ix <= hi[0]; ++ix) {
            const std::int64_t cell = grid_.linear(ix, iy, iz);
            for (const std::int32_t* it = grid_.begin(cell); it != grid_.end(cell); ++it) {
              const auto i = static_cast<std::size_t>(*it);
              if (p.is_pebble(i)) continue;
              const double reach = p.radius[i] + skin;
              const auto cp = geometry::closest_point_on_triangle(p.x[i], a, b, c);
              if ((cp.point - p.x[i]).squaredNorm() < reach * reach)
                found.push_back({*it, static_cast<std::int32_t>(w), static_cast<std::int32_t>(t)});
            }
          }
    }
  }
  std::sort(found.begin(), found.end(), [](const Candidate& l, const Candidate& r) {
    return std::tie(l.ball, l.wall, l.triangle) < std::tie(r.ball, r.wall, r.triangle);
  });
  WallContacts wc;
  std::vector<std::int64_t> wall_source;
  for (std::size_t k = 0; k < found.size(); ++k) {
    if (k == 0 || found[k].ball != found[k - 1].ball || found[k].wall != found[k - 1].wall) {
      if (!wc.ball.empty()) wc.triangle_end.push_back(static_cast<std::int32_t>(wc.triangles.size()));
      wc.ball.push_back(found[k].ball);
      wc.wall.push_back(found[k].wall);
      wc.triangle_begin.push_back(static_cast<std::int32_t>(wc.triangles.size()));
      wall_source.push_back(lookup(old_wall_keys, pair_key(p.id[static_cast<std::size_t>(found[k].ball)], found[k].wall)));
    }
    wc.triangles.push_back(found[k].triangle);
  }
  if (!wc.ball.empty()) wc.triangle_end.push_back(static_cast<std::int32_t>(wc.triangles.size()));
  carry_history(model(ContactKind::BallFacet), wc, ball_facet, wall_source, threads);
  ball_facet = std::move(wc);
  find_surface_contacts(state, old_surface_keys, model(ContactKind::BallFacet), skin, threads);

  record.x_at_rebuild = p.x;
  record.max_travel_sq = 0.0;
  record.max_wall_travel = 0.0;
  record.wall_disp_at_rebuild.clear();
  for (const auto& w : walls) record.wall_disp_at_rebuild.push_back(w.displacement);
  record.need_rebuild = false;
  ++record.rebuilds;
  near_stale_ = true;
}

bool BroadPhase::near_stale(const WorldState& state) const {
  if (state.cell)
    return near_stale_ || 2.0 * std::sqrt(max_near_travel_sq_) + state.cell->image_travel_since(cell_at_near_) > near_skin_;
  return near_stale_ || 2.0 * std::sqrt(max_near_travel_sq_) > near_skin_;
}

void BroadPhase::refresh_near(const WorldState& state, StepPlan& plan, int threads_available) {
  const ParticleStore& p = state.particles;
  near_skin_ = state.settings.near_skin > 0.0 ? state.settings.near_skin : 0.2 * state.rebuild.skin;
  std::optional<ImageShifts> images;
  if (state.cell) images = state.cell->image_shifts(), cell_at_near_ = state.cell->matrix();
  const ImageShifts* shifts = images ? &*images : nullptr;
  state.contacts.for_each_pair_set([&](const PairContacts& c) {
    // A candidate left out is more than near_skin apart now, so it cannot touch before some
    // particle has moved half of that, when the list is made again. One that touched in the
    // last step stays in, so that the loop ends its history as usual.
    // Each thread lists a contiguous range of candidates; the lists are joined in range order,
    // so the near list is the same for any thread count.
    const auto count = static_cast<std::int64_t>(c.size());
    const int threads = threads_for(count, threads_available);
    std::vector<std::vector<std::int32_t>> local(static_cast<std::size_t>(threads));
#pragma omp parallel for schedule(static) num_threads(open_team(threads))
    for (int t = 0; t < threads; ++t) {
      std::vector<std::int32_t>& out = local[static_cast<std::size_t>(t)];
      const std::int64_t begin = count * t / threads, end = count * (t + 1) / threads;
      for (std::int64_t k = begin; k < end; ++k) {
        const auto i = static_cast<std::size_t>(c.first[static_cast<std::size_t>(k)]);
        const auto j = static_cast<std::size_t>(c.second[static_cast<std::size_t>(k)]);
        const double reach = p.radius[i] + p.radius[j] + near_skin_;
        if (c.touching[static_cast<std::size_t>(k)] ||
            contact_branch(c, static_cast<std::size_t>(k), p.x.data(), shifts).squaredNorm() < reach * reach)
          out.push_back(static_cast<std::int32_t>(k));
      }
    }
    std::vector<std::int32_t>& near = plan.pairs(c.kind).near;
    near.clear();
    for (const auto& part : local) near.insert(near.end(), part.begin(), part.end());
  });
  x_at_near_ = p.x;
  max_near_travel_sq_ = 0.0;
  near_stale_ = false;
  ++near_refreshes_;
}

}  // namespace dem
