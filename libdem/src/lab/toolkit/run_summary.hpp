// Private to the library: the part of summary.json every protocol's run writes the same way.
#pragma once

#include <string>

#include <dem/lab/toolkit/run.hpp>

#include "../../io/json_file.hpp"

namespace dem::lab {

/// Appends the run's part to a protocol's summary `document` (steps, wall clock and pace, threads
/// and processes, time step, where the steps spent their time, the resolved configuration, and
/// for a run from a restart file that file and its step, and the keys the resume changed), then
/// writes it to the run's summary.json atomically.
/// `wall_seconds`: the seconds the protocol counts as its run (the Run's own, unless a protocol
/// built on another counts only its part).
void save_summary(const Run& run, io::Json& document, const std::string& resolved_config_json, double wall_seconds);

}  // namespace dem::lab
