// The cell grid of a periodic cell (boundary/periodic_cell.hpp): the cell cut into search cells
// along its own edges, in reduced coordinates, and the neighbours of a search cell found across
// the faces, with the image vector n (components -1, 0, 1) that brings the partner next to the
// particle. Each search cell is at least as thick as the largest diameter plus the skin, so every
// pair within reach lies in the same or a neighbouring search cell, in a skewed cell too.
//
// Chosen over ghost copies of the particles near the faces: the contact carries its image vector
// (PairContacts::image) instead of pointing at a copy, so nothing is copied or kept in step each
// step and the particle store stays the particles' own; ghosts of other processes can later name
// their partner the same way (core/pair_geometry.hpp).
//
// The grid needs at least three search cells along each axis (the three neighbours of a cell are
// then three different cells, and a particle touches at most one image of another); the World
// refuses a thinner cell.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>

namespace dem {

class PeriodicGrid {
 public:
  /// Search cells along each axis for a cell `widths` thick (m, the distances between its
  /// opposite faces) and search cells at least `min_cell_size` (m) thick.
  static std::array<int, 3> dims_for(const Vec3& widths, double min_cell_size);
  /// Bins the points `x` (m, inside the cell h from `origin`, up to rounding at the faces) into
  /// `dims` search cells along the edges (each >= 3), on up to `threads` threads (the same grid
  /// for any count). `h_inverse` is h^-1 (1/m).
  void build(const std::vector<Vec3>& x, const Mat3& h_inverse, const Vec3& origin, const std::array<int, 3>& dims,
             int threads);
  /// After the points were reordered by cell_order(): the grid build() would make of them.
  void renumber_in_cell_order();
  /// All point indices in search-cell order (z slowest, x fastest), to re-sort the particles.
  const std::vector<std::int32_t>& cell_order() const { return order_; }
  const std::array<int, 3>& dims() const { return dims_; }
  /// The search cell of point k.
  std::array<int, 3> cell_of_point(std::size_t k) const;
  std::int64_t linear(const std::array<int, 3>& c) const { return c[0] + dims_[0] * (c[1] + std::int64_t{dims_[1]} * c[2]); }
  const std::int32_t* begin(std::int64_t c) const { return order_.data() + start_[static_cast<std::size_t>(c)]; }
  const std::int32_t* end(std::int64_t c) const { return order_.data() + start_[static_cast<std::size_t>(c) + 1]; }

 private:
  std::array<int, 3> dims_{3, 3, 3};
  std::vector<std::int64_t> cell_index_;  // per point
  std::vector<std::int32_t> start_;       // per search cell + 1
  std::vector<std::int32_t> order_;       // point indices sorted by search cell
};

/// Every pair i < j whose nearest images are closer than r_i + r_j + skin: `first` i, `second` j
/// and `image` the image code (boundary/periodic_cell.hpp: (n0 + 1) + 3 (n1 + 1) + 9 (n2 + 1)) of
/// the image x_j + h n that i reaches. In order of i, the same for any thread count. `grid` was
/// built of `x` with search cells at least the largest diameter plus the skin thick.
void find_periodic_pairs_in(const PeriodicGrid& grid, const std::vector<Vec3>& x, const Mat3& h,
                            const std::vector<double>& radius, double skin, int threads, std::vector<std::int32_t>& first,
                            std::vector<std::int32_t>& second, std::vector<std::uint8_t>& image);

}  // namespace dem
