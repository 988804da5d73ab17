// The engine's SIMD kernels (contact blocks, leapfrog) on a chosen instruction set, and the bit
// for bit comparison of two runs, for tests that compare every path on one machine.
#pragma once

#include <catch2/catch.hpp>

#include <dem/dem.hpp>

namespace dem::testing {

/// The instruction set for one scope (detail::use_block_isa), then the processor's best again.
struct BlockIsaScope {
  explicit BlockIsaScope(detail::BlockIsa isa) { detail::use_block_isa(isa); }
  ~BlockIsaScope() { detail::use_block_isa(detail::detected_block_isa()); }
  BlockIsaScope(const BlockIsaScope&) = delete;
  BlockIsaScope& operator=(const BlockIsaScope&) = delete;
};

/// Every particle of `a` ends where, and moving as, the same particle of `b` does, bit for bit;
/// so do the walls' sums and every ball-wall contact's records and history.
inline void require_same_bits(const World& a, const World& b) {
  const ParticleStore& p = a.particles();
  const ParticleStore& q = b.particles();
  REQUIRE(p.size() == q.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.x[i] != q.x[i] || p.v[i] != q.v[i] || p.w[i] != q.w[i]) ++differing;
  CHECK(differing == 0);
  REQUIRE(a.walls().size() == b.walls().size());
  for (std::size_t k = 0; k < a.walls().size(); ++k) {
    INFO("wall " << a.walls()[k].name);
    CHECK(a.walls()[k].force == b.walls()[k].force);
    CHECK(a.walls()[k].moment == b.walls()[k].moment);
  }
  const auto same_records = [](const WallContacts& c, const WallContacts& d) {
    REQUIRE(c.size() == d.size());
    CHECK(c.force == d.force);
    CHECK(c.torque_ball == d.torque_ball);
    CHECK(c.point == d.point);
    CHECK(c.moment == d.moment);
    CHECK(c.normal_force == d.normal_force);
    CHECK(c.normal_stiffness == d.normal_stiffness);
    CHECK(c.state.bytes == d.state.bytes);
  };
  same_records(a.state().contacts.ball_facet, b.state().contacts.ball_facet);
  same_records(a.state().contacts.ball_surface, b.state().contacts.ball_surface);
}

}  // namespace dem::testing
