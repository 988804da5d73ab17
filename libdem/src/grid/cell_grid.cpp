#include <dem/grid/cell_grid.hpp>

#include <algorithm>
#include <cmath>

#include <omp.h>

#include <dem/base/threads.hpp>

namespace dem {

void CellGrid::build(const std::vector<Vec3>& points, double min_cell_size, double padding, int threads) {
  Vec3 lo = Vec3::Constant(0.0), hi = Vec3::Constant(0.0);
  if (!points.empty()) {
    lo = hi = points[0];
    for (const Vec3& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  lo.array() -= padding;
  hi.array() += padding;
  const Vec3 extent = (hi - lo).cwiseMax(1e-300);
  // A runaway particle must not blow up memory: keep the cell count within a few per point.
  const double max_cells = 8.0 * static_cast<double>(std::max<std::size_t>(points.size(), 64));
  cell_ = min_cell_size;
  while ((std::floor(extent.x() / cell_) + 1) * (std::floor(extent.y() / cell_) + 1) *
             (std::floor(extent.z() / cell_) + 1) > max_cells)
    cell_ *= 1.25;
  origin_ = lo;
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor(extent[a] / cell_)) + 1;
  axes_ = {0, 1, 2};
  std::stable_sort(axes_.begin(), axes_.end(), [this](int l, int r) { return dims_[l] > dims_[r]; });
  stride_[axes_[2]] = 1;
  stride_[axes_[1]] = dims_[axes_[2]];
  stride_[axes_[0]] = static_cast<std::int64_t>(dims_[axes_[2]]) * dims_[axes_[1]];

  const std::int64_t cells = static_cast<std::int64_t>(dims_[0]) * dims_[1] * dims_[2];
  start_.assign(static_cast<std::size_t>(cells) + 1, 0);
  std::vector<std::int64_t> cell_index(points.size());
  const auto n = static_cast<std::int64_t>(points.size());
#pragma omp parallel for schedule(static) num_threads(open_team(threads_for(n, std::max(1, threads))))
  for (std::int64_t i = 0; i < n; ++i) {
    const auto c = cell_of(points[static_cast<std::size_t>(i)]);
    cell_index[static_cast<std::size_t>(i)] = linear(c[0], c[1], c[2]);
  }
  for (std::size_t i = 0; i < points.size(); ++i) ++start_[static_cast<std::size_t>(cell_index[i]) + 1];
  for (std::int64_t c = 0; c < cells; ++c) start_[static_cast<std::size_t>(c) + 1] += start_[static_cast<std::size_t>(c)];
  order_.resize(points.size());
  std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i)
    order_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_index[i])]++)] = static_cast<std::int32_t>(i);
}

void CellGrid::renumber_in_cell_order() {
  for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<std::int32_t>(k);
}

std::array<int, 3> CellGrid::cell_of(const Vec3& point) const {
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double s = std::floor((point[a] - origin_[a]) / cell_);
    c[a] = static_cast<int>(std::clamp(s, 0.0, static_cast<double>(dims_[a] - 1)));
  }
  return c;
}

void find_pairs(const std::vector<Vec3>& x, const std::vector<double>& radius, double skin, int threads,
                CellGrid& grid, std::vector<std::int32_t>& first, std::vector<std::int32_t>& second) {
  const double max_radius = radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
  grid.build(x, 2.0 * max_radius + skin, 0.0, threads);
  find_pairs_in(grid, x, radius, skin, threads, first, second);
}

void find_pairs_in(const CellGrid& grid, const std::vector<Vec3>& x, const std::vector<double>& radius, double skin,
                   int threads, std::vector<std::int32_t>& first, std::vector<std::int32_t>& second) {
  const auto n = static_cast<std::int64_t>(x.size());
  const int nthreads = threads_for(n, std::max(1, threads));
  std::vector<std::vector<std::int32_t>> local_first(static_cast<std::size_t>(nthreads)),
      local_second(static_cast<std::size_t>(nthreads));
  const auto dims = grid.dims();
  const auto axes = grid.axes_slowest_first();
#pragma omp parallel num_threads(open_team(nthreads))
  {
    const auto me = static_cast<std::size_t>(omp_get_thread_num());
    auto& out_first = local_first[me];
    auto& out_second = local_second[me];
    std::size_t found = 0;
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      const Vec3 xi = x[static_cast<std::size_t>(i)];
      const double ri = radius[static_cast<std::size_t>(i)] + skin;
      const auto c = grid.cell_of(xi);
      // Rows along the fastest axis of the grid's order, visited in that order.
      const int slow = axes[0], middle = axes[1], fast = axes[2];
      std::array<int, 3> lo = c, hi = c;
      lo[fast] = std::max(c[fast] - 1, 0), hi[fast] = std::min(c[fast] + 1, dims[fast] - 1);
      for (int d_slow = -1; d_slow <= 1; ++d_slow) {
        const int s = c[slow] + d_slow;
        if (s < 0 || s >= dims[slow]) continue;
        lo[slow] = hi[slow] = s;
        for (int d_middle = -1; d_middle <= 1; ++d_middle) {
          const int m = c[middle] + d_middle;
          if (m < 0 || m >= dims[middle]) continue;
          lo[middle] = hi[middle] = m;
          // The row's three cells are neighbours in the grid's order: one run of points, cell by
          // cell, each cell's in ascending order. A row whose every point comes before i (each
          // cell's last point is its largest; all earlier rows once the particles are sorted by
          // cells) goes with three comparisons.
          const std::int64_t row_lo = grid.linear(lo), row_hi = grid.linear(hi);
          const std::int32_t* it = grid.begin(row_lo);
          const std::int32_t* const last = grid.end(row_hi);
          std::int32_t row_max = -1;
          for (std::int64_t cell = row_lo; cell <= row_hi; ++cell)
            if (grid.begin(cell) != grid.end(cell)) row_max = std::max(row_max, grid.end(cell)[-1]);
          if (row_max <= i) continue;
          // Every point is written to the next slot, which only a pair within reach keeps: about
          // one in five is, in no predictable pattern, and a branch on it would mispredict.
          const auto room = found + static_cast<std::size_t>(last - it);
          if (out_second.size() < room) {
            out_first.resize(std::max(room, 2 * out_second.size()));
            out_second.resize(out_first.size());
          }
          for (; it != last; ++it) {
            const std::int32_t j = *it;
            const double reach = ri + radius[static_cast<std::size_t>(j)];
            const bool keep = j > i && (x[static_cast<std::size_t>(j)] - xi).squaredNorm() < reach * reach;
            out_first[found] = static_cast<std::int32_t>(i);
            out_second[found] = j;
            found += keep ? 1 : 0;
          }
        }
      }
    }
    out_first.resize(found);
    out_second.resize(found);
  }
  // Exact-size result, each thread's buffer freed once copied: the rebuild's peak memory is the
  // largest of the run (it sets the bytes per ball of the largest specimens).
  std::size_t total = 0;
  for (const auto& l : local_first) total += l.size();
  first.clear();
  second.clear();
  first.reserve(total);
  second.reserve(total);
  for (std::size_t t = 0; t < local_first.size(); ++t) {
    first.insert(first.end(), local_first[t].begin(), local_first[t].end());
    second.insert(second.end(), local_second[t].begin(), local_second[t].end());
    std::vector<std::int32_t>().swap(local_first[t]);
    std::vector<std::int32_t>().swap(local_second[t]);
  }
}

}  // namespace dem
