// Cementation of a specimen (docs/cementation.md): linear parallel bonds installed between the
// balls that are close, at a chosen moment of a protocol. The keys (cementation.*) are declared
// once here and read into CementationConfig; cement() works on the World it is given.
#pragma once

#include <cstddef>
#include <cstdint>

#include <dem/contact/bond_material.hpp>
#include <dem/core/world.hpp>
#include <dem/io/config_binding.hpp>
#include <dem/lab/toolkit/history_log.hpp>

namespace dem::lab {

/// When a protocol installs the bonds: never, once the specimen is generated (placed), or once it
/// is consolidated (before the loading, so a consolidated restart file is the plain specimen).
enum class CementAfter { None = 0, Generation = 1, Consolidation = 2 };

/// [cementation]
struct CementationConfig {
  CementAfter after = CementAfter::None;
  double gap_ratio = 0.05;            // -, a pair is bonded when its gap is below this x its mean radius
  double fraction = 1.0;              // -, of those pairs bonded (chosen per pair from the seed)
  double radius_multiplier = 1.0;     // -, lambda: bond radius lambda min(R1, R2)
  double normal_stiffness = 1e11;     // Pa/m
  double shear_stiffness = 1e11;      // Pa/m
  double tensile_strength = 1e6;      // Pa, mean
  double tensile_strength_std = 0.0;  // Pa
  double cohesion = 1e6;              // Pa, mean
  double cohesion_std = 0.0;          // Pa
  double friction_angle = 0.0;        // deg
  bool operator==(const CementationConfig&) const = default;
};

/// The cementation.* keys, each with its unit, range and help; `rule`: when a resumed run may no
/// longer change them.
const io::BindingTable<CementationConfig>& cementation_keys();

/// The bond material of `c`, its strengths drawn from `seed` (each pair's its own).
ParallelBondMaterial bond_material(const CementationConfig& c, std::uint64_t seed);

/// Bonds every pair of free balls of `world` whose gap is below gap_ratio x their mean radius
/// (overlapping pairs included), or the `fraction` of them chosen per pair from the material's
/// seed, with parameters drawn from `material`; returns how many bonds it made. The neighbour
/// lists are remade first, so gap_ratio x the largest mean radius must be within the World's skin
/// (InputError naming cementation.gap_ratio otherwise). Pairs already bonded are left as they are.
std::size_t cement(World& world, const ParallelBondMaterial& material, double gap_ratio, double fraction = 1.0);

/// The history columns of a cemented run (added only when cementation is on, so that a plain run's
/// files stay as they were): bonds_intact, bonds_broken_tension, bonds_broken_shear and
/// bond_energy_released_J (the strain energy the broken bonds held when they broke, summed).
void add_bond_columns(HistoryLog& history, const World& world);

}  // namespace dem::lab
