// Small parallel helpers every floor may use (the ground floor of the house: no engine types).
#pragma once

#include <cstdint>

namespace dem {

/// Threads worth using for a loop of `count` items: small loops run serially, since starting a
/// parallel region costs more than it saves (and oversubscribed cores make it far worse).
inline constexpr std::int64_t min_parallel_items = 4096;
inline int threads_for(std::int64_t count, int threads) { return count >= min_parallel_items ? threads : 1; }

}  // namespace dem
