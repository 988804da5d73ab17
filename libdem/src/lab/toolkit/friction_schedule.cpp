#include <dem/lab/toolkit/friction_schedule.hpp>

#include <algorithm>

namespace dem::lab {

std::optional<Friction> next_friction(const FrictionSchedule& schedule, double porosity, const Friction& now) {
  if (!(porosity > schedule.target_porosity + schedule.porosity_tolerance && (now.sliding > 0 || now.rolling > 0)))
    return std::nullopt;
  Friction next{now.sliding * schedule.reduction, now.rolling * schedule.reduction};
  if (std::max(next.sliding, next.rolling) < schedule.floor) next = {};
  return next;
}

}  // namespace dem::lab
