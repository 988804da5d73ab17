// The cyclic simple-shear test on the reduced specimen (30 mm x 12 mm, 4D balls: about 170,
// consolidated to 200 kPa): the stress servo holds its amplitude, a circular path keeps |tau|
// while it turns, constant volume holds the height, r_u is the vertical stress drop, the strain
// path is followed exactly, and each stop criterion ends the run at the first row that meets it.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/cyclic_shear.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

#include "support/reduced_specimen.hpp"
#include "support/temp_dir.hpp"

using namespace dem;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace dem::lab;

namespace {

struct Consolidated {
  dem::testing::TempDir dir;
  std::ostringstream log;
  SimpleShearTest specimen;
  explicit Consolidated(const std::string& name)
      : dir(name), specimen(simple_shear_config(dem::testing::reduced_specimen()), dir.path, log) {
    specimen.open_outputs({.more_run_files = CyclicShearTest::run_files()});
    specimen.generate();
    specimen.consolidate();
  }
};

// The rows of the cyclic stage, with the column of `name`.
struct Rows {
  const io::CsvTable& table;
  std::vector<std::size_t> cyclic;
  explicit Rows(const io::CsvTable& t) : table(t) {
    for (std::size_t r = 0; r < t.rows().size(); ++r)
      if (t.rows()[r][t.column_index("phase")] == 1.0) cyclic.push_back(r);
  }
  double at(std::size_t r, const std::string& name) const { return table.rows()[r][table.column_index(name)]; }
};

}  // namespace

TEST_CASE("cyclic shear: a stress-controlled sine at constant volume holds its amplitude and the height", "[cyclic][integration]") {
  Consolidated run("cyclic_sine");
  CyclicShearConfig c;
  c.csr = 0.1;
  c.max_cycles = 3;
  c.snapshot_cycles = {3.0, 1.0};
  c.fabric_cycles = {2.0};
  CyclicShearTest test(run.specimen.resumable_run(), run.specimen.specimen(), c);
  test.run();
  const double sigma_v0 = test.outcome().vertical_stress_initial, amplitude = c.csr * sigma_v0;
  CHECK(sigma_v0 == Approx(200e3).epsilon(0.01));  // the consolidation's tolerance
  // Peaks of every complete cycle within 2 % of the amplitude (the servo lags the target by a few
  // degrees, so the peak falls between rows: 40 rows a cycle sample it within cos(4.5 deg)).
  REQUIRE(test.cycles().cycles().size() == 3);
  for (const CycleRow& r : test.cycles().cycles()) {
    CHECK(r.complete);
    CHECK(r.stress_max == Approx(amplitude).epsilon(0.02));
    CHECK(-r.stress_min == Approx(amplitude).epsilon(0.02));
    CHECK(r.energy > 0.0);  // a hysteresis loop takes work
  }
  const Rows rows(test.history());
  const double h_c = test.outcome().consolidated_height;
  for (std::size_t r = 0; r < test.history().rows().size(); ++r) {
    CHECK(std::abs(rows.at(r, "height") - h_c) <= 1e-6 * h_c);
    // r_u from the plate stress, row by row: (sigma_v0 - sigma_v) / sigma_v0.
    CHECK(rows.at(r, "pore_pressure_ratio") == Approx((sigma_v0 - rows.at(r, "vertical_stress")) / sigma_v0).margin(1e-12));
  }
  CHECK(test.outcome().stop == "cycles");
  CHECK(test.outcome().cycles == 3.0);
  // The outputs are on disk, complete.
  CHECK(io::read_csv(run.dir.path / "cycles.csv").rows.size() == 3);
  CHECK(io::read_csv(run.dir.path / "cyclic_history.csv", io::Missing::Allowed).rows.size() == test.history().rows().size());
  // Snapshots and fabric at the chosen cycles, in order whatever order they were given in.
  const std::string index = dem::testing::file_text(run.dir.path / "cyclic_snapshots" / "snapshots.csv");
  CHECK(index.find("cycle_1,") != std::string::npos);
  CHECK(index.find("cycle_3,") != std::string::npos);
  CHECK(index.find("cycle_1,") < index.find("cycle_3,"));
  CHECK(std::filesystem::exists(run.dir.path / "cyclic_snapshots" / "balls_cycle_3.vtp"));
  CHECK(dem::testing::file_text(run.dir.path / "cyclic_fabric.csv").find("cycle_2,") != std::string::npos);
}

TEST_CASE("cyclic shear: a circular stress path keeps |tau| while its direction turns once per cycle", "[cyclic][integration]") {
  Consolidated run("cyclic_circle");
  CyclicShearConfig c;
  c.path = CyclicShape::Circle;
  c.csr = 0.1;
  c.max_cycles = 3;
  CyclicShearTest test(run.specimen.resumable_run(), run.specimen.specimen(), c);
  test.run();
  const double amplitude = c.csr * test.outcome().vertical_stress_initial;
  const Rows rows(test.history());
  double turned = 0.0;
  Vec3 previous = Vec3::Zero();
  for (std::size_t r : rows.cyclic) {
    const double n = rows.at(r, "cycles");
    if (n < 1.0) continue;  // the ramp and the first turn
    const Vec3 tau(rows.at(r, "shear_stress_x"), rows.at(r, "shear_stress_y"), 0.0);
    CHECK(tau.norm() == Approx(amplitude).epsilon(0.03));
    if (previous.norm() > 0) turned += std::atan2(previous.cross(tau).z(), previous.dot(tau));
    previous = tau;
  }
  // From N = 1 to N = 3: two turns, clockwise seen from above (from e towards d).
  CHECK(turned * 180 / pi == Approx(-720.0).margin(5.0));
}

TEST_CASE("cyclic shear: strain control follows the path exactly; drained holds the vertical stress", "[cyclic][integration]") {
  Consolidated run("cyclic_strain");
  CyclicShearConfig c;
  c.control = CyclicControl::Strain;
  c.drainage = CyclicDrainage::Drained;
  c.strain_amplitude = 0.004;
  c.direction_deg = 90.0;
  c.max_cycles = 2;
  CyclicShearTest test(run.specimen.resumable_run(), run.specimen.specimen(), c);
  test.run();
  const Rows rows(test.history());
  double trapezoid = 0.0;
  for (std::size_t k = 0; k < rows.cyclic.size(); ++k) {
    const std::size_t r = rows.cyclic[k];
    const double n = rows.at(r, "cycles");
    CHECK(rows.at(r, "shear_strain_y") == Approx(0.004 * std::sin(2 * pi * n)).margin(1e-12));
    CHECK(std::abs(rows.at(r, "shear_strain_x")) < 1e-12);
    if (k > 0) {  // the loop's area by the rows, beside the per-step sum of the history
      const std::size_t p = rows.cyclic[k - 1];
      trapezoid += 0.5 * (rows.at(r, "shear_stress_y") + rows.at(p, "shear_stress_y")) *
                   (rows.at(r, "shear_strain_y") - rows.at(p, "shear_strain_y"));
    }
  }
  const double work = rows.at(rows.cyclic.back(), "work");
  CHECK(work > 0.0);
  CHECK(work == Approx(trapezoid).epsilon(0.1));  // 40 rows a cycle resolve the loop to a few per cent
  // The vertical servo keeps sigma_v at the consolidation stress within its tolerance on average.
  double mean = 0.0;
  for (std::size_t r : rows.cyclic) mean += rows.at(r, "vertical_stress") / static_cast<double>(rows.cyclic.size());
  CHECK(mean == Approx(200e3).epsilon(0.02));
}

TEST_CASE("cyclic shear: each stop criterion ends the run at the first row that meets it", "[cyclic][integration]") {
  Consolidated run("cyclic_stop");
  run.specimen.save_restart(run.dir.path / "start.restart");
  for (const char* criterion : {"pore pressure ratio", "double-amplitude strain"}) {
    DYNAMIC_SECTION(criterion) {
      dem::testing::TempDir other(std::string("cyclic_stop_") + (criterion[0] == 'p' ? "ru" : "da"));
      std::ostringstream log;
      SimpleShearTest specimen(simple_shear_config(dem::testing::reduced_specimen()), other.path, log);
      specimen.load_restart(run.dir.path / "start.restart");
      CyclicShearConfig c;
      c.csr = 0.15;
      c.max_cycles = 10;
      const bool by_ru = criterion[0] == 'p';
      c.ru_limit = by_ru ? 0.03 : 0.0;
      c.da_strain_limit = by_ru ? 0.0 : 0.012;
      CyclicShearTest test(specimen.resumable_run(), specimen.specimen(), c);
      test.run();
      CHECK(test.outcome().stop == criterion);
      const Rows rows(test.history());
      const std::string column = by_ru ? "pore_pressure_ratio" : "double_amplitude_strain";
      const double limit = by_ru ? c.ru_limit : c.da_strain_limit;
      REQUIRE(rows.cyclic.size() >= 2);
      CHECK(rows.at(rows.cyclic.back(), column) >= limit);
      for (std::size_t k = 0; k + 1 < rows.cyclic.size(); ++k) CHECK(rows.at(rows.cyclic[k], column) < limit);
      const double n = by_ru ? test.outcome().cycles_to_ru : test.outcome().cycles_to_da_strain;
      CHECK(n == rows.at(rows.cyclic.back(), "cycles"));
      CHECK(n < 10.0);
    }
  }
}

TEST_CASE("cyclic shear: a static shear stress is held under the cycles, and the post-cyclic shear adds its strain", "[cyclic][integration]") {
  Consolidated run("cyclic_static_post");
  CyclicShearConfig c;
  c.static_csr = 0.05;
  c.static_direction_deg = 90.0;  // across the cycles' direction
  c.csr = 0.05;
  c.max_cycles = 1;
  c.post_strain = 0.01;
  c.post_direction_deg = 0.0;
  CyclicShearTest test(run.specimen.resumable_run(), run.specimen.specimen(), c);
  test.run();
  const double sigma_v0 = test.outcome().vertical_stress_initial, held = c.static_csr * sigma_v0;
  const Rows rows(test.history());
  // Through the cycles the stress across them stays at the static value (the servo holds the
  // vector sum of both), and along them it swings by the cyclic amplitude.
  for (std::size_t r : rows.cyclic) {
    CHECK(rows.at(r, "shear_stress_y") == Approx(held).margin(0.05 * held + 0.02 * c.csr * sigma_v0));
    CHECK(rows.at(r, "target_y") == Approx(held).epsilon(1e-12));
  }
  // The post-cyclic rows: strain-controlled along +x by post_strain from where the cycles ended.
  std::vector<std::size_t> post;
  for (std::size_t r = 0; r < test.history().rows().size(); ++r)
    if (rows.at(r, "phase") == 2.0) post.push_back(r);
  REQUIRE(!post.empty());
  const double start_x = rows.at(rows.cyclic.back(), "shear_strain_x"), start_y = rows.at(rows.cyclic.back(), "shear_strain_y");
  CHECK(rows.at(post.back(), "shear_strain_x") - start_x == Approx(0.01).margin(0.001));
  CHECK(rows.at(post.back(), "shear_strain_y") == Approx(start_y).margin(1e-12));
}

TEST_CASE("cyclic shear: a strain series from CSV is followed and ends the stage at its last row", "[cyclic][integration]") {
  Consolidated run("cyclic_series");
  CyclicShearConfig c;
  c.control = CyclicControl::Strain;
  c.path = CyclicShape::Series;
  c.series_file = run.dir.write("path.csv", "cycle,x,y\n0,0,0\n0.5,0.002,0\n1.5,0.002,0.003\n").string();
  c.max_cycles = 10;
  check_cyclic_inputs(c);
  CyclicShearTest test(run.specimen.resumable_run(), run.specimen.specimen(), c);
  test.run();
  CHECK(test.outcome().stop == "series end");
  CHECK(test.outcome().cycles == 1.5);
  const Rows rows(test.history());
  for (std::size_t r : rows.cyclic) {
    const double n = rows.at(r, "cycles");
    const double x = n <= 0.5 ? 0.004 * n : 0.002, y = n <= 0.5 ? 0.0 : 0.003 * (n - 0.5);
    CHECK(rows.at(r, "shear_strain_x") == Approx(x).margin(1e-12));
    CHECK(rows.at(r, "shear_strain_y") == Approx(y).margin(1e-12));
  }
  c.series_file = (run.dir.path / "missing.csv").string();
  CHECK_THROWS_AS(check_cyclic_inputs(c), InputError);
}

TEST_CASE("cyclic shear: a run stopped in any stage resumes from its restart file to the uninterrupted run's files",
          "[cyclic][integration][resume]") {
  Consolidated base("cyclic_resume");
  const auto specimen = [] {
    io::Config keys = dem::testing::reduced_specimen();
    keys.set("output.restart_every_steps", "150");
    return simple_shear_config(keys);
  };
  CyclicShearConfig c;
  c.static_csr = 0.05;
  c.csr = 0.1;
  c.max_cycles = 2;
  c.rows_per_cycle = 20;
  c.post_strain = 0.012;  // three rows of output.every_strain
  c.snapshot_cycles = {1.0};
  c.fabric_cycles = {1.0, 2.0};
  const auto run_to_end = [&](const fs::path& dir, const fs::path& from, std::int64_t stop_at_step) {
    std::ostringstream log;
    CyclicShearTest test(specimen(), c, dir, log);
    if (stop_at_step > 0)  // a kill at that step, as far as the files can tell
      test.world().add_controller([stop_at_step](World& w) {
        if (w.step_count() == stop_at_step) throw std::runtime_error("stopped");
      });
    test.load_restart(from);
    test.open_outputs();
    test.run();
    test.write_summary("{}");
  };
  const fs::path consolidated = base.dir.path / "consolidated.restart";
  const dem::testing::TempDir whole("cyclic_resume_whole");
  run_to_end(whole.path, consolidated, 0);
  const io::CsvData rows = io::read_csv(whole.path / "cyclic_history.csv", io::Missing::Allowed);
  {
    // The specimen's stage stays "consolidated" through the cycles: a monotonic test must not take
    // the cycled specimen for a consolidated one (the specimen it started from it may).
    std::ostringstream log;
    SimpleShearTest monotonic(specimen(), whole.path / "monotonic", log);
    CHECK_THROWS_WITH(monotonic.load_restart(whole.path / "final.restart"),
                      Contains("written by dem-cyclic-shear") && Contains("consolidated.restart"));
    CHECK_FALSE(fs::exists(whole.path / "monotonic"));
    SimpleShearTest before_cycles(specimen(), whole.path / "monotonic", log);
    CHECK_NOTHROW(before_cycles.load_restart(consolidated));
  }
  // A step in the middle of each stage: static, cyclic, post-cyclic.
  for (const double phase : {0.0, 1.0, 2.0}) {
    std::vector<double> steps;
    for (const auto& r : rows.rows)
      if (r[rows.column("phase")] == phase) steps.push_back(r[rows.column("step")]);
    REQUIRE(steps.size() >= 3);
    const auto stop = static_cast<std::int64_t>(steps[steps.size() / 2]) + 7;
    DYNAMIC_SECTION("stopped at step " << stop << " of phase " << phase) {
      const dem::testing::TempDir dir("cyclic_resume_" + std::to_string(static_cast<int>(phase)));
      CHECK_THROWS_WITH(run_to_end(dir.path, consolidated, stop), Contains("stopped"));
      REQUIRE(fs::exists(dir.path / "restart.restart"));
      run_to_end(dir.path, dir.path / "restart.restart", 0);
      for (const char* file : {"cyclic_history.csv", "cycles.csv", "cyclic_fabric.csv", "history.csv", "fabric.csv",
                               "cyclic_snapshots/snapshots.csv", "cyclic_snapshots/balls.pvd"})
        CHECK(dem::testing::file_text(dir.path / file) == dem::testing::file_text(whole.path / file));
      CHECK(!dem::testing::file_text(dir.path / "cyclic_history.csv").empty());
    }
  }
}

TEST_CASE("cyclic shear: a plain consolidated specimen cemented for the cycles counts its bonds and resumes after a kill",
          "[cyclic][integration][resume][bond]") {
  Consolidated base("cyclic_cemented");  // plain: its consolidated.restart has no bonds
  const auto specimen = [] {
    io::Config keys = dem::testing::reduced_specimen();
    keys.set("output.restart_every_steps", "400");
    keys.set("cementation.after", "consolidation");
    keys.set("cementation.tensile_strength", "2e5");  // Pa: weak, most break within the first cycle
    keys.set("cementation.cohesion", "2e5");
    return simple_shear_config(keys);
  };
  CyclicShearConfig c;
  c.control = CyclicControl::Strain;
  c.strain_amplitude = 0.01;
  c.max_cycles = 1;
  c.rows_per_cycle = 20;
  c.snapshot_cycles = {1.0};
  std::size_t bonds = 0;
  std::string log_text;
  const auto run_to_end = [&](const fs::path& dir, const fs::path& from, std::int64_t stop_at_step) {
    std::ostringstream log;
    CyclicShearTest test(specimen(), c, dir, log);
    if (stop_at_step > 0)
      test.world().add_controller([stop_at_step](World& w) {
        if (w.step_count() == stop_at_step) throw std::runtime_error("stopped");
      });
    test.load_restart(from);
    test.open_outputs();
    try {
      test.run();
    } catch (...) {
      log_text = log.str();
      throw;
    }
    log_text = log.str();
    bonds = test.world().bonds().size();
  };
  const dem::testing::TempDir whole("cyclic_cemented_whole");
  run_to_end(whole.path, base.dir.path / "consolidated.restart", 0);
  CHECK_THAT(log_text, Contains("cemented at step"));
  const std::size_t made = bonds;
  CHECK(made > 100);
  const io::CsvData rows = io::read_csv(whole.path / "cyclic_history.csv", io::Missing::Allowed);
  const auto& last = rows.rows.back();
  const double broken = last[rows.column("bonds_broken_tension")] + last[rows.column("bonds_broken_shear")];
  CHECK(last[rows.column("bonds_intact")] + broken == static_cast<double>(made));
  CHECK(broken > 0.0);
  CHECK(last[rows.column("bond_energy_released_J")] > 0.0);
  CHECK(fs::exists(whole.path / "cyclic_snapshots" / "broken_bonds_cycle_1.vtp"));
  // Killed in the middle of the cycle, resumed from its restart file: the same files, the bonds
  // installed once.
  std::vector<double> steps;
  for (const auto& r : rows.rows)
    if (r[rows.column("phase")] == 1.0) steps.push_back(r[rows.column("step")]);
  REQUIRE(steps.size() >= 3);
  const auto stop = static_cast<std::int64_t>(steps[steps.size() / 2]) + 7;
  const dem::testing::TempDir dir("cyclic_cemented_killed");
  CHECK_THROWS_WITH(run_to_end(dir.path, base.dir.path / "consolidated.restart", stop), Contains("stopped"));
  REQUIRE(fs::exists(dir.path / "restart.restart"));
  run_to_end(dir.path, dir.path / "restart.restart", 0);
  CHECK_THAT(log_text, !Contains("cemented at step"));
  CHECK(bonds == made);
  for (const char* file : {"cyclic_history.csv", "cycles.csv", "cyclic_snapshots/snapshots.csv", "cyclic_snapshots/broken_bonds_cycle_1.vtp"})
    CHECK(dem::testing::file_text(dir.path / file) == dem::testing::file_text(whole.path / file));
}
