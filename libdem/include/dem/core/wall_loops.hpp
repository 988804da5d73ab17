// The ball-wall loops of contact_loops.hpp (which includes this header between its attribute
// macros; include that one): the closest point of each candidate's wall, then the law, one contact
// at a time or, for a lane law, in blocks of touching contacts as the pair loop does.
#pragma once

#if !defined(DEM_TARGET_AVX2)
#error "dem/core/wall_loops.hpp is part of dem/core/contact_loops.hpp: include that header"
#endif

namespace dem::detail {

/// One block of touching ball-wall contacts: the ball's side gathered, the wall's velocity, the
/// law's history copied out of (and back into) the contact store, and the results.
template <class State>
struct WallBlock : BlockHistory<State> {
  std::int64_t contact[pair_block];
  // inputs: d = closest point - centre and its squared length (from the closest-point search),
  // the ball's radius, velocity, spin and inverse mass, the wall's velocity
  double dx[pair_block], dy[pair_block], dz[pair_block], dist_sq[pair_block];
  double radius[pair_block], inv_mass[pair_block];
  double vx[pair_block], vy[pair_block], vz[pair_block], wx[pair_block], wy[pair_block], wz[pair_block];
  double wall_vx[pair_block], wall_vy[pair_block], wall_vz[pair_block];
  // results: force on the wall, torque on the ball, rolling moment, the arm x_c - x_ball, elastic
  // normal force and stiffness, overlap
  double fx[pair_block], fy[pair_block], fz[pair_block];
  double tx[pair_block], ty[pair_block], tz[pair_block], mx[pair_block], my[pair_block], mz[pair_block];
  double ax[pair_block], ay[pair_block], az[pair_block];
  double normal_force[pair_block], normal_stiffness[pair_block], overlap[pair_block];
};

/// Kinematics, law and torque of the `count` contacts of a wall block: wall_range's arithmetic
/// in the same order, lane by lane (same bits).
template <LaneContactLaw Law, int Variant>
DEM_HOT_INLINE void block_lanes(const typename Law::Params& shared_params, WallBlock<typename Law::State>& b,
                                int count, double dt, ContactKind) {
  const typename Law::Params params = shared_params;  // as in the pair block: no reloads in the loop
DEM_INDEPENDENT_ITERATIONS
  for (int m = 0; m < count; ++m) {
    const Lane3 d{b.dx[m], b.dy[m], b.dz[m]};
    const double r = b.radius[m];
    const double dist = std::sqrt(b.dist_sq[m]);
    LaneKinematics kin;
    kin.normal = (1.0 / dist) * d;
    kin.overlap = r - dist;
    const Lane3 arm = (r - 0.5 * kin.overlap) * kin.normal;  // x_c - x_ball
    const Lane3 v{b.vx[m], b.vy[m], b.vz[m]}, w{b.wx[m], b.wy[m], b.wz[m]};
    kin.relative_velocity = Lane3{b.wall_vx[m], b.wall_vy[m], b.wall_vz[m]} - (v + cross(w, arm));
    kin.relative_angular_velocity = -w;
    kin.radius_1 = r;
    kin.radius_2 = 0.0;
    kin.effective_radius = r;
    kin.effective_mass = 1.0 / b.inv_mass[m];
    kin.dt = dt;
    kin.kind = ContactKind::BallFacet;
    typename Law::State state;
    b.store_history(m, reinterpret_cast<std::byte*>(&state));
    const LaneForce out = lane_force<Law, Variant>(params, kin, state);
    b.load_history(m, reinterpret_cast<const std::byte*>(&state));
    const Lane3 torque = -cross(arm, out.force) - out.moment;
    b.fx[m] = out.force.x, b.fy[m] = out.force.y, b.fz[m] = out.force.z;
    b.tx[m] = torque.x, b.ty[m] = torque.y, b.tz[m] = torque.z;
    b.mx[m] = out.moment.x, b.my[m] = out.moment.y, b.mz[m] = out.moment.z;
    b.ax[m] = arm.x, b.ay[m] = arm.y, b.az[m] = arm.z;
    b.normal_force[m] = out.normal_force;
    b.normal_stiffness[m] = out.normal_stiffness;
    b.overlap[m] = kin.overlap;
  }
}

/// Candidate k found apart from its wall: its history ends and its records are zeroed.
template <class State>
void end_wall_contact(WallContacts& c, std::int64_t k, const Vec3& centre) {
  state_at<State>(c.state, static_cast<std::size_t>(k)) = State{};
  c.force[k].setZero();
  c.torque_ball[k].setZero();
  c.moment[k].setZero();
  c.point[k] = centre;  // defined bytes in restart files, and a harmless point if read
  c.normal_force[k] = 0.0;
  c.normal_stiffness[k] = 0.0;
}

/// Candidate k's closest point on its wall and its squared distance from the ball's centre; false
/// when the ball is another process's (its records are left) or apart from the wall (its history
/// ends and its records are zeroed).
template <class State, class Closest>
DEM_HOT_INLINE bool touching_wall(WallContacts& c, const KernelContext& ctx, std::int64_t k, const Closest& closest_of,
                                  Vec3& closest, double& best_sq) {
  if (c.ball[k] < ctx.owned_begin || c.ball[k] >= ctx.owned_end) return false;  // another process's ball
  const auto b = static_cast<std::size_t>(c.ball[k]);
  const Vec3& centre = ctx.particles->x[b];
  best_sq = std::numeric_limits<double>::infinity();
  closest = closest_of(k, (*ctx.walls)[static_cast<std::size_t>(c.wall[k])], centre, best_sq);
  const double r = ctx.particles->radius[b];
  if (best_sq >= r * r || best_sq == 0.0) {
    end_wall_contact<State>(c, k, centre);
    return false;
  }
  return true;
}

/// The wall loop over candidates [begin, end), one contact at a time.
template <ContactLaw Law, class Closest>
void wall_range(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx, std::int64_t begin,
                std::int64_t end, const Closest& closest_of, OverlapMonitor& local) {
  using State = typename Law::State;
  const ParticleStore& p = *ctx.particles;
  const std::vector<Wall>& walls = *ctx.walls;
  for (std::int64_t k = begin; k < end; ++k) {
    Vec3 closest;
    double best_sq;
    if (!touching_wall<State>(c, ctx, k, closest_of, closest, best_sq)) continue;
    const auto b = static_cast<std::size_t>(c.ball[k]);
    const Wall& wall = walls[static_cast<std::size_t>(c.wall[k])];
    const Vec3& centre = p.x[b];
    const double r = p.radius[b];
    State& state = state_at<State>(c.state, static_cast<std::size_t>(k));
    const double dist = std::sqrt(best_sq);
    ContactKinematics kin;
    kin.normal = (closest - centre) * (1.0 / dist);
    kin.overlap = r - dist;
    const Vec3 arm = (r - 0.5 * kin.overlap) * kin.normal;  // x_c - x_ball
    kin.relative_velocity = wall.velocity - (p.v[b] + p.w[b].cross(arm));
    kin.relative_angular_velocity = -p.w[b];
    kin.radius_1 = r;
    kin.radius_2 = 0.0;
    kin.effective_radius = r;
    kin.effective_mass = 1.0 / p.inv_mass[b];
    kin.dt = ctx.dt;
    kin.kind = ContactKind::BallFacet;
    const ContactForce out = Law::force(params, kin, state);
    c.force[k] = out.force;
    c.torque_ball[k] = -arm.cross(out.force) - out.moment;
    c.point[k] = centre + arm;
    c.moment[k] = out.moment;
    c.normal_force[k] = out.normal_force;
    c.normal_stiffness[k] = out.normal_stiffness;
    note_overlap(local, kin.overlap, r, k);
  }
}

/// Candidates ahead whose ball the wall loop asks for: a wall's balls lie two to a row of cells
/// (the row runs from the bottom plate to the top one), so each is a line of its own, from main
/// memory on a large specimen.
inline constexpr std::int64_t wall_prefetch_distance = 8;

/// Starts loading the lines of ball b that a wall contact reads.
DEM_HOT_INLINE void prefetch_wall_ball(const ParticleStore& p, std::int32_t b) {
  const auto i = static_cast<std::size_t>(b);
  DEM_PREFETCH_FOR_READ(&p.x[i]);
  DEM_PREFETCH_FOR_READ(&p.v[i]);
  DEM_PREFETCH_FOR_READ(&p.w[i]);
  DEM_PREFETCH_FOR_READ(&p.radius[i]);
  DEM_PREFETCH_FOR_READ(&p.inv_mass[i]);
}

/// wall_range for a lane law: the closest points one candidate at a time, the law in blocks of the
/// touching ones. Each contact writes only its own records, so the order of the blocks is free.
template <LaneContactLaw Law, class Closest>
void wall_range_lanes(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx,
                      std::int64_t begin, std::int64_t end, const Closest& closest_of, OverlapMonitor& local) {
  using State = typename Law::State;
  const ParticleStore& p = *ctx.particles;
  const std::vector<Wall>& walls = *ctx.walls;
  WallBlock<State> b;
  const BlockKernel<Law, WallBlock<State>> compute_block = block_kernel<Law, WallBlock<State>>(params, block_isa());
  for (std::int64_t k = begin; k < end;) {
    int count = 0;
    for (; k < end && count < pair_block; ++k) {
      if (k + wall_prefetch_distance < end) prefetch_wall_ball(p, c.ball[k + wall_prefetch_distance]);
      Vec3 closest;
      double best_sq;
      if (!touching_wall<State>(c, ctx, k, closest_of, closest, best_sq)) continue;
      const auto i = static_cast<std::size_t>(c.ball[k]);
      const Wall& wall = walls[static_cast<std::size_t>(c.wall[k])];
      const double r = p.radius[i];
      const Vec3 d = closest - p.x[i];
      b.contact[count] = k;
      b.dx[count] = d.x(), b.dy[count] = d.y(), b.dz[count] = d.z();
      b.dist_sq[count] = best_sq;
      b.radius[count] = r, b.inv_mass[count] = p.inv_mass[i];
      b.vx[count] = p.v[i].x(), b.vy[count] = p.v[i].y(), b.vz[count] = p.v[i].z();
      b.wx[count] = p.w[i].x(), b.wy[count] = p.w[i].y(), b.wz[count] = p.w[i].z();
      b.wall_vx[count] = wall.velocity.x(), b.wall_vy[count] = wall.velocity.y(), b.wall_vz[count] = wall.velocity.z();
      b.load_history(count, c.state.at(static_cast<std::size_t>(k)));
      ++count;
    }
    compute_block(params, b, count, ctx.dt, ContactKind::BallFacet);
    for (int m = 0; m < count; ++m) {
      const std::int64_t k_m = b.contact[m];
      b.store_history(m, c.state.at(static_cast<std::size_t>(k_m)));
      c.force[k_m] = Vec3(b.fx[m], b.fy[m], b.fz[m]);
      c.torque_ball[k_m] = Vec3(b.tx[m], b.ty[m], b.tz[m]);
      c.point[k_m] = p.x[static_cast<std::size_t>(c.ball[k_m])] + Vec3(b.ax[m], b.ay[m], b.az[m]);
      c.moment[k_m] = Vec3(b.mx[m], b.my[m], b.mz[m]);
      c.normal_force[k_m] = b.normal_force[m];
      c.normal_stiffness[k_m] = b.normal_stiffness[m];
      note_overlap(local, b.overlap[m], b.radius[m], k_m);
    }
  }
}

/// One thread's share of the wall loop: blocks for a lane law where they pay (lanes_worthwhile), one
/// contact at a time otherwise.
template <ContactLaw Law, class Closest>
void wall_share(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx, std::int64_t begin,
                std::int64_t end, const Closest& closest_of, OverlapMonitor& local) {
  if constexpr (LaneContactLaw<Law>) {
    if (lanes_worthwhile()) return wall_range_lanes<Law>(params, c, ctx, begin, end, closest_of, local);
  }
  wall_range<Law>(params, c, ctx, begin, end, closest_of, local);
}

/// Adds the touching contacts [begin, end) of c, in order, into their balls' sums (force, torque)
/// and their walls' totals (KernelContext::wall_totals; the World's own loop when it adds them
/// after the loops).
inline void add_wall_contacts(const WallContacts& c, std::int64_t begin, std::int64_t end, Vec3* force, Vec3* torque,
                              std::vector<Wall>& walls) {
  for (std::int64_t k = begin; k < end; ++k) {
    if (k + wall_prefetch_distance < end) {
      const auto ahead = static_cast<std::size_t>(c.ball[static_cast<std::size_t>(k + wall_prefetch_distance)]);
      DEM_PREFETCH_FOR_WRITE(&force[ahead]);
      DEM_PREFETCH_FOR_WRITE(&torque[ahead]);
    }
    if (c.normal_stiffness[static_cast<std::size_t>(k)] == 0.0) continue;
    const auto b = static_cast<std::size_t>(c.ball[static_cast<std::size_t>(k)]);
    const Vec3& f = c.force[static_cast<std::size_t>(k)];
    Wall& w = walls[static_cast<std::size_t>(c.wall[static_cast<std::size_t>(k)])];
    force[b] -= f;
    torque[b] += c.torque_ball[static_cast<std::size_t>(k)];
    w.force += f;
    w.moment += (c.point[static_cast<std::size_t>(k)] - w.reference_point).cross(f) + c.moment[static_cast<std::size_t>(k)];
    ++w.contact_count;
    w.stiffness_sum += c.normal_stiffness[static_cast<std::size_t>(k)];
  }
}

/// The wall loop over c's candidates: `closest(k, wall, centre, best_sq)` gives the closest point of
/// candidate k's wall to the ball's centre and its squared distance; the law and the records are
/// the same for every wall geometry. `work` weighs the candidates for the thread count.
template <ContactLaw Law, class Closest>
void wall_loop(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx, OverlapMonitor& worst,
               std::int64_t work, const Closest& closest_of) {
  const std::int64_t count = static_cast<std::int64_t>(c.size());
  c.force.resize(c.size());
  c.torque_ball.resize(c.size());
  c.point.resize(c.size());
  c.moment.resize(c.size());
  c.normal_force.resize(c.size());
  c.normal_stiffness.resize(c.size());
  const int threads = threads_for(work, ctx.threads);
  // Each contact writes only its own records: the same results for any thread count and split.
  // Then each thread adds its share into the sums when the shares before it are in (`turn`).
  std::atomic<std::int64_t> turn{0};
#pragma omp parallel num_threads(open_team(threads))
  {
    OverlapMonitor local;
#if defined(_OPENMP)
    const std::int64_t team = omp_get_num_threads(), me = omp_get_thread_num();
#else
    const std::int64_t team = 1, me = 0;
#endif
    // Shares sized by the threads' speeds (KernelContext::thread_fractions), so that the thread
    // on the faster core does not wait. (Shares of equal work, counting the touching candidates
    // as heavier, cost more to plan every step than they saved on the 14k benchmark.)
    const std::int64_t begin = share_begin(count, ctx.thread_fractions, team, me);
    const std::int64_t end = share_begin(count, ctx.thread_fractions, team, me + 1);
    wall_share<Law>(params, c, ctx, begin, end, closest_of, local);
    if (ctx.wall_totals) {
      // Waiting is rare (the shares are sized to end together); a thread that waits for one
      // without a core yields it.
      for (int spins = 0; turn.load(std::memory_order_acquire) != me;)
        if (spins < 64) ++spins;
        else std::this_thread::yield();
      add_wall_contacts(c, begin, end, ctx.scatter_force, ctx.scatter_torque, *ctx.wall_totals);
      turn.store(me + 1, std::memory_order_release);
    }
#pragma omp critical(dem_overlap_monitor)
    merge_worst(worst, local);
  }
}

template <ContactLaw Law>
void compute_walls(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx,
                   OverlapMonitor& worst) {
  if (c.surfaces) {
    // Counted as one pair candidate each, the 14k benchmark's 3,400 candidates ran on one thread,
    // a tenth of a two-thread step.
    wall_loop<Law>(params, c, ctx, worst, analytic_wall_weight * static_cast<std::int64_t>(c.size()),
                   [](std::int64_t, const Wall& wall, const Vec3& centre, double& best_sq) {
                     const Vec3 closest = wall.surface.closest_point(centre);
                     best_sq = (closest - centre).squaredNorm();
                     return closest;
                   });
    return;
  }
  // Worth threads by the triangles tested, not the contacts: a ball near a curved wall tests
  // several, each a closest-point search (triangle_test_weight). (The 14k benchmark cylinder has
  // 3,400 candidates and 9,500 triangle tests; counted by candidates they ran on one thread, a
  // fifth of a two-thread step.)
  const auto triangle_tests = static_cast<std::int64_t>(c.triangles.size());
  wall_loop<Law>(params, c, ctx, worst, triangle_test_weight * triangle_tests,
                 [&c](std::int64_t k, const Wall& wall, const Vec3& centre, double& best_sq) {
                   // The closest point over the candidate triangles: one contact per ball and wall.
                   Vec3 closest = Vec3::Zero();
                   for (std::int32_t t = c.triangle_begin[k]; t < c.triangle_end[k]; ++t) {
                     const auto& tri = wall.mesh.triangles[static_cast<std::size_t>(c.triangles[static_cast<std::size_t>(t)])];
                     const geometry::ClosestPoint cp = geometry::closest_point_on_triangle(
                         centre, wall.mesh.vertices[static_cast<std::size_t>(tri[0])],
                         wall.mesh.vertices[static_cast<std::size_t>(tri[1])],
                         wall.mesh.vertices[static_cast<std::size_t>(tri[2])]);
                     const double dsq = (cp.point - centre).squaredNorm();
                     if (dsq < best_sq) {
                       best_sq = dsq;
                       closest = cp.point;
                     }
                   }
                   return closest;
                 });
}

}  // namespace dem::detail
