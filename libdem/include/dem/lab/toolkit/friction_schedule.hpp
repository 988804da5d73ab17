// The friction schedule of a specimen grown against a low stress (docs/model.md 7.1): a frictional
// packing stays looser than the target porosity while its friction holds it open, so the ball-ball
// friction is lowered step by step, the packing settling after each step, until the porosity is
// within a tolerance of the target or the friction is zero. This part decides the next step; the
// protocol sets the contact laws and settles the packing.
#pragma once

#include <optional>

namespace dem::lab {

/// Sliding and rolling friction coefficients of a contact law.
struct Friction {
  double sliding = 0.0;  // -, mu
  double rolling = 0.0;  // -, mu_r
};

struct FrictionSchedule {
  double target_porosity = 0.4;     // -
  double porosity_tolerance = 0.005;  // -, the schedule ends within this of the target
  double reduction = 0.5;           // -, factor on both coefficients per step
  double floor = 0.0;               // -, both coefficients become 0 once the larger is below this
};

/// The friction of the next step, or none when the schedule is over: the porosity is within the
/// tolerance of the target (or below it), or the friction is already zero.
std::optional<Friction> next_friction(const FrictionSchedule& schedule, double porosity, const Friction& now);

}  // namespace dem::lab
