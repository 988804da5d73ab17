// The attributes of the engine's SIMD blocks (the contact blocks of contact_loops.hpp and the
// bond blocks of the World's bond loop): the instruction set each copy of a block is compiled for,
// and the hint that a loop's iterations are independent.
//
// contact_loops.hpp undefines these at its end (they are not part of the API), so this header is
// guarded per macro rather than once: included again after that, it defines them again.
#if !defined(DEM_TARGET_AVX2)

// "The iterations of the next loop are independent": lets GCC vectorise a loop whose arrays it
// cannot prove apart.
#if defined(__GNUC__) && !defined(__clang__)
#define DEM_INDEPENDENT_ITERATIONS _Pragma("GCC ivdep")
#else
#define DEM_INDEPENDENT_ITERATIONS
#endif

// Blocks pay for staging their inputs and results through memory; they win where the processor
// has 4-wide double SIMD (AVX2: about 2.4x the contact arithmetic per second of one contact at a
// time), and lose with SSE2's 2 lanes. With AVX-512's 8 lanes the block takes a quarter less time
// again (12 instead of 16 ns per rolling-linear contact): its square roots and divisions have the
// same throughput per lane, the rest of its arithmetic twice that. So on x86-64 with GCC or Clang
// each block is compiled for AVX2 and for AVX-512, and the processor's best is chosen at run time;
// one contact at a time elsewhere. Every path gives the same bits: IEEE operations lane by lane,
// and no FMA (a fused multiply-add rounds once where the others round twice).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// AVX-512 has fused multiply-adds of its own, which the compiler would contract products and sums
// into (GCC's default, -ffp-contract=fast): GCC's AVX-512 copy is told not to. Clang has no such
// per-function switch, so with Clang the blocks stay on AVX2 (block_isa.cpp). GCC also keeps to
// 256-bit vectors unless told otherwise.
#define DEM_TARGET_AVX2 __attribute__((target("avx2")))
#if defined(__clang__)
#define DEM_TARGET_AVX512 DEM_TARGET_AVX2  // never chosen
#else
#define DEM_TARGET_AVX512 __attribute__((target("avx512f,prefer-vector-width=512"), optimize("fp-contract=off")))
#endif
#else
#define DEM_TARGET_AVX2
#define DEM_TARGET_AVX512
#endif

#endif  // !defined(DEM_TARGET_AVX2)
