// The law-typed contact loops behind make_contact_model. Included by contact_model.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#if defined(_OPENMP)
#include <omp.h>
#endif

#include <dem/boundary/facet_wall.hpp>
#include <dem/core/particles.hpp>
#include <dem/geometry/triangle.hpp>

namespace dem::detail {

template <class State>
State& state_at(StateBuffer& buffer, std::size_t k) {
  return *std::launder(reinterpret_cast<State*>(buffer.at(k)));
}

/// Keeps the largest overlap ratio of a loop; ties go to the lower contact index so that the
/// report does not depend on the thread count.
inline void merge_worst(OverlapMonitor& into, const OverlapMonitor& other) {
  if (other.ratio > into.ratio || (other.ratio == into.ratio && other.contact >= 0 &&
                                    (into.contact < 0 || other.contact < into.contact)))
    into = other;
}

/// The pair loop over contacts [begin, end): one thread's share. `Threaded`: skip the particles
/// the engine gathers (KernelContext::gathered) and leave their records; otherwise add into all.
template <ContactLaw Law, bool Threaded>
void pair_range(const typename Law::Params& params, PairContacts& c, const KernelContext& ctx, std::int64_t begin,
                std::int64_t end, bool records, OverlapMonitor& local) {
  using State = typename Law::State;
  const ParticleStore& p = *ctx.particles;
  for (std::int64_t k = begin; k < end; ++k) {
    const auto i = static_cast<std::size_t>(c.first[k]);
    const auto j = static_cast<std::size_t>(c.second[k]);
    const Vec3 d = p.x[j] - p.x[i];
    const double reach = p.radius[i] + p.radius[j];
    const double dist_sq = d.squaredNorm();
    if (dist_sq >= reach * reach) {
      // Separated: history ends. A pair that was apart already holds a fresh State and zero
      // records, so most candidates cost no writes at all.
      if (c.normal_force[k] != 0.0 || !c.force[k].isZero(0.0)) {
        state_at<State>(c.state, static_cast<std::size_t>(k)) = State{};
        c.force[k].setZero();
        if (records) c.torque_first[k].setZero();
        c.normal_force[k] = 0.0;
      }
      continue;
    }
    State& state = state_at<State>(c.state, static_cast<std::size_t>(k));
    const double dist = std::sqrt(dist_sq);
    ContactKinematics kin;
    kin.normal = d / dist;
    kin.overlap = reach - dist;
    const Vec3 arm_first = (p.radius[i] - 0.5 * kin.overlap) * kin.normal;  // x_c - x_i
    const Vec3 arm_second = arm_first - d;                                   // x_c - x_j
    kin.relative_velocity = (p.v[j] + p.w[j].cross(arm_second)) - (p.v[i] + p.w[i].cross(arm_first));
    kin.relative_angular_velocity = p.w[j] - p.w[i];
    kin.radius_1 = p.radius[i];
    kin.radius_2 = p.radius[j];
    kin.effective_radius = p.radius[i] * p.radius[j] / reach;
    kin.effective_mass = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
    kin.dt = ctx.dt;
    kin.kind = c.kind;
    const ContactForce out = Law::force(params, kin, state);
    c.force[k] = out.force;
    c.normal_force[k] = out.normal_force;
    const Vec3 torque_first = -arm_first.cross(out.force) - out.moment;
    const bool gather_first = Threaded && ctx.gathered[i] != 0;
    const bool gather_second = Threaded && ctx.gathered[j] != 0;
    if (!gather_first) {
      ctx.scatter_force[i] -= out.force;
      ctx.scatter_torque[i] += torque_first;
    }
    if (!gather_second) {
      ctx.scatter_force[j] += out.force;
      ctx.scatter_torque[j] += second_torque(d, out.force, torque_first);
    }
    if (gather_first || gather_second) c.torque_first[k] = torque_first;
    const double ratio = kin.overlap / std::min(p.radius[i], p.radius[j]);
    if (ratio > local.ratio) local = OverlapMonitor{ratio, k};
  }
}

template <ContactLaw Law>
void compute_pairs(const typename Law::Params& params, PairContacts& c, const KernelContext& ctx,
                   OverlapMonitor& worst) {
  const std::int64_t count = static_cast<std::int64_t>(c.size());
  const std::uint8_t* gathered = ctx.gathered;
  const int threads = gathered && c.shares.size() >= 2 ? static_cast<int>(c.shares.size()) - 1 : 1;
  c.force.resize(c.size(), Vec3::Zero());
  c.normal_force.resize(c.size(), 0.0);
  if (gathered) c.torque_first.resize(c.size(), Vec3::Zero());  // records only the gather reads
  const bool records = !c.torque_first.empty();
#pragma omp parallel num_threads(threads)
  {
    OverlapMonitor local;
    // The shares the engine planned the gather on; should the runtime give fewer threads than
    // asked, one thread takes every share (each particle still has a single writer).
#if defined(_OPENMP)
    const bool as_planned = omp_get_num_threads() == threads;
    const int me = omp_get_thread_num();
#else
    const bool as_planned = threads == 1;
    const int me = 0;
#endif
    const std::int64_t begin = as_planned ? (threads > 1 ? c.shares[static_cast<std::size_t>(me)] : 0) : 0;
    const std::int64_t end = as_planned ? (threads > 1 ? c.shares[static_cast<std::size_t>(me) + 1] : count) : (me == 0 ? count : 0);
    if (gathered) pair_range<Law, true>(params, c, ctx, begin, end, records, local);
    else pair_range<Law, false>(params, c, ctx, begin, end, records, local);
#pragma omp critical(dem_overlap_monitor)
    merge_worst(worst, local);
  }
}

template <ContactLaw Law>
void compute_walls(const typename Law::Params& params, WallContacts& c, const KernelContext& ctx,
                   OverlapMonitor& worst) {
  using State = typename Law::State;
  const ParticleStore& p = *ctx.particles;
  const std::vector<FacetWall>& walls = *ctx.walls;
  const std::int64_t count = static_cast<std::int64_t>(c.size());
  c.force.resize(c.size());
  c.torque_ball.resize(c.size());
  c.point.resize(c.size());
  c.moment.resize(c.size());
  c.normal_force.resize(c.size());
  c.normal_stiffness.resize(c.size());
#pragma omp parallel num_threads(threads_for(count, ctx.threads))
  {
    OverlapMonitor local;
#pragma omp for schedule(static)
    for (std::int64_t k = 0; k < count; ++k) {
      const auto b = static_cast<std::size_t>(c.ball[k]);
      const FacetWall& wall = walls[static_cast<std::size_t>(c.wall[k])];
      const Vec3& centre = p.x[b];
      // The closest point over the candidate triangles: one contact per ball and wall.
      Vec3 closest = Vec3::Zero();
      double best_sq = std::numeric_limits<double>::infinity();
      for (std::int32_t t = c.triangle_begin[k]; t < c.triangle_end[k]; ++t) {
        const auto& tri = wall.mesh.triangles[static_cast<std::size_t>(c.triangles[static_cast<std::size_t>(t)])];
        const geometry::ClosestPoint cp = geometry::closest_point_on_triangle(
            centre, wall.mesh.vertices[static_cast<std::size_t>(tri[0])],
            wall.mesh.vertices[static_cast<std::size_t>(tri[1])], wall.mesh.vertices[static_cast<std::size_t>(tri[2])]);
        const double dsq = (cp.point - centre).squaredNorm();
        if (dsq < best_sq) {
          best_sq = dsq;
          closest = cp.point;
        }
      }
      State& state = state_at<State>(c.state, static_cast<std::size_t>(k));
      const double r = p.radius[b];
      if (best_sq >= r * r || best_sq == 0.0) {
        state = State{};
        c.force[k].setZero();
        c.torque_ball[k].setZero();
        c.moment[k].setZero();
        c.point[k] = centre;  // defined bytes in restart files, and a harmless point if read
        c.normal_force[k] = 0.0;
        c.normal_stiffness[k] = 0.0;
        continue;
      }
      const double dist = std::sqrt(best_sq);
      ContactKinematics kin;
      kin.normal = (closest - centre) / dist;
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
      const double ratio = kin.overlap / r;
      if (ratio > local.ratio) local = OverlapMonitor{ratio, k};
    }
#pragma omp critical(dem_overlap_monitor)
    merge_worst(worst, local);
  }
}

template <ContactLaw Law>
class ContactModelFor final : public ContactModel {
 public:
  explicit ContactModelFor(const typename Law::Params& params) : params_(params) {}
  const char* law_name() const override { return Law::name; }
  void compute(PairContacts& c, const KernelContext& ctx, OverlapMonitor& worst) const override {
    compute_pairs<Law>(params_, c, ctx, worst);
  }
  void compute(WallContacts& c, const KernelContext& ctx, OverlapMonitor& worst) const override {
    compute_walls<Law>(params_, c, ctx, worst);
  }
  ContactStiffness stiffness(const ContactKinematics& k) const override { return Law::stiffness(params_, k); }

  void reset_states(StateBuffer& buffer, std::size_t count) const override {
    using State = typename Law::State;
    buffer.stride = sizeof(State);
    buffer.count = count;
    buffer.bytes.assign(count * sizeof(State), std::byte{0});
    for (std::size_t k = 0; k < count; ++k) ::new (buffer.at(k)) State{};
  }
  void remap_states(const StateBuffer& source, const std::vector<std::int64_t>& source_of,
                    StateBuffer& target) const override {
    using State = typename Law::State;
    reset_states(target, source_of.size());
    if (source.stride != sizeof(State)) return;  // history of another law: start fresh
    for (std::size_t k = 0; k < source_of.size(); ++k) {
      if (source_of[k] < 0) continue;
      state_at<State>(target, k) =
          *std::launder(reinterpret_cast<const State*>(source.at(static_cast<std::size_t>(source_of[k]))));
    }
  }

 private:
  typename Law::Params params_;
};

}  // namespace dem::detail

namespace dem {

template <ContactLaw Law>
std::shared_ptr<const ContactModel> make_contact_model(const typename Law::Params& params, const std::string& where) {
  params.validate(where);
  return std::make_shared<detail::ContactModelFor<Law>>(params);
}

}  // namespace dem
