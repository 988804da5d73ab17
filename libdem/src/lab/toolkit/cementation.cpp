// Cementation: bonds between the close pairs of a specimen, found in the World's own neighbour
// lists (the pair geometry there already knows a periodic cell's images), in list order.
#include <dem/lab/toolkit/cementation.hpp>

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include <dem/core/errors.hpp>
#include <dem/core/pair_geometry.hpp>

namespace dem::lab {

const io::BindingTable<CementationConfig>& cementation_keys() {
  using S = CementationConfig;
  static const io::BindingTable<S> table = {
      {"after", io::enum_choice({"none", "generation", "consolidation"}, &S::after), "-",
       "when bonds are installed: none, generation (the specimen placed), consolidation (compressed, before the loading)"},
      {"gap_ratio", &S::gap_ratio, "-", "a pair is bonded when its gap is below this x its mean radius (within the skin)", 0.0, 1.0},
      {"fraction", &S::fraction, "-", "fraction of those pairs bonded, chosen per pair", 0.0, 1.0, true},
      {"radius_multiplier", &S::radius_multiplier, "-", "bond radius / smaller ball radius (lambda)", 0.0, 1.0, true},
      {"normal_stiffness", &S::normal_stiffness, "Pa/m", "bond normal stiffness per area", 0.0, 1e18, true},
      {"shear_stiffness", &S::shear_stiffness, "Pa/m", "bond shear stiffness per area", 0.0, 1e18, true},
      {"tensile_strength", &S::tensile_strength, "Pa", "mean tensile strength of a bond", 0.0, 1e12},
      {"tensile_strength_std", &S::tensile_strength_std, "Pa", "standard deviation of the tensile strength", 0.0, 1e12},
      {"cohesion", &S::cohesion, "Pa", "mean cohesion of a bond (shear strength at zero normal stress)", 0.0, 1e12},
      {"cohesion_std", &S::cohesion_std, "Pa", "standard deviation of the cohesion", 0.0, 1e12},
      {"friction_angle", &S::friction_angle, "deg", "bond friction angle: shear strength c - sigma tan(phi), tension positive", 0.0, 89.0},
  };
  return table;
}

ParallelBondMaterial bond_material(const CementationConfig& c, std::uint64_t seed) {
  ParallelBondMaterial m;
  m.radius_multiplier = c.radius_multiplier;
  m.normal_stiffness = c.normal_stiffness;
  m.shear_stiffness = c.shear_stiffness;
  m.tensile_strength = c.tensile_strength;
  m.tensile_strength_std = c.tensile_strength_std;
  m.cohesion = c.cohesion;
  m.cohesion_std = c.cohesion_std;
  m.friction_angle = c.friction_angle * pi / 180.0;
  m.seed = seed;
  m.validate("cementation");
  return m;
}

std::size_t cement(World& world, const ParallelBondMaterial& material, double gap_ratio, double fraction) {
  material.validate("cementation");
  require(gap_ratio >= 0.0 && gap_ratio <= 1.0, "cementation.gap_ratio", gap_ratio, "in [0, 1]");
  require(fraction > 0.0 && fraction <= 1.0, "cementation.fraction", fraction, "in (0, 1]");
  world.rebuild_now(false);  // candidates: every pair closer than its radii plus the skin, now
  const ParticleStore& p = world.particles();
  double largest = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_pebble(i)) largest = std::max(largest, p.radius[i]);
  const double skin = world.state().rebuild.skin;
  require(gap_ratio * largest <= skin, "cementation.gap_ratio", gap_ratio,
          "at most skin / largest radius = " + io::real_text(skin / largest) +
              " (bonded gaps are found in the neighbour lists, whose skin is half the smallest radius unless WorldSettings::skin sets it)");
  std::set<std::pair<ParticleId, ParticleId>> bonded;
  const BondStore& bonds = world.bonds();
  for (std::size_t k = 0; k < bonds.size(); ++k)
    bonded.insert(std::minmax(bonds.first[k], bonds.second[k]));
  const PairContacts& c = world.pair_contacts(ContactKind::BallBall);
  std::optional<ImageShifts> images;
  if (world.periodic_cell()) images = world.periodic_cell()->image_shifts();
  std::size_t made = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto i = static_cast<std::size_t>(c.first[k]), j = static_cast<std::size_t>(c.second[k]);
    const double mean_radius = 0.5 * (p.radius[i] + p.radius[j]);
    const double gap = contact_branch(c, k, p.x.data(), images ? &*images : nullptr).norm() - p.radius[i] - p.radius[j];
    if (gap > gap_ratio * mean_radius) continue;
    const ParticleId a = p.id[i], b = p.id[j];
    if (fraction < 1.0) {  // this pair's own uniform deviate, from the seed and its ids
      const auto key = ParallelBondMaterial::mix(material.seed ^ ParallelBondMaterial::mix(
                                                     (static_cast<std::uint64_t>(std::max(a, b)) << 32) ^ 0x5bd1e995ULL ^
                                                     static_cast<std::uint64_t>(std::min(a, b))));
      if (static_cast<double>(key >> 11) * 0x1.0p-53 >= fraction) continue;
    }
    if (!bonded.insert(std::minmax(a, b)).second) continue;
    world.add_bond(a, b, material.draw(a, b, p.radius[i], p.radius[j]));
    ++made;
  }
  return made;
}

void add_bond_columns(HistoryLog& h, const World& w) {
  h.add("bonds_intact", [&w] { return static_cast<double>(w.bonds().count(BondStatus::intact)); });
  h.add("bonds_broken_tension", [&w] { return static_cast<double>(w.bonds().count(BondStatus::broken_tension)); });
  h.add("bonds_broken_shear", [&w] { return static_cast<double>(w.bonds().count(BondStatus::broken_shear)); });
  h.add("bond_energy_released_J", [&w] { return w.bonds().released_energy(); });
}

}  // namespace dem::lab
