// The engine's SIMD kernels (contact blocks, leapfrog) on a chosen instruction set, for tests that
// compare every path on one machine.
#pragma once

#include <dem/dem.hpp>

namespace dem::testing {

/// The instruction set for one scope (detail::use_block_isa), then the processor's best again.
struct BlockIsaScope {
  explicit BlockIsaScope(detail::BlockIsa isa) { detail::use_block_isa(isa); }
  ~BlockIsaScope() { detail::block_isa_override().store(-1); }
  BlockIsaScope(const BlockIsaScope&) = delete;
  BlockIsaScope& operator=(const BlockIsaScope&) = delete;
};

}  // namespace dem::testing
