// Broad phase: a uniform linked-cell grid. Cells are at least as large as the largest diameter
// plus the skin, so every pair closer than (Ri + Rj + skin) lies in the same or a neighbouring
// cell. Polydisperse radii are fine; a few very large spheres make the cells coarse.
//
// The pair list it produces is in (i, j) order with i < j, whatever the thread count: threads
// work on contiguous blocks of i and their results are concatenated in block order.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <dem/base/math.hpp>

namespace dem {

class CellGrid {
 public:
  /// Bins the points into cells of edge >= min_cell_size (m) over their bounding box, padded by
  /// `padding` (m). Cells grow if needed so that there are at most 8 per point (a runaway
  /// particle must not exhaust memory). The points' cells are found on up to `threads` OpenMP
  /// threads (the same grid for any count).
  void build(const std::vector<Vec3>& points, double min_cell_size, double padding = 0.0, int threads = 1);
  /// After the points were reordered by cell_order() (point k is now the one that was
  /// cell_order()[k]): the grid that build() would make of them, without binning them again.
  void renumber_in_cell_order();

  /// Cell coordinates of a point (clamped to the grid).
  std::array<int, 3> cell_of(const Vec3& point) const;
  /// The cell's place in the grid's order: the grid's longest axis varies slowest, its shortest
  /// fastest (of two axes as many cells long, x is the slower, then y). A plane of cells across
  /// the slowest axis is then the smallest section of the specimen: contiguous shares of the
  /// particles (threads, processes) have the fewest particles in common, and a particle's
  /// neighbours lie closest in memory.
  std::int64_t linear(int ix, int iy, int iz) const { return ix * stride_[0] + iy * stride_[1] + iz * stride_[2]; }
  std::int64_t linear(const std::array<int, 3>& cell) const { return linear(cell[0], cell[1], cell[2]); }
  /// The axes (0 x, 1 y, 2 z) from the slowest-varying in the grid's order to the fastest.
  const std::array<int, 3>& axes_slowest_first() const { return axes_; }

  /// Indices of the points in cell `c` (a contiguous range of the sorted order).
  const std::int32_t* begin(std::int64_t c) const { return order_.data() + start_[static_cast<std::size_t>(c)]; }
  const std::int32_t* end(std::int64_t c) const { return order_.data() + start_[static_cast<std::size_t>(c) + 1]; }

  /// All point indices in cell order (used to re-sort particles for cache locality).
  const std::vector<std::int32_t>& cell_order() const { return order_; }
  const std::array<int, 3>& dims() const { return dims_; }
  double cell_size() const { return cell_; }
  const Vec3& origin() const { return origin_; }

 private:
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::array<int, 3> axes_{0, 1, 2};              // slowest first
  std::array<std::int64_t, 3> stride_{1, 1, 1};  // cells, along x, y, z
  std::vector<std::int32_t> start_;  // size cells + 1
  std::vector<std::int32_t> order_;  // point indices sorted by cell
};

/// Finds every pair (i < j) with |x_i - x_j| < r_i + r_j + skin. `grid` is rebuilt here.
/// `first` and `second` receive the pairs in (i, j) order.
void find_pairs(const std::vector<Vec3>& x, const std::vector<double>& radius, double skin, int threads,
                CellGrid& grid, std::vector<std::int32_t>& first, std::vector<std::int32_t>& second);
/// The same with `grid` already built of these points, with cells of at least the largest
/// diameter plus the skin.
void find_pairs_in(const CellGrid& grid, const std::vector<Vec3>& x, const std::vector<double>& radius, double skin,
                   int threads, std::vector<std::int32_t>& first, std::vector<std::int32_t>& second);

}  // namespace dem
