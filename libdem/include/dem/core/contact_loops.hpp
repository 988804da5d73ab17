// The law-typed contact loops behind make_contact_model: the engine's loops over the contacts of
// one kind, with the law inlined (run-time choice of law, compile-time loop). The built-in laws'
// loops are compiled once in the library (core/contact_model.hpp declares them extern), so a
// program that uses them needs only contact_model.hpp; a program with a law of its own includes
// this header (dem/dem.hpp does) where it calls make_contact_model for it.
//
// Here: what the pair and wall loops share (the worst-overlap monitor, the blocks of a lane law and
// their instruction sets) and the law-bound ContactModel; the loops themselves are in
// pair_loops.hpp and wall_loops.hpp, parts of this header. The attribute macros it defines for the
// loops are undefined again at its end.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <thread>
#include <utility>
#if defined(_OPENMP)
#include <omp.h>
#endif

#include <dem/boundary/wall.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/lanes.hpp>
#include <dem/core/block_isa.hpp>
#include <dem/core/block_targets.hpp>
#include <dem/core/contact_model.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/core/parallel.hpp>
#include <dem/core/particles.hpp>
#include <dem/core/step_plan.hpp>
#include <dem/geometry/triangle.hpp>

// "This address will be read (written) soon": starts loading its cache line (a hint; no effect on
// results).
#if defined(__GNUC__)
#define DEM_PREFETCH_FOR_READ(address) __builtin_prefetch((address), 0)
#define DEM_PREFETCH_FOR_WRITE(address) __builtin_prefetch((address), 1)
#else
#define DEM_PREFETCH_FOR_READ(address) ((void)(address))
#define DEM_PREFETCH_FOR_WRITE(address) ((void)(address))
#endif

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

/// Keeps {overlap / smaller, k} in `worst` if that ratio is the larger. The division (among the
/// slowest instructions) runs only where the ratio can be larger: for smaller > 0 and rounding to
/// nearest, overlap / smaller > w implies overlap >= w * smaller in floating point too, so the
/// same contacts are kept as with a division for each.
DEM_HOT_INLINE void note_overlap(OverlapMonitor& worst, double overlap, double smaller, std::int64_t k) {
  if (!(overlap >= worst.ratio * smaller)) return;
  const double ratio = overlap / smaller;
  if (ratio > worst.ratio) worst = OverlapMonitor{ratio, k};
}

/// A law with a plain-double force (lanes.hpp): the engine computes its contacts in blocks.
/// Its State must be made of doubles only: a block keeps each of them as an array (SoA).
template <class L>
concept LaneContactLaw = ContactLaw<L> && requires(const typename L::Params& p, const LaneKinematics& k,
                                                    typename L::State& s) {
  { L::force_lanes(p, k, s) } -> std::same_as<LaneForce>;
} && std::is_trivially_copyable_v<typename L::State> && sizeof(typename L::State) % sizeof(double) == 0;

/// Contacts of a lane law are computed side by side: one contact's arithmetic is a chain of
/// dependent square roots and divisions, so one contact after the other leaves the processor
/// waiting on that chain; a block staged as arrays runs in SIMD lanes.
inline constexpr int pair_block = 64;

/// The law's history of a block's contacts, double by double (SoA): copied out of the contact
/// store before the block and back after it.
template <class State>
struct BlockHistory {
  static constexpr int state_doubles = static_cast<int>(sizeof(State) / sizeof(double));
  double state[state_doubles][pair_block];

  /// Copies a State's bytes (`history`) into entry m of `state`, and back.
  void load_history(int m, const std::byte* history) {
    for (int s = 0; s < state_doubles; ++s) std::memcpy(&state[s][m], history + s * sizeof(double), sizeof(double));
  }
  void store_history(int m, std::byte* history) const {
    for (int s = 0; s < state_doubles; ++s) std::memcpy(history + s * sizeof(double), &state[s][m], sizeof(double));
  }
};

/// A lane law with versions of force_lanes for special parameters (lanes.hpp: lane variants).
template <class L>
concept VariantLaneLaw = LaneContactLaw<L> && requires(const typename L::Params& p) {
  { L::lane_variants } -> std::convertible_to<int>;
  { L::lane_variant(p) } -> std::convertible_to<int>;
};

/// The law's force in lanes, in version `Variant` (-1: a law without variants).
template <class Law, int Variant>
DEM_HOT_INLINE LaneForce lane_force(const typename Law::Params& p, const LaneKinematics& k, typename Law::State& s) {
  if constexpr (Variant < 0) return Law::force_lanes(p, k, s);
  else return Law::template force_lanes<Variant>(p, k, s);
}

inline bool lanes_worthwhile() { return block_isa() != BlockIsa::scalar; }

/// One block of contacts (a PairBlock of pair_loops.hpp, or a WallBlock of wall_loops.hpp) in the
/// law's variant `Variant`, compiled for one instruction set. Each block's arithmetic, block_lanes,
/// is defined with its block and found by its argument where a loop instantiates the kernel.
template <class Law, class Block>
using BlockKernel = void (*)(const typename Law::Params&, Block&, int, double, ContactKind);
template <LaneContactLaw Law, int Variant, class Block>
DEM_TARGET_AVX2 void block_avx2(const typename Law::Params& params, Block& b, int count, double dt, ContactKind kind) {
  block_lanes<Law, Variant>(params, b, count, dt, kind);
}
template <LaneContactLaw Law, int Variant, class Block>
DEM_TARGET_AVX512 void block_avx512(const typename Law::Params& params, Block& b, int count, double dt,
                                    ContactKind kind) {
  block_lanes<Law, Variant>(params, b, count, dt, kind);
}

/// The block kernel for these parameters (the law's lane variant) on this instruction set.
template <LaneContactLaw Law, class Block, std::size_t... V>
BlockKernel<Law, Block> block_kernel_among(const typename Law::Params& params, BlockIsa isa, std::index_sequence<V...>) {
  constexpr bool variants = VariantLaneLaw<Law>;
  static constexpr BlockKernel<Law, Block> avx2[] = {&block_avx2<Law, variants ? static_cast<int>(V) : -1, Block>...};
  static constexpr BlockKernel<Law, Block> avx512[] = {&block_avx512<Law, variants ? static_cast<int>(V) : -1, Block>...};
  std::size_t variant = 0;
  if constexpr (variants) variant = static_cast<std::size_t>(Law::lane_variant(params));
  return isa == BlockIsa::avx512 ? avx512[variant] : avx2[variant];
}
template <LaneContactLaw Law, class Block>
BlockKernel<Law, Block> block_kernel(const typename Law::Params& params, BlockIsa isa) {
  if constexpr (VariantLaneLaw<Law>)
    return block_kernel_among<Law, Block>(params, isa,
                                          std::make_index_sequence<static_cast<std::size_t>(Law::lane_variants)>{});
  else
    return block_kernel_among<Law, Block>(params, isa, std::make_index_sequence<1>{});
}

}  // namespace dem::detail

#include <dem/core/pair_loops.hpp>
#include <dem/core/wall_loops.hpp>

namespace dem::detail {

/// One address per law type: the type tag of its contact history (StateBuffer::law).
template <ContactLaw Law>
const void* law_tag() {
  static const char tag = 0;
  return &tag;
}

template <ContactLaw Law>
class ContactModelFor final : public ContactModel {
 public:
  explicit ContactModelFor(const typename Law::Params& params) : params_(params) {}
  const char* law_name() const override { return Law::name; }
  void compute(PairContacts& c, PairPlan& plan, const KernelContext& ctx, OverlapMonitor& worst) const override {
    compute_pairs<Law>(params_, c, plan, ctx, worst);
  }
  void compute(WallContacts& c, const KernelContext& ctx, OverlapMonitor& worst) const override {
    compute_walls<Law>(params_, c, ctx, worst);
  }
  ContactStiffness stiffness(const ContactKinematics& k) const override { return Law::stiffness(params_, k); }

  void reset_states(StateBuffer& buffer, std::size_t count) const override {
    using State = typename Law::State;
    buffer.law = law_tag<Law>();
    buffer.stride = sizeof(State);
    buffer.count = count;
    buffer.bytes.assign(count * sizeof(State), std::byte{0});
    for (std::size_t k = 0; k < count; ++k) ::new (buffer.at(k)) State{};
  }
  void remap_states(const StateBuffer& source, const std::vector<std::int64_t>& source_of, StateBuffer& target,
                    int threads) const override {
    using State = typename Law::State;
    const auto count = static_cast<std::int64_t>(source_of.size());
    target.law = law_tag<Law>();
    target.stride = sizeof(State);
    target.count = source_of.size();
    target.bytes.assign(source_of.size() * sizeof(State), std::byte{0});  // padding bytes defined
    const bool same_law = source.law == law_tag<Law>() && source.stride == sizeof(State);  // else all fresh
    // One pass, each entry either copied or fresh.
#pragma omp parallel for schedule(static) num_threads(open_team(threads_for(count, threads)))
    for (std::int64_t k = 0; k < count; ++k) {
      const std::int64_t from = source_of[static_cast<std::size_t>(k)];
      std::byte* entry = target.at(static_cast<std::size_t>(k));
      if (same_law && from >= 0)
        ::new (entry) State(*std::launder(reinterpret_cast<const State*>(source.at(static_cast<std::size_t>(from)))));
      else
        ::new (entry) State{};
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

// The loops above have taken these in; they are not part of the API.
#undef DEM_INDEPENDENT_ITERATIONS
#undef DEM_PREFETCH_FOR_READ
#undef DEM_PREFETCH_FOR_WRITE
#undef DEM_TARGET_AVX2
#undef DEM_TARGET_AVX512
