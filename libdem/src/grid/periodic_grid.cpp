#include <dem/grid/periodic_grid.hpp>

#include <algorithm>
#include <cmath>

#include <omp.h>

#include <dem/base/threads.hpp>

namespace dem {

std::array<int, 3> PeriodicGrid::dims_for(const Vec3& widths, double min_cell_size) {
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[static_cast<std::size_t>(a)] = static_cast<int>(std::min(std::floor(widths[a] / min_cell_size), 1e6));
  return dims;
}

void PeriodicGrid::build(const std::vector<Vec3>& x, const Mat3& h_inverse, const Vec3& origin,
                         const std::array<int, 3>& dims, int threads) {
  dims_ = dims;
  const auto n = static_cast<std::int64_t>(x.size());
  cell_index_.resize(x.size());
  const Vec3 scale(dims[0], dims[1], dims[2]);
#pragma omp parallel for schedule(static) num_threads(open_team(threads_for(n, std::max(1, threads))))
  for (std::int64_t k = 0; k < n; ++k) {
    const Vec3 s = (h_inverse * (x[static_cast<std::size_t>(k)] - origin)).cwiseProduct(scale);
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)  // a point a rounding outside a face goes to the cell at that face
      c[static_cast<std::size_t>(a)] = static_cast<int>(std::clamp(std::floor(s[a]), 0.0, scale[a] - 1.0));
    cell_index_[static_cast<std::size_t>(k)] = linear(c);
  }
  const std::int64_t cells = std::int64_t{dims[0]} * dims[1] * dims[2];
  start_.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (const std::int64_t c : cell_index_) ++start_[static_cast<std::size_t>(c) + 1];
  for (std::int64_t c = 0; c < cells; ++c) start_[static_cast<std::size_t>(c) + 1] += start_[static_cast<std::size_t>(c)];
  order_.resize(x.size());
  std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t k = 0; k < x.size(); ++k)
    order_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_index_[k])]++)] = static_cast<std::int32_t>(k);
}

void PeriodicGrid::renumber_in_cell_order() {
  std::vector<std::int64_t> sorted(order_.size());
  for (std::size_t k = 0; k < order_.size(); ++k) {
    sorted[k] = cell_index_[static_cast<std::size_t>(order_[k])];
    order_[k] = static_cast<std::int32_t>(k);
  }
  cell_index_ = std::move(sorted);
}

std::array<int, 3> PeriodicGrid::cell_of_point(std::size_t k) const {
  const std::int64_t c = cell_index_[k];
  return {static_cast<int>(c % dims_[0]), static_cast<int>(c / dims_[0] % dims_[1]),
          static_cast<int>(c / (std::int64_t{dims_[0]} * dims_[1]))};
}

void find_periodic_pairs_in(const PeriodicGrid& grid, const std::vector<Vec3>& x, const Mat3& h,
                            const std::vector<double>& radius, double skin, int threads, std::vector<std::int32_t>& first,
                            std::vector<std::int32_t>& second, std::vector<std::uint8_t>& image) {
  const auto n = static_cast<std::int64_t>(x.size());
  const int team = threads_for(n, std::max(1, threads));
  struct Part {
    std::vector<std::int32_t> first, second;
    std::vector<std::uint8_t> image;
  };
  std::vector<Part> parts(static_cast<std::size_t>(team));
  const auto dims = grid.dims();
#pragma omp parallel for schedule(static) num_threads(open_team(team))
  for (int t = 0; t < team; ++t) {
    Part& out = parts[static_cast<std::size_t>(t)];
    for (std::int64_t i = n * t / team; i < n * (t + 1) / team; ++i) {
      const Vec3& xi = x[static_cast<std::size_t>(i)];
      const double ri = radius[static_cast<std::size_t>(i)] + skin;
      const std::array<int, 3> c = grid.cell_of_point(static_cast<std::size_t>(i));
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            // The neighbour across a face is the search cell at the far side, seen through image n.
            std::array<int, 3> neighbour{c[0] + dx, c[1] + dy, c[2] + dz}, cells_across{0, 0, 0};
            for (std::size_t a = 0; a < 3; ++a) {
              if (neighbour[a] < 0) cells_across[a] = -1;
              if (neighbour[a] >= dims[a]) cells_across[a] = 1;
              neighbour[a] -= cells_across[a] * dims[a];
            }
            const Vec3 shift = h * Vec3(cells_across[0], cells_across[1], cells_across[2]);
            const auto code = static_cast<std::uint8_t>((cells_across[0] + 1) + 3 * (cells_across[1] + 1) +
                                                        9 * (cells_across[2] + 1));
            const std::int64_t cell = grid.linear(neighbour);
            for (const std::int32_t* it = grid.begin(cell); it != grid.end(cell); ++it) {
              const std::int32_t j = *it;
              if (j <= i) continue;
              const double reach = ri + radius[static_cast<std::size_t>(j)];
              if (((x[static_cast<std::size_t>(j)] + shift) - xi).squaredNorm() < reach * reach) {
                out.first.push_back(static_cast<std::int32_t>(i));
                out.second.push_back(j);
                out.image.push_back(code);
              }
            }
          }
    }
  }
  first.clear(), second.clear(), image.clear();
  for (Part& part : parts) {
    first.insert(first.end(), part.first.begin(), part.first.end());
    second.insert(second.end(), part.second.begin(), part.second.end());
    image.insert(image.end(), part.image.begin(), part.image.end());
  }
}

}  // namespace dem
