// The instruction set of the engine's contact blocks and leapfrog kernel: the processor's best
// (detected once, in the library), or a lesser one that a test asks for, so that every path can be
// compared on one machine. Every path gives the same bits (contact_loops.hpp).
#pragma once

namespace dem::detail {

enum class BlockIsa { scalar = 0, avx2 = 1, avx512 = 2 };

/// The best this processor and compiler offer: AVX-512 with GCC on x86-64 where the processor has
/// it, AVX2 (also Clang's best), else scalar.
BlockIsa detected_block_isa();
/// The set the loops use now: detected_block_isa(), or less if use_block_isa asked for less.
BlockIsa block_isa();
/// Tests: run the pair loops and the leapfrog with `isa` (or the processor's best, if that is less),
/// for the whole process.
void use_block_isa(BlockIsa isa);

}  // namespace dem::detail
