// What dem-simple-shear does with its command line, for the apps that run it (dem-simple-shear,
// dem-ensemble once per seed).
#pragma once

#include <iosfwd>
#include <string>

#include "shear_command_line.hpp"
#include "spread_run.hpp"

namespace dem::cli {

/// The simple-shear test of `cli` end to end (or from its --from restart), with progress to `log`
/// and history.csv, summary.json, fabric.csv and snapshots/ in its --out; `program` names the
/// run in the output folder's lock. With `spread`, the simulation runs over its processes and
/// each writes where it says.
void run_simple_shear(const ShearCommandLine& cli, std::ostream& log, const std::string& program,
                      SpreadRun* spread = nullptr);

}  // namespace dem::cli
