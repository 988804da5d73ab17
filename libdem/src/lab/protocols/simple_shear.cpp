// The NGI simple-shear test, as its method reads: make the specimen in the ring stack, consolidate
// it to the vertical stress, then shear it leg after leg at the rate of the inertial number, a
// history row every output.every_strain. Each stage goes on where a loaded restart file left it.
#include <dem/lab/protocols/simple_shear.hpp>

#include <algorithm>
#include <chrono>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>

namespace dem::lab {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

SimpleShearConfig validated(SimpleShearConfig config) {
  config.validate();
  require(config.shear.total_strain() > 0.0, "shear strain", config.shear.total_strain(), "> 0");
  return config;
}

}  // namespace

std::vector<std::string> SimpleShearTest::run_files() {
  std::vector<std::string> files = ShearOutputs::files();
  for (const char* name : {"summary.json", "restart.restart", "consolidated.restart", "final.restart"}) files.push_back(name);
  return files;
}

SimpleShearTest::SimpleShearTest(SimpleShearConfig config, std::filesystem::path out_dir, std::ostream& log)
    : config_(validated(std::move(config))),
      legs_(config_.shear.legs()),
      run_(std::make_unique<World>(world_settings(config_)), std::move(out_dir), {run_files(), ShearOutputs::files()}, log),
      specimen_(run_, config_),
      outputs_(run_, specimen_, [this] { return legs_.direction(); }) {
  run_.set_restart_every(config_.output.restart_every_steps);
  run_.set_progress_every(config_.output.progress_seconds);
  run_.keep("steps_at_shear_start", steps_at_shear_start_);
  legs_.keep_in(run_, [this] { return specimen_.consolidated_height(); });
}



void SimpleShearTest::generate() {
  run_.claim_if_needed();
  specimen_.generate();
}

void SimpleShearTest::consolidate() {
  run_.claim_if_needed();
  specimen_.consolidate();
  outputs_.next_row_at(0.0);
  outputs_.record(legs_.strain(), true);  // the shear's first row: the consolidated specimen
  run_.save(run_.folder() / "consolidated.restart");
}

void SimpleShearTest::reconsolidate() {
  run_.claim_if_needed();
  specimen_.reconsolidate();
  outputs_.next_row_at(0.0);
  outputs_.record(legs_.strain(), true);
  run_.save(run_.folder() / "consolidated.restart");
}

void SimpleShearTest::load_restart(const std::filesystem::path& file, ResumeIntent intent) {
  specimen_.load(file, intent);
  // The cyclic test leaves the specimen's stage at "consolidated" (it shears it its own way): its
  // files after its consolidated.restart (cyclic_step 0) would pass for a consolidated specimen,
  // with the cycles missing from the history.
  if (const ProtocolRecord& record = run_.loaded_record(); record.has("cyclic_step") && record.number("cyclic_step") != 0)
    throw InputError("restart file " + file.string() + " was written by dem-cyclic-shear (cyclic_step " +
                     std::to_string(static_cast<long long>(record.number("cyclic_step"))) +
                     "): its specimen has been cycled, not only consolidated, and this test cannot go on from it. "
                     "Allowed: --from the consolidated.restart of that folder (the specimen before the cycles), or "
                     "dem-cyclic-shear --from this file (more cycles)");
  run_.log() << "resumed from " << file.string() << " at step " << world().step_count() << ", time step " << world().time_step()
             << " s (" << to_string(specimen_.progress()) << ", shear strain " << legs_.strain() << ")\n";
}

void SimpleShearTest::start_leg(const ShearLeg& leg) {
  start_shear_leg(world(), cell(), *specimen_.servo(), shear_leg_motion(config_, leg.direction_deg, shear_rate(), consolidated_height()));
}

void SimpleShearTest::shear() {
  require(stage() == ShearStage::Consolidated || stage() == ShearStage::Shearing, "shear() stage", static_cast<int>(stage()),
          "2 (consolidated) or 3 (shearing)");
  run_.claim_if_needed();
  const auto t0 = std::chrono::steady_clock::now();
  World& w = world();
  if (stage() == ShearStage::Consolidated) {
    specimen_.cement(CementAfter::Consolidation);  // consolidated.restart, written before, is the plain specimen
    specimen_.set_stage(ShearStage::Shearing);
    steps_at_shear_start_ = w.step_count();
    legs_.start(w, cell(), consolidated_height());
    // The row at zero strain was written after consolidation; the interval is this run's (a
    // specimen consolidated by another run may have used another one).
    outputs_.next_row_at(config_.output.every_strain);
    start_leg(legs_.current());
    run_.log() << "shear: rate " << shear_rate() << " 1/s, inertial number " << inertial_number() << ", "
               << ((config_.shear.mode == ShearMode::ConstantVolume) ? "constant volume" : "drained") << ", "
               << legs_.legs().size() << " leg(s) to " << legs_.total_strain() << "\n";
    if (inertial_number() > 1e-3 * 1.0001) run_.log() << "warning: inertial number above 1e-3: not quasi-static\n";
  }
  const std::int64_t steps_before = w.step_count();
  const auto particles = static_cast<double>(w.particles().size());
  legs_.run(w, cell(), chunk_steps, [this](const ShearLeg& leg) { start_leg(leg); }, [&](double strain, bool done) {
    outputs_.record(strain, done);
    run_.save_if_due();
    std::ostringstream detail;
    detail.precision(4);
    const double elapsed = seconds_since(t0);
    detail << "strain " << strain << " of " << legs_.total_strain() << ", tau " << outputs_.history().last("shear_stress") / 1e3
           << " kPa, sigma_v " << w.wall(cell().top).normal_stress() / 1e3 << " kPa, "
           << static_cast<double>(w.step_count() - steps_before) * particles / std::max(elapsed, 1e-9) << " particle-steps/s";
    run_.progress("shear", detail.str(), strain, legs_.total_strain());
  });
  specimen_.set_stage(ShearStage::Done);
  stop_shear(w, cell());
  run_.add_wall_seconds(seconds_since(t0));
  run_.save(run_.folder() / "final.restart");
  run_.log() << "shear done in " << seconds_since(t0) << " s, " << w.step_count() - steps_at_shear_start_ << " steps\n";
}

void SimpleShearTest::run() {
  if (stage() == ShearStage::Empty) generate();
  if (stage() == ShearStage::Generated) consolidate();
  if (stage() == ShearStage::Consolidated || stage() == ShearStage::Shearing) shear();
}

}  // namespace dem::lab
