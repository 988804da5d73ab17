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

/// Every particle of `a` ends where, and moving as, the same particle of `b` does, bit for bit.
inline void require_same_bits(const World& a, const World& b) {
  const ParticleStore& p = a.particles();
  const ParticleStore& q = b.particles();
  REQUIRE(p.size() == q.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.x[i] != q.x[i] || p.v[i] != q.v[i] || p.w[i] != q.w[i]) ++differing;
  CHECK(differing == 0);
}

}  // namespace dem::testing
