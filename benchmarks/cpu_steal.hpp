// The share of the time this virtual machine's processors wanted to run but the hypervisor ran
// something else while a measurement ran ("steal", the eighth field of /proc/stat's `cpu` line),
// out of the time they ran or wanted to (idle time left out, so that a one-thread run on two
// processors is not diluted by the idle one). On a cloud VM it is what makes one binary 20-40 %
// slower from one hour to the next: the rate of a run with a few percent of steal or more is
// lowered by it, and is no measure of the code.
#pragma once

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace dem::bench {

/// Cumulative CPU time of all processors since boot, in clock ticks (Linux /proc/stat).
struct CpuTicks {
  double steal = 0.0;
  double wanted = 0.0;  // every field but idle and iowait: running, or ready and stolen
  bool known = false;

  static CpuTicks now() {
    CpuTicks t;
    std::ifstream in("/proc/stat");
    std::string line, name;
    if (!std::getline(in, line)) return t;
    std::istringstream fields(line);
    // user nice system idle iowait irq softirq steal (guest and guest_nice are inside user and nice)
    std::array<double, 8> v{};
    if (!(fields >> name) || name != "cpu") return t;
    for (double& x : v)
      if (!(fields >> x)) return t;
    t.wanted = v[0] + v[1] + v[2] + v[5] + v[6] + v[7];
    t.steal = v[7];
    t.known = true;
    return t;
  }
};

/// Steal between two readings as a fraction of the time the processors ran or wanted to; NaN if
/// /proc/stat could not be read or no tick passed.
inline double steal_fraction(const CpuTicks& before, const CpuTicks& after) {
  const double wanted = after.wanted - before.wanted;
  if (!before.known || !after.known || wanted <= 0.0) return std::nan("");
  return (after.steal - before.steal) / wanted;
}

}  // namespace dem::bench
