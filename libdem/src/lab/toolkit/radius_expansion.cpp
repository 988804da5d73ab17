#include <dem/lab/toolkit/radius_expansion.hpp>

#include <algorithm>
#include <string>

#include <dem/core/errors.hpp>
#include <dem/grid/cell_grid.hpp>

namespace dem::lab {

namespace {

// The balls placed so far, searchable: a CellGrid over all but the latest few, which are checked
// one by one until the grid is rebuilt with them (a CellGrid is built over fixed points).
class PlacedBalls {
 public:
  explicit PlacedBalls(double largest_radius) : cell_(2.0 * largest_radius) {}

  bool overlaps(const Vec3& x, double r) const {
    for (std::size_t i = gridded_; i < x_.size(); ++i)
      if ((x_[i] - x).norm() < radius_[i] + r) return true;
    if (gridded_ == 0) return false;
    // Cells are at least two of the largest radii wide: an overlapping ball is in a neighbouring cell.
    const auto c = grid_.cell_of(x);
    const auto& dims = grid_.dims();
    for (int iz = std::max(c[2] - 1, 0); iz <= std::min(c[2] + 1, dims[2] - 1); ++iz)
      for (int iy = std::max(c[1] - 1, 0); iy <= std::min(c[1] + 1, dims[1] - 1); ++iy)
        for (int ix = std::max(c[0] - 1, 0); ix <= std::min(c[0] + 1, dims[0] - 1); ++ix) {
          const std::int64_t cell = grid_.linear(ix, iy, iz);
          for (const std::int32_t* j = grid_.begin(cell); j != grid_.end(cell); ++j)
            if ((x_[static_cast<std::size_t>(*j)] - x).norm() < radius_[static_cast<std::size_t>(*j)] + r) return true;
        }
    return false;
  }

  void add(const Vec3& x, double r) {
    x_.push_back(x);
    radius_.push_back(r);
    if (x_.size() - gridded_ >= recent_limit) {
      grid_.build(x_, cell_);
      gridded_ = x_.size();
    }
  }

  const std::vector<Vec3>& positions() const { return x_; }

 private:
  static constexpr std::size_t recent_limit = 1024;
  double cell_;  // m
  CellGrid grid_;
  std::size_t gridded_ = 0;  // x_[0, gridded_) are in grid_
  std::vector<Vec3> x_;
  std::vector<double> radius_;
};

}  // namespace

std::vector<Vec3> place_without_overlap(const Cylinder& cavity, const std::vector<double>& radii, std::mt19937_64& rng) {
  require(cavity.radius > 0 && cavity.height > 0, "cavity radius and height", std::to_string(cavity.radius) + ", " +
          std::to_string(cavity.height), "> 0");
  const double largest = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PlacedBalls placed(largest);
  const double radius = cavity.radius, height = cavity.height;
  for (const double r : radii) {
    for (int attempt = 0;; ++attempt) {
      if (attempt == 100000)
        require(false, "ball placement", "no room for ball " + std::to_string(placed.positions().size() + 1) + " of " +
                              std::to_string(radii.size()), "a cavity large enough for the balls as placed (a looser target porosity)");
      const Vec3 x((2 * unit(rng) - 1) * (radius - r), (2 * unit(rng) - 1) * (radius - r), r + unit(rng) * (height - 2 * r));
      if (x.head<2>().norm() > radius - r) continue;
      if (placed.overlaps(x, r)) continue;
      placed.add(x, r);
      break;
    }
  }
  return placed.positions();
}

double RadiusExpansion::factor(int stage, int increment) const {
  return start_factor + (1.0 - start_factor) * ((stage - 1) + static_cast<double>(increment) / increments) / stages;
}

void set_radii(World& world, const RadiusExpansion& expansion, double factor) {
  require(expansion.balls.size() == expansion.diameters.size(), "radius expansion: balls", expansion.balls.size(),
          std::to_string(expansion.diameters.size()) + ", one per diameter");
  ParticleStore& p = world.particles();
  for (std::size_t n = 0; n < expansion.balls.size(); ++n)
    p.set_radius(p.index_of(expansion.balls[n]), factor * expansion.diameters[n] / 2);
  world.invalidate_contacts();
  world.update_time_step();
}

RadiusExpansion add_expanding_balls(World& world, const Cylinder& cavity, const std::vector<double>& diameters,
                                    double density, int stages, std::mt19937_64& rng) {
  RadiusExpansion expansion;
  expansion.diameters = diameters;
  expansion.stages = stages;
  std::vector<double> radii;
  radii.reserve(diameters.size());
  for (double d : diameters) radii.push_back(expansion.start_factor * d / 2);
  const std::vector<Vec3> centres = place_without_overlap(cavity, radii, rng);
  for (std::size_t n = 0; n < centres.size(); ++n) {
    BallSpec b;
    b.position = centres[n];
    b.radius = radii[n];
    b.density = density;
    expansion.balls.push_back(world.add_ball(b));
  }
  return expansion;
}

}  // namespace dem::lab
