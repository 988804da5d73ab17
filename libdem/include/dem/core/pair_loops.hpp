// The pair loops of contact_loops.hpp (which includes this header between its attribute macros;
// include that one): ball-ball and ball-pebble contacts over the near candidates of the step's
// plan (PairPlan), one contact at a time or, for a lane law, in blocks of touching contacts, each
// contact's force and torque added into its particles' sums in contact order, with the threads'
// shares and the deferred parts of shared particles as the plan says.
#pragma once

#if !defined(DEM_TARGET_AVX2)
#error "dem/core/pair_loops.hpp is part of dem/core/contact_loops.hpp: include that header"
#endif

namespace dem::detail {

/// A candidate found separated: its history ends (docs/model.md 1.1) and its records are zeroed.
template <class State>
void end_contact(PairContacts& c, std::int64_t k) {
  state_at<State>(c.state, static_cast<std::size_t>(k)) = State{};
  c.force[k].setZero();
  c.normal_force[k] = 0.0;
  c.touching[static_cast<std::size_t>(k)] = 0;
}

/// sum += v and sum -= v, component by component (Eigen's arithmetic, the same bits). Plain doubles
/// in: an Eigen vector built from a block's arrays goes through the stack, and reading it back
/// as one 16-byte load waits for its separate 8-byte stores.
DEM_HOT_INLINE void add_into(Vec3& sum, const Lane3& v) { sum.x() += v.x, sum.y() += v.y, sum.z() += v.z; }
DEM_HOT_INLINE void subtract_from(Vec3& sum, const Lane3& v) { sum.x() -= v.x, sum.y() -= v.y, sum.z() -= v.z; }

/// Which of a contact's parts a loop adds into the particles' sums itself, and which it leaves in
/// a list for the engine to add once the contacts before it have added theirs: the first share
/// adds all; a later share defers the particles shared with other shares (StepPlan::shared);
/// a chunk taken from another thread's share defers all, since that share's own thread may still
/// be adding into the same particles.
enum class Sums { direct, defer_shared, defer_all };

/// Adds contact k (force `f` on piece 2, torques on both pieces) into its particles' sums, in the
/// caller's contact order, or leaves a part in `later` (Sums).
template <Sums Mode>
DEM_HOT_INLINE void add_to_particles(const KernelContext& ctx, std::vector<DeferredSum>* later, std::size_t i,
                                     std::size_t j, const Lane3& f, const Lane3& torque_first,
                                     const Lane3& torque_second) {
  const bool defer_first = Mode == Sums::defer_all || (Mode == Sums::defer_shared && ctx.shared[i] != 0);
  const bool defer_second = Mode == Sums::defer_all || (Mode == Sums::defer_shared && ctx.shared[j] != 0);
  if (defer_first) later->push_back({static_cast<std::int32_t>(i), true, f, torque_first});
  else {
    subtract_from(ctx.scatter_force[i], f);
    add_into(ctx.scatter_torque[i], torque_first);
  }
  if (defer_second) later->push_back({static_cast<std::int32_t>(j), false, f, torque_second});
  else {
    add_into(ctx.scatter_force[j], f);
    add_into(ctx.scatter_torque[j], torque_second);
  }
}

/// Adds the parts `add_to_particles` deferred, in the order they were deferred: the same
/// operations on the same values as the direct sums, so the same bits.
inline void add_deferred(const KernelContext& ctx, const std::vector<DeferredSum>& later) {
  for (const DeferredSum& d : later) {
    const auto i = static_cast<std::size_t>(d.particle);
    if (d.first_piece) subtract_from(ctx.scatter_force[i], d.force);
    else add_into(ctx.scatter_force[i], d.force);
    add_into(ctx.scatter_torque[i], d.torque);
  }
}

/// The pair loop over the near candidates near[begin, end) (PairPlan::near): a chunk of one
/// thread's share, its sums added or left in `later` as `Mode` says.
/// `periodic`: piece 2 is the image PairContacts::image names (KernelContext::images).
template <ContactLaw Law, Sums Mode, bool periodic>
void pair_range(const typename Law::Params& params, PairContacts& c, const std::vector<std::int32_t>& near,
                const KernelContext& ctx, std::int64_t begin, std::int64_t end, std::vector<DeferredSum>* later,
                OverlapMonitor& local) {
  using State = typename Law::State;
  const ParticleStore& p = *ctx.particles;
  for (std::int64_t a = begin; a < end; ++a) {
    const std::int64_t k = near[static_cast<std::size_t>(a)];
    const auto i = static_cast<std::size_t>(c.first[k]);
    const auto j = static_cast<std::size_t>(c.second[k]);
    Vec3 d, v_second = p.v[j];  // piece 2 (its image in a periodic cell): branch, velocity
    if constexpr (periodic) {
      const ImageCode image = c.image[static_cast<std::size_t>(k)];
      d = branch(p.x.data(), i, j, ctx.images->position[image]);
      v_second += ctx.images->velocity[image];
    } else {
      d = branch(p.x.data(), i, j);
    }
    const double reach = p.radius[i] + p.radius[j];
    const double dist_sq = d.squaredNorm();
    if (dist_sq >= reach * reach) {
      // Separated: history ends. A pair that was apart already holds a fresh State and zero
      // records, so most candidates cost no writes at all.
      if (c.touching[static_cast<std::size_t>(k)]) end_contact<State>(c, k);
      continue;
    }
    State& state = state_at<State>(c.state, static_cast<std::size_t>(k));
    const double dist = std::sqrt(dist_sq);
    ContactKinematics kin;
    kin.normal = d * (1.0 / dist);  // as block_lanes: one division, not three
    kin.overlap = reach - dist;
    const Vec3 arm_first = (p.radius[i] - 0.5 * kin.overlap) * kin.normal;  // x_c - x_i
    const Vec3 arm_second = arm_first - d;                                   // x_c - x_j
    kin.relative_velocity = (v_second + p.w[j].cross(arm_second)) - (p.v[i] + p.w[i].cross(arm_first));
    kin.relative_angular_velocity = p.w[j] - p.w[i];
    kin.radius_1 = p.radius[i];
    kin.radius_2 = p.radius[j];
    kin.effective_radius = p.radius[i] * p.radius[j] / reach;
    kin.effective_mass = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
    kin.dt = ctx.dt;
    kin.kind = c.kind;
    const ContactForce out = Law::force(params, kin, state);
    if (ctx.record_pair_forces) {
      c.force[k] = out.force;
      c.normal_force[k] = out.normal_force;
    }
    c.touching[static_cast<std::size_t>(k)] = (out.normal_force != 0.0) | !out.force.isZero(0.0);
    const Vec3 torque_first = -arm_first.cross(out.force) - out.moment;
    add_to_particles<Mode>(ctx, later, i, j, lane(out.force), lane(torque_first),
                               lane(second_torque(d, out.force, torque_first)));
    note_overlap(local, kin.overlap, std::min(p.radius[i], p.radius[j]), k);
  }
}

/// One block of touching pair contacts: inputs staged from the particles, the law's history
/// copied out of (and back into) the contact store, and the results, one entry per contact.
template <class State>
struct PairBlock : BlockHistory<State> {
  std::int64_t contact[pair_block];
  std::int32_t first[pair_block], second[pair_block];
  // inputs: branch d = x2 - x1 (branch_lanes) and radii (found while choosing the touching candidates)
  double dx[pair_block], dy[pair_block], dz[pair_block];
  double radius_1[pair_block], radius_2[pair_block];
  // Both pieces' velocities (m/s) and angular velocities (rad/s), x y z of each contact in turn,
  // and inverse masses (1/kg), copied from the particles for the touching candidates only.
  double v1[3 * pair_block], v2[3 * pair_block], w1[3 * pair_block], w2[3 * pair_block];
  double inv_mass_1[pair_block], inv_mass_2[pair_block];
  // results: force on piece 2, torques on pieces 1 and 2, elastic normal force, overlap (the
  // scalar loop divides it by the smaller radius into the overlap ratio: a division is among the
  // block's slowest instructions), and 1 where the contact still touches (non-zero normal force or
  // force; PairContacts::touching)
  double fx[pair_block], fy[pair_block], fz[pair_block];
  double t1x[pair_block], t1y[pair_block], t1z[pair_block], t2x[pair_block], t2y[pair_block], t2z[pair_block];
  double normal_force[pair_block], overlap[pair_block], touching[pair_block];
};

/// Kinematics, law and torques of the `count` contacts of a block, each independent of the others
/// (the same arithmetic as pair_range's, in the same order: same bits).
template <LaneContactLaw Law, int Variant>
DEM_HOT_INLINE void block_lanes(const typename Law::Params& shared_params, PairBlock<typename Law::State>& b,
                                int count, double dt, ContactKind kind) {
  // A local copy: the loop's history copies could otherwise alias the parameters for the
  // compiler, which then reloads them in the loop (and cannot vectorise a reloaded flag).
  const typename Law::Params params = shared_params;
DEM_INDEPENDENT_ITERATIONS
  for (int m = 0; m < count; ++m) {
    const Lane3 d{b.dx[m], b.dy[m], b.dz[m]};
    const double r1 = b.radius_1[m], r2 = b.radius_2[m];
    const double reach = r1 + r2;
    const double dist = std::sqrt(squared_norm(d));
    LaneKinematics kin;
    // One division and three products: divisions are among the block's slowest instructions.
    kin.normal = (1.0 / dist) * d;
    kin.overlap = reach - dist;
    const Lane3 arm_first = (r1 - 0.5 * kin.overlap) * kin.normal;  // x_c - x_1
    const Lane3 arm_second = arm_first - d;                         // x_c - x_2
    const Lane3 w1{b.w1[3 * m], b.w1[3 * m + 1], b.w1[3 * m + 2]}, w2{b.w2[3 * m], b.w2[3 * m + 1], b.w2[3 * m + 2]};
    const Lane3 v1{b.v1[3 * m], b.v1[3 * m + 1], b.v1[3 * m + 2]}, v2{b.v2[3 * m], b.v2[3 * m + 1], b.v2[3 * m + 2]};
    kin.relative_velocity = (v2 + cross(w2, arm_second)) - (v1 + cross(w1, arm_first));
    kin.relative_angular_velocity = w2 - w1;
    kin.radius_1 = r1;
    kin.radius_2 = r2;
    kin.effective_radius = r1 * r2 / reach;
    kin.effective_mass = 1.0 / (b.inv_mass_1[m] + b.inv_mass_2[m]);
    kin.dt = dt;
    kin.kind = kind;
    typename Law::State state;
    b.store_history(m, reinterpret_cast<std::byte*>(&state));
    const LaneForce out = lane_force<Law, Variant>(params, kin, state);
    b.load_history(m, reinterpret_cast<const std::byte*>(&state));
    const Lane3 torque_first = -cross(arm_first, out.force) - out.moment;
    const Lane3 torque_second = -cross(d, out.force) - torque_first;  // as second_torque()
    b.fx[m] = out.force.x, b.fy[m] = out.force.y, b.fz[m] = out.force.z;
    b.t1x[m] = torque_first.x, b.t1y[m] = torque_first.y, b.t1z[m] = torque_first.z;
    b.t2x[m] = torque_second.x, b.t2y[m] = torque_second.y, b.t2z[m] = torque_second.z;
    b.normal_force[m] = out.normal_force;
    b.overlap[m] = kin.overlap;
    // here, four lanes at once, rather than four NaN-aware comparisons per contact afterwards
    const bool touching = (out.normal_force != 0.0) | (out.force.x != 0.0) | (out.force.y != 0.0) | (out.force.z != 0.0);
    b.touching[m] = touching ? 1.0 : 0.0;
  }
}

/// Whether the pair loop asks for the second pieces' velocity, spin, force and torque lines while
/// it scans (for the copy pass and the sums after the block). Those pieces lie up to a plane of
/// cells ahead in particle order, so where a step's data outgrows the last-level cache they come
/// from main memory: asked for ahead, the 112k benchmark runs about 6 % faster on one thread.
/// Where the data fits (14k), the lines are near already and the requests cost about 3 %.
/// The data counted: the particles' arrays the loop reads and writes, and each candidate's indices,
/// history and flag.
inline bool prefetch_second_pieces(std::size_t particles, std::size_t candidates, std::size_t history_bytes) {
  constexpr std::size_t particle_bytes = 5 * sizeof(Vec3) + 2 * sizeof(double);  // x v w f t, radius, 1/m
  constexpr std::size_t cache_bytes = std::size_t{16} << 20;  // half a server core group's L3: others use it too
  return particles * particle_bytes + candidates * (2 * sizeof(std::int32_t) + history_bytes + 1) > cache_bytes;
}

/// pair_range for a lane law: the same near candidates, block by block. Sums into particles happen
/// in contact order, as in pair_range, so both give the same bits. `record`: the step keeps the
/// force records (KernelContext::record_pair_forces); `prefetch_second`: prefetch_second_pieces.
/// Both are compiled in rather than tested per candidate: the scan is short of registers, and a
/// flag held in one pushes a pointer out to the stack (about 2 % of the 14k loop on one thread).
template <LaneContactLaw Law, Sums Mode, bool record, bool prefetch_second, bool periodic>
void pair_range_lanes_with(const typename Law::Params& params, PairContacts& c,
                           const std::vector<std::int32_t>& near_list, const KernelContext& shared_ctx,
                           std::int64_t begin, std::int64_t end, std::vector<DeferredSum>* later, OverlapMonitor& local) {
  using State = typename Law::State;
  // Local copies: the history's byte copies may alias anything for the compiler, which would
  // otherwise reload the sums' addresses and the history's base and stride for every contact.
  const KernelContext ctx = shared_ctx;
  std::byte* const histories = c.state.bytes.data();  // States of sizeof(State) bytes (reset_states)
  const ParticleStore& p = *ctx.particles;
  const Vec3* x = p.x.data();
  const double* radius = p.radius.data();
  const double* inv_mass = p.inv_mass.data();
  const std::int32_t* first = c.first.data();
  const std::int32_t* second = c.second.data();
  const std::int32_t* near = near_list.data();
  Vec3* force = c.force.data();
  double* normal_force = c.normal_force.data();
  std::uint8_t* touching = c.touching.data();
  const ImageCode* image = c.image.data();  // periodic only
  PairBlock<State> b;
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "the block takes a Vec3 as three doubles");
  const Vec3* v = p.v.data();
  const Vec3* w = p.w.data();
  const BlockKernel<Law, PairBlock<State>> compute_block = block_kernel<Law, PairBlock<State>>(params, block_isa());
  OverlapMonitor worst = local;  // in registers: the loop's stores could alias `local`
  for (std::int64_t a = begin; a < end;) {
    // The touching candidates of the next stretch, in order, without a branch on which ones
    // touch (three in four near candidates do, in no predictable pattern): every candidate is
    // written to the next slot, which only a touching one keeps. A separated candidate that
    // touched last step ends its history (the rare case, so its branch predicts well).
    int count = 0;
    for (; a < end && count < pair_block; ++a) {
      const std::int64_t k = near[a];
      const std::int32_t i = first[k], j = second[k];
      Lane3 d;
      if constexpr (periodic) d = branch_lanes(x, i, j, ctx.images->position[image[k]]);
      else d = branch_lanes(x, i, j);
      const double reach = radius[i] + radius[j];
      const bool separated = squared_norm(d) >= reach * reach;
      b.contact[count] = k;
      b.first[count] = i, b.second[count] = j;
      b.dx[count] = d.x, b.dy[count] = d.y, b.dz[count] = d.z;
      b.radius_1[count] = radius[i], b.radius_2[count] = radius[j];
      count += separated ? 0 : 1;
      if (separated & (touching[k] != 0)) end_contact<State>(c, k);
      // The block reads this contact's history and writes its results after the whole stretch
      // is found: ask for those lines now, so that they arrive meanwhile.
      const std::byte* history = histories + k * sizeof(State);
      DEM_PREFETCH_FOR_WRITE(history);
      DEM_PREFETCH_FOR_WRITE(history + sizeof(State) - 1);
      if constexpr (record) {
        DEM_PREFETCH_FOR_WRITE(&force[k]);
        DEM_PREFETCH_FOR_WRITE(&normal_force[k]);
      }
      if constexpr (prefetch_second) {
        DEM_PREFETCH_FOR_READ(&v[j]);
        DEM_PREFETCH_FOR_READ(&w[j]);
        DEM_PREFETCH_FOR_WRITE(&ctx.scatter_force[j]);
        DEM_PREFETCH_FOR_WRITE(&ctx.scatter_torque[j]);
      }
    }
    for (int m = 0; m < count; ++m) {
      b.load_history(m, histories + b.contact[m] * sizeof(State));
      // Copied here, for the touching ones only, as three doubles a piece: the block's SIMD lanes
      // load such strided arrays whole and shuffle them, where loads by particle index cost
      // about three instructions a double (half of the block's instructions).
      const auto i = static_cast<std::size_t>(b.first[m]), j = static_cast<std::size_t>(b.second[m]);
      std::memcpy(&b.v1[3 * m], v[i].data(), sizeof(Vec3));
      if constexpr (periodic) {  // the image's velocity: v2 + L h n
        const Vec3 v_image = v[j] + ctx.images->velocity[image[b.contact[m]]];
        std::memcpy(&b.v2[3 * m], v_image.data(), sizeof(Vec3));
      } else {
        std::memcpy(&b.v2[3 * m], v[j].data(), sizeof(Vec3));
      }
      std::memcpy(&b.w1[3 * m], w[i].data(), sizeof(Vec3));
      std::memcpy(&b.w2[3 * m], w[j].data(), sizeof(Vec3));
      b.inv_mass_1[m] = inv_mass[i], b.inv_mass_2[m] = inv_mass[j];
    }
    compute_block(params, b, count, ctx.dt, c.kind);
    for (int m = 0; m < count; ++m) {
      const std::int64_t k_m = b.contact[m];
      const auto i = static_cast<std::size_t>(b.first[m]);
      const auto j = static_cast<std::size_t>(b.second[m]);
      b.store_history(m, histories + k_m * sizeof(State));
      // Added into the particles from plain doubles, not read back from force[k_m]: a load that
      // spans the three stores just made waits for them (no store forwarding).
      const Lane3 f{b.fx[m], b.fy[m], b.fz[m]};
      // The records only where they can be read: 32 of the 81 bytes a touching rolling-resistance
      // contact writes, and on a packing larger than the cache, main-memory traffic.
      if constexpr (record) {
        force[k_m].x() = f.x, force[k_m].y() = f.y, force[k_m].z() = f.z;
        normal_force[k_m] = b.normal_force[m];
      }
      touching[k_m] = b.touching[m] != 0.0;
      add_to_particles<Mode>(ctx, later, i, j, f, Lane3{b.t1x[m], b.t1y[m], b.t1z[m]},
                                 Lane3{b.t2x[m], b.t2y[m], b.t2z[m]});
      // The overlap ratio here, in the scalar loop, leaves the block's divider to the law.
      note_overlap(worst, b.overlap[m], std::min(b.radius_1[m], b.radius_2[m]), k_m);
    }
  }
  local = worst;
}

/// pair_range_lanes_with for this step's flags.
template <LaneContactLaw Law, Sums Mode>
void pair_range_lanes(const typename Law::Params& params, PairContacts& c, const std::vector<std::int32_t>& near,
                      const KernelContext& ctx, std::int64_t begin, std::int64_t end, std::vector<DeferredSum>* later,
                      OverlapMonitor& local) {
  const bool prefetch = prefetch_second_pieces(ctx.particles->size(), c.size(), sizeof(typename Law::State));
  if (ctx.images != nullptr) {  // a periodic cell
    if (ctx.record_pair_forces) {
      if (prefetch) return pair_range_lanes_with<Law, Mode, true, true, true>(params, c, near, ctx, begin, end, later, local);
      return pair_range_lanes_with<Law, Mode, true, false, true>(params, c, near, ctx, begin, end, later, local);
    }
    if (prefetch) return pair_range_lanes_with<Law, Mode, false, true, true>(params, c, near, ctx, begin, end, later, local);
    return pair_range_lanes_with<Law, Mode, false, false, true>(params, c, near, ctx, begin, end, later, local);
  }
  if (ctx.record_pair_forces) {
    if (prefetch) return pair_range_lanes_with<Law, Mode, true, true, false>(params, c, near, ctx, begin, end, later, local);
    return pair_range_lanes_with<Law, Mode, true, false, false>(params, c, near, ctx, begin, end, later, local);
  }
  if (prefetch) return pair_range_lanes_with<Law, Mode, false, true, false>(params, c, near, ctx, begin, end, later, local);
  pair_range_lanes_with<Law, Mode, false, false, false>(params, c, near, ctx, begin, end, later, local);
}

/// One mode's loop for one thread's share: blocks for a lane law where they pay (lanes_worthwhile),
/// one contact at a time otherwise.
template <ContactLaw Law, Sums Mode>
void pair_share(const typename Law::Params& params, PairContacts& c, const std::vector<std::int32_t>& near,
                const KernelContext& ctx, std::int64_t begin, std::int64_t end, std::vector<DeferredSum>* later,
                OverlapMonitor& local) {
  if constexpr (LaneContactLaw<Law>) {
    if (lanes_worthwhile()) return pair_range_lanes<Law, Mode>(params, c, near, ctx, begin, end, later, local);
  }
  if (ctx.images != nullptr) return pair_range<Law, Mode, true>(params, c, near, ctx, begin, end, later, local);
  pair_range<Law, Mode, false>(params, c, near, ctx, begin, end, later, local);
}

/// Near candidates per chunk that a thread takes from another's share: a few microseconds of work
/// (small enough that the threads end within about that of each other, large enough that claiming
/// costs nothing and a chunk's blocks are nearly full).
inline constexpr std::int64_t steal_chunk = 512;

/// The pair loop over every near candidate of `plan`, on the threads of its shares.
template <ContactLaw Law>
void compute_pairs(const typename Law::Params& params, PairContacts& c, PairPlan& plan, const KernelContext& ctx,
                   OverlapMonitor& worst) {
  const std::vector<std::int32_t>& near = plan.near;
  const int threads = ctx.shared && plan.shares.size() >= 2 ? static_cast<int>(plan.shares.size()) - 1 : 1;
  c.force.resize(c.size(), Vec3::Zero());
  c.normal_force.resize(c.size(), 0.0);
  if (c.touching.size() != c.size()) mark_touching(c);
  if (threads == 1) {
    pair_share<Law, Sums::direct>(params, c, near, ctx, 0, static_cast<std::int64_t>(near.size()), nullptr, worst);
    return;
  }
  // Share t is the near candidates [near_begin[t], near_begin[t + 1]), cut into chunks; its chunks
  // are numbered from chunk_base[t] on.
  const auto shares = static_cast<std::size_t>(threads);
  std::vector<std::int64_t> near_begin(shares + 1), chunk_base(shares + 1, 0);
  for (std::size_t t = 0; t <= shares; ++t) {
    near_begin[t] = std::lower_bound(near.begin(), near.end(), plan.shares[t]) - near.begin();
    if (t > 0)
      chunk_base[t] = chunk_base[t - 1] + (near_begin[t] - near_begin[t - 1] + steal_chunk - 1) / steal_chunk;
  }
  // Each share's unshared run (PairPlan::unshared_run) as near candidates.
  std::vector<std::pair<std::int64_t, std::int64_t>> unshared_near(shares, {0, 0});
  for (std::size_t t = 0; t < shares && t < plan.unshared_run.size(); ++t) {
    const auto near_of = [&near](std::int64_t k) { return std::lower_bound(near.begin(), near.end(), k) - near.begin(); };
    unshared_near[t] = {near_of(plan.unshared_run[t].first), near_of(plan.unshared_run[t].second)};
  }
  std::unique_ptr<ChunkQueue[]> queues(new ChunkQueue[shares]);
  for (std::size_t t = 0; t < shares; ++t) queues[t].reset(chunk_base[t + 1] - chunk_base[t]);
  plan.deferred.resize(shares);
  for (std::vector<DeferredSum>& later : plan.deferred) later.clear();
  plan.taken.resize(static_cast<std::size_t>(chunk_base[shares]));
  for (std::vector<DeferredSum>& later : plan.taken) later.clear();
  if (plan.share_seconds.size() != shares || plan.share_done.size() != shares) {
    plan.share_seconds.assign(shares, 0.0);
    plan.share_done.assign(shares, 0);
  }
#pragma omp parallel num_threads(open_team(threads))
  {
    OverlapMonitor local;
#if defined(_OPENMP)
    const double started = omp_get_wtime();
    const bool as_planned = omp_get_num_threads() == threads;
    const auto me = static_cast<std::size_t>(omp_get_thread_num());
#else
    const bool as_planned = false;
    const std::size_t me = 0;
#endif
    // The near candidates [begin, end) of share t's chunk `chunk`.
    const auto chunk_range = [&](std::size_t t, std::int64_t chunk) {
      const std::int64_t begin = near_begin[t] + chunk * steal_chunk;
      return std::pair{begin, std::min(begin + steal_chunk, near_begin[t + 1])};
    };
    // Share t's chunk [begin, end) in its own thread: the part in the share's unshared run with
    // every sum added directly (no particle there is shared), the rest deferring the shared ones.
    const auto own_chunk = [&](std::size_t t, std::int64_t begin, std::int64_t end) {
      if (t == 0) return pair_share<Law, Sums::direct>(params, c, near, ctx, begin, end, nullptr, local);
      const std::int64_t direct_begin = std::clamp(unshared_near[t].first, begin, end);
      const std::int64_t direct_end = std::clamp(unshared_near[t].second, direct_begin, end);
      pair_share<Law, Sums::defer_shared>(params, c, near, ctx, begin, direct_begin, &plan.deferred[t], local);
      pair_share<Law, Sums::direct>(params, c, near, ctx, direct_begin, direct_end, nullptr, local);
      pair_share<Law, Sums::defer_shared>(params, c, near, ctx, direct_end, end, &plan.deferred[t], local);
    };
    std::int64_t done = 0;
    if (!as_planned) {
      // The runtime gave fewer threads than planned: one thread takes every contact and adds
      // every sum itself.
      if (me == 0)
        pair_share<Law, Sums::direct>(params, c, near, ctx, 0, static_cast<std::int64_t>(near.size()), nullptr, local);
    } else {
      // Its own share from the front, in contact order (the first share adds every sum itself)...
      for (std::int64_t chunk; (chunk = queues[me].take_front()) >= 0;) {
        const auto [begin, end] = chunk_range(me, chunk);
        own_chunk(me, begin, end);
        done += end - begin;
      }
      // ...then chunks from the back of the share with the most left, deferring every sum.
      for (;;) {
        std::size_t from = shares;
        std::int64_t most = 0;
        for (std::size_t t = 0; t < shares; ++t)
          if (const std::int64_t left = queues[t].left(); left > most) most = left, from = t;
        if (from == shares) break;
        const std::int64_t chunk = queues[from].take_back();
        if (chunk < 0) continue;
        const auto [begin, end] = chunk_range(from, chunk);
        pair_share<Law, Sums::defer_all>(params, c, near, ctx, begin, end,
                                         &plan.taken[static_cast<std::size_t>(chunk_base[from] + chunk)], local);
        done += end - begin;
      }
    }
#if defined(_OPENMP)
    if (as_planned) {
      plan.share_seconds[me] += omp_get_wtime() - started;
      plan.share_done[me] += done;
    }
#endif
#pragma omp critical(dem_overlap_monitor)
    merge_worst(worst, local);
  }
  // Then the deferred parts in contact order, share by share: its own thread's, then those of the
  // chunks other threads took from its end. Each particle's sum is the serial one.
  for (std::size_t t = 0; t < shares; ++t) {
    add_deferred(ctx, plan.deferred[t]);
    for (std::int64_t g = chunk_base[t]; g < chunk_base[t + 1]; ++g) add_deferred(ctx, plan.taken[static_cast<std::size_t>(g)]);
  }
}


}  // namespace dem::detail
