#include "run_summary.hpp"

namespace dem::lab {

void save_summary(const Run& run, io::Json& j, const std::string& resolved_config_json, double wall_seconds) {
  const World& w = run.world();
  j["steps"] = w.step_count();
  j["wall_clock_s"] = wall_seconds;
  j["particle_steps_per_second"] =
      wall_seconds > 0 ? static_cast<double>(w.step_count()) * static_cast<double>(w.particles().size()) / wall_seconds : 0.0;
  j["threads"] = w.threads();
  j["processes"] = w.ranks();  // MPI ranks the simulation was spread over
  j["time_step_s"] = w.time_step();
  // Where this process's steps spent their time (a resumed run: since it resumed).
  const StepTiming& t = w.step_timing();
  j["step_timing_s"] = {{"rebuilds", t.rebuilds},       {"ball_ball", t.ball_ball},     {"ball_pebble", t.ball_pebble},
                        {"ball_facet", t.ball_facet},   {"force_sums", t.force_sums},   {"controllers", t.controllers},
                        {"integration", t.integration}, {"communication", t.communication}, {"total", t.total()}};
  // A cemented specimen's bonds at the end (a plain run's summary has no such entry).
  if (const BondStore& bonds = w.bonds(); !bonds.empty())
    j["bonds"] = {{"installed", bonds.size()},
                  {"intact", bonds.count(BondStatus::intact)},
                  {"broken_tension", bonds.count(BondStatus::broken_tension)},
                  {"broken_shear", bonds.count(BondStatus::broken_shear)},
                  {"energy_released_J", bonds.released_energy()}};
  j["configuration"] = io::Json::parse(resolved_config_json);
  if (run.loaded()) {
    // Which run this one continues, and from where: its rows up to that step came from there.
    j["continued_from"] = {{"restart_file", run.loaded_file().string()}, {"step", run.loaded_step()}};
    io::Json changed;
    for (const auto& [key, before, after] : run.changes()) {
      io::Json c;
      c["restart_file"] = before;
      c["this_run"] = after;
      changed[key] = c;
    }
    j["resume_changed_keys"] = changed;
  }
  io::save_json(run.folder() / "summary.json", j);
}

}  // namespace dem::lab
