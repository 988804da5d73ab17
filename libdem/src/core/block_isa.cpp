// The one place that detects the instruction set and holds the process-wide test override.
#include <dem/core/block_isa.hpp>

#include <algorithm>
#include <atomic>

namespace dem::detail {

namespace {

std::atomic<int> asked_isa{-1};  // -1: none asked; the processor's best

}  // namespace

BlockIsa detected_block_isa() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#if defined(__clang__)
  // Clang cannot keep products and sums apart in an AVX-512 function (contact_loops.hpp).
  static const BlockIsa isa = __builtin_cpu_supports("avx2") ? BlockIsa::avx2 : BlockIsa::scalar;
#else
  static const BlockIsa isa = __builtin_cpu_supports("avx512f") ? BlockIsa::avx512
                              : __builtin_cpu_supports("avx2")  ? BlockIsa::avx2
                                                                : BlockIsa::scalar;
#endif
  return isa;
#else
  return BlockIsa::scalar;
#endif
}

BlockIsa block_isa() {
  const int asked = asked_isa.load(std::memory_order_relaxed);
  const BlockIsa best = detected_block_isa();
  return asked < 0 ? best : static_cast<BlockIsa>(std::min(asked, static_cast<int>(best)));
}

void use_block_isa(BlockIsa isa) { asked_isa.store(static_cast<int>(isa), std::memory_order_relaxed); }

}  // namespace dem::detail
