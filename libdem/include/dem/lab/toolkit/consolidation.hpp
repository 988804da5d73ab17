// Consolidation as a part of a protocol: a servo-controlled plate brought to a target stress until
// the stress has stayed on target (the servo's settle criterion) and the packing is near
// equilibrium, on a World the caller owns and whose controller runs the servo.
#pragma once

#include <cstdint>
#include <functional>

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>

namespace dem::lab {

/// Where to take the servo plate, and when to stop.
struct ConsolidationTarget {
  double vertical_stress = 200e3;    // Pa, on the servo plate (consolidation.vertical_stress)
  double servo_max_speed = 0.05;     // m/s, cap of the plate's speed
  double equilibrium_ratio = 1e-2;   // -, unbalanced / mean contact force at which the packing counts as settled
  std::int64_t max_steps = 400000;   // steps after which the consolidation stops unsettled
  std::int64_t chunk_steps = 10;     // steps between two checks (and two calls of `between_chunks`)
};

/// How the consolidation ended.
struct ConsolidationReport {
  bool settled = false;           // false: max_steps ran out first
  std::int64_t steps = 0;         // steps since the consolidation started
  double stress = 0.0;            // Pa, on the servo plate in the last step
  double unbalanced_ratio = 0.0;  // -
};

/// Gives the servo the target's stress and speed cap: the start of a consolidation.
void start_consolidation(ServoWall& servo, const ConsolidationTarget& target);

/// Steps `world` in chunks until the servo has settled and the unbalanced-force ratio is below the
/// target's, or `max_steps` have passed since step `start_step` (a consolidation resumed from a
/// restart file passes the step it started at). `between_chunks` runs after every chunk that does
/// not end it: outputs, restart files, progress lines. The servo must be run by the world's
/// controller.
ConsolidationReport consolidate(World& world, const ServoWall& servo, const ConsolidationTarget& target,
                                std::int64_t start_step, const std::function<void()>& between_chunks = {});

}  // namespace dem::lab
