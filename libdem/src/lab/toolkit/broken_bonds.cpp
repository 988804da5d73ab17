// The broken bonds of a cemented run: the strain each was first seen broken at, and a VTK file.
#include <dem/lab/toolkit/broken_bonds.hpp>

#include <cmath>
#include <limits>
#include <utility>

#include <dem/io/vtk.hpp>

namespace dem::lab {

BrokenBondLog::BrokenBondLog(Run& run, const std::string& key, std::string strain_name)
    : strain_name_(std::move(strain_name)) {
  run.keep_points(key, seen_);
}

void BrokenBondLog::update(const World& world, double strain) {
  const BondStore& b = world.bonds();
  const double none = std::numeric_limits<double>::quiet_NaN();
  if (seen_.size() < b.size()) seen_.resize(b.size(), Vec3(none, 0.0, 0.0));
  for (std::size_t k = 0; k < b.size(); ++k)
    if (!b.intact(k) && std::isnan(seen_[k].x())) seen_[k] = Vec3(strain, 0.0, 0.0);
}

std::vector<double> BrokenBondLog::strains() const {
  std::vector<double> s;
  for (const Vec3& v : seen_) s.push_back(v.x());
  return s;
}

void BrokenBondLog::write_vtp(const World& world, const std::filesystem::path& file) const {
  const BondStore& b = world.bonds();
  const ParticleStore& p = world.particles();
  std::vector<Vec3> points;
  std::vector<double> mode, strain, energy, first, second;
  for (std::size_t k = 0; k < b.size() && k < seen_.size(); ++k) {
    if (b.intact(k) || std::isnan(seen_[k].x())) continue;
    const std::size_t i = p.index_of(b.first[k]), j = p.index_of(b.second[k]);
    const Vec3 d = world.bond_branch(k);  // to the nearest image in a periodic cell
    const double dist = d.norm();
    const double overlap = p.radius[i] + p.radius[j] - dist;
    points.push_back(dist > 0.0 ? Vec3(p.x[i] + (p.radius[i] - 0.5 * overlap) / dist * d) : p.x[i]);
    mode.push_back(static_cast<double>(b.status[k]));
    strain.push_back(seen_[k].x());
    energy.push_back(ParallelBondLaw::strain_energy(b.params(k), b.state(k)));
    first.push_back(static_cast<double>(b.first[k]));
    second.push_back(static_cast<double>(b.second[k]));
  }
  io::write_points_vtp(file, points,
                       {{"mode", mode}, {strain_name_ + "_broken", strain}, {"energy_released_J", energy}, {"first_id", first}, {"second_id", second}});
}

}  // namespace dem::lab
