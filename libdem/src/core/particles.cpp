#include <dem/core/particles.hpp>

#include <string>

#include <dem/core/errors.hpp>
#include <dem/core/parallel.hpp>

namespace dem {

namespace {
template <class T>
void apply_order(std::vector<T>& data, const std::vector<std::int32_t>& order, int threads) {
  std::vector<T> sorted(data.size());
  const auto n = static_cast<std::int64_t>(order.size());
#pragma omp parallel for schedule(static) num_threads(open_team(threads))
  for (std::int64_t k = 0; k < n; ++k) {
    const auto at = static_cast<std::size_t>(k);
    sorted[at] = data[static_cast<std::size_t>(order[at])];
  }
  data.swap(sorted);
}
}  // namespace

ParticleId ParticleStore::add(const BallSpec& s, std::int32_t owner_clump) {
  const std::string what = "ball " + std::to_string(size());
  require(s.position.allFinite(), what + " position", "(non-finite)", "finite");
  require_positive(what + " radius", s.radius);
  if (owner_clump < 0) require_positive(what + " density", s.density);
  const ParticleId pid = static_cast<ParticleId>(size());
  const double m = s.density * 4.0 / 3.0 * pi * s.radius * s.radius * s.radius;
  x.push_back(s.position);
  v.push_back(s.velocity);
  w.push_back(s.angular_velocity);
  f.push_back(Vec3::Zero());
  t.push_back(Vec3::Zero());
  radius.push_back(s.radius);
  mass.push_back(m);
  inv_mass.push_back(m > 0.0 ? 1.0 / m : 0.0);
  inv_inertia.push_back(m > 0.0 ? 1.0 / (0.4 * m * s.radius * s.radius) : 0.0);
  id.push_back(pid);
  group.push_back(s.group);
  clump.push_back(owner_clump);
  fixed.push_back(s.fixed);
  index_of_id_.push_back(pid);
  return pid;
}

void ParticleStore::set_radius(std::size_t i, double new_radius) {
  require_positive("radius of ball id " + std::to_string(id[i]), new_radius);
  const double scale = new_radius / radius[i];
  radius[i] = new_radius;
  const double m = mass[i] * scale * scale * scale;
  mass[i] = m;
  inv_mass[i] = 1.0 / m;
  inv_inertia[i] = 1.0 / (0.4 * m * new_radius * new_radius);
}

void ParticleStore::restore_index() {
  index_of_id_.assign(id.size(), -1);
  for (std::size_t k = 0; k < id.size(); ++k) {
    const ParticleId pid = id[k];
    require(pid >= 0 && static_cast<std::size_t>(pid) < id.size() && index_of_id_[static_cast<std::size_t>(pid)] < 0,
            "particle id", pid, "unique and in [0, count)");
    index_of_id_[static_cast<std::size_t>(pid)] = static_cast<std::int32_t>(k);
  }
}

void ParticleStore::permute(const std::vector<std::int32_t>& order, int threads) {
  const int team = threads_for(static_cast<std::int64_t>(order.size()), threads);
  apply_order(x, order, team);
  apply_order(v, order, team);
  apply_order(w, order, team);
  apply_order(f, order, team);
  apply_order(t, order, team);
  apply_order(radius, order, team);
  apply_order(mass, order, team);
  apply_order(inv_mass, order, team);
  apply_order(inv_inertia, order, team);
  apply_order(id, order, team);
  apply_order(group, order, team);
  apply_order(clump, order, team);
  apply_order(fixed, order, team);
  const auto n = static_cast<std::int64_t>(id.size());
#pragma omp parallel for schedule(static) num_threads(open_team(team))
  for (std::int64_t k = 0; k < n; ++k)  // ids are unique: each thread writes its own entries
    index_of_id_[static_cast<std::size_t>(id[static_cast<std::size_t>(k)])] = static_cast<std::int32_t>(k);
}

}  // namespace dem
