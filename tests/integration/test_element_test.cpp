// Element tests in a periodic cell (lab/protocols/element_test.hpp) on a small specimen of the 4D
// material: the isotropic compression ends at the target with equal principal stresses, a drained
// triaxial path holds sigma_3, the constant-volume paths keep the cell's volume, a run killed in
// either stage resumes to the same history byte for byte, a cyclic simple shear follows its
// strain or stress path at constant volume, and bad keys are refused by name.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/element_test.hpp>

#include "support/json.hpp"
#include "support/reduced_specimen.hpp"

using namespace dem;
using namespace dem::lab;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("libdem_element_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

io::Config small_keys(const std::string& test) {
  io::Config keys(element_test_schema());
  keys.set("element.test", test);
  keys.set("element.balls", "200");
  keys.set("element.target_strain", "0.01");
  keys.set("element.every_strain", "0.001");
  // A restart file after every chunk of steps: a resume then starts from a chunk that wrote a row.
  keys.set("output.restart_every_steps", "10");
  keys.set("engine.threads", "1");
  return keys;
}

// Runs the test in `dir` (from `from` if given); a controller throws at `stop_at_step` (> 0), as a
// kill there would, as far as the files can tell.
void run_to_end(const io::Config& keys, const fs::path& dir, const fs::path& from = {}, std::int64_t stop_at_step = 0) {
  std::ostringstream log;
  ElementTest test(element_test_config(keys), dir, log);
  test.record_configuration(keys);
  if (stop_at_step > 0)
    test.world().add_controller([stop_at_step](World& w) {
      if (w.step_count() == stop_at_step) throw std::runtime_error("stopped");
    });
  if (!from.empty()) test.load_restart(from);
  test.run();
  test.write_summary(keys.to_json());
}

// The compression-positive cell stress of a history row (Pa).
Mat3 row_stress(const io::CsvData& rows, std::size_t k) {
  const auto& r = rows.rows[k];
  const auto at = [&](const char* name) { return r[rows.column(name)]; };
  Mat3 s;
  s << at("cell_stress_xx"), at("cell_stress_xy"), at("cell_stress_xz"), at("cell_stress_xy"), at("cell_stress_yy"), at("cell_stress_yz"),
      at("cell_stress_xz"), at("cell_stress_yz"), at("cell_stress_zz");
  return s;
}

}  // namespace

TEST_CASE("element test: the isotropic compression ends at the target with equal principal stresses", "[element-test][periodic]") {
  const io::Config keys = small_keys("isotropic");
  const fs::path dir = fresh_dir("isotropic");
  run_to_end(keys, dir);
  const io::CsvData rows = io::read_csv(dir / "history.csv");
  REQUIRE(rows.rows.size() >= 10);  // a row every 0.001 of volumetric strain, checked every 100 steps
  const Eigen::SelfAdjointEigenSolver<Mat3> principal(row_stress(rows, rows.rows.size() - 1));
  INFO("principal stresses " << principal.eigenvalues().transpose() << " Pa");
  for (int a = 0; a < 3; ++a) CHECK(std::abs(principal.eigenvalues()[a] - 100e3) <= 0.01 * 100e3);
  CHECK(rows.rows.back()[rows.column("mean_stress")] == Approx(100e3).epsilon(0.005));
  CHECK(rows.rows.back()[rows.column("volumetric_strain")] > 0.3);  // from the gas
  const auto summary = testing::load_json(dir / "summary.json");
  CHECK(summary["final"]["void_ratio"].get<double>() < 0.7);
  CHECK(summary["final"]["coordination"].get<double>() > 4.0);

  // Killed in the compression just after a row, resumed from restart.restart: the same history.
  const auto row_step = static_cast<std::int64_t>(rows.rows[rows.rows.size() / 2][rows.column("step")]);
  const fs::path resumed = fresh_dir("isotropic_resumed");
  CHECK_THROWS_WITH(run_to_end(keys, resumed, {}, row_step + 3), Contains("stopped"));
  run_to_end(keys, resumed, resumed / "restart.restart");
  CHECK(testing::file_text(resumed / "history.csv") == testing::file_text(dir / "history.csv"));
}

TEST_CASE("element test: constant-p holds the mean stress, and extension lengthens zz at the confining stress",
          "[element-test][periodic]") {
  // One compressed specimen, loaded from its consolidated.restart along each path.
  const io::Config keys = small_keys("triaxial-drained");
  const fs::path made = fresh_dir("paths_made");
  run_to_end(keys, made);
  const auto loaded = [&](const std::string& key, const std::string& value, const std::string& name) {
    io::Config path = keys;
    path.set(key, value);
    const fs::path dir = fresh_dir(name);
    run_to_end(path, dir, made / "consolidated.restart");
    return io::read_csv(dir / "history.csv");
  };
  SECTION("constant p: sigma_xx = sigma_yy = (3 p0 - sigma_zz) / 2 while q rises") {
    const io::CsvData rows = loaded("element.drained_path", "constant-p", "paths_p");
    REQUIRE(rows.rows.size() >= 10);
    for (std::size_t k = 0; k < rows.rows.size(); ++k) {
      INFO("row " << k);
      CHECK(std::abs(rows.rows[k][rows.column("mean_stress")] - 100e3) <= 0.01 * 100e3);
      CHECK(rows.rows[k][rows.column("cell_stress_xx")] == Approx(rows.rows[k][rows.column("cell_stress_yy")]).epsilon(0.01));
    }
    CHECK(rows.rows.back()[rows.column("deviator_stress")] > 0.3 * 100e3);
    CHECK(rows.rows.back()[rows.column("cell_stress_xx")] < 0.9 * 100e3);  // the lateral stress fell
  }
  SECTION("extension: the axial strain and q negative, the lateral stresses held") {
    const io::CsvData rows = loaded("element.direction", "extension", "paths_extension");
    REQUIRE(rows.rows.size() >= 10);
    for (std::size_t k = 0; k < rows.rows.size(); ++k) {
      INFO("row " << k);
      CHECK(std::abs(rows.rows[k][rows.column("cell_stress_xx")] - 100e3) <= 0.01 * 100e3);
      CHECK(std::abs(rows.rows[k][rows.column("cell_stress_yy")] - 100e3) <= 0.01 * 100e3);
    }
    CHECK(rows.rows.back()[rows.column("axial_strain")] <= -0.01);
    CHECK(rows.rows.back()[rows.column("deviator_stress")] < -0.2 * 100e3);
  }
}

TEST_CASE("element test: a drained triaxial path holds sigma_3 while the axial strain runs, and resumes in each stage",
          "[element-test][periodic][resume]") {
  const io::Config keys = small_keys("triaxial-drained");
  const fs::path whole = fresh_dir("triaxial_whole");
  run_to_end(keys, whole);
  const io::CsvData rows = io::read_csv(whole / "history.csv");
  REQUIRE(rows.rows.size() >= 10);
  for (std::size_t k = 0; k < rows.rows.size(); ++k) {
    const auto& r = rows.rows[k];
    INFO("row " << k);
    CHECK(std::abs(r[rows.column("cell_stress_xx")] - 100e3) <= 0.01 * 100e3);
    CHECK(std::abs(r[rows.column("cell_stress_yy")] - 100e3) <= 0.01 * 100e3);
    const Mat3 s = row_stress(rows, k);
    CHECK(r[rows.column("deviator_stress")] == Approx(s(2, 2) - 0.5 * (s(0, 0) + s(1, 1))).margin(1e-6));
  }
  CHECK(rows.rows.back()[rows.column("axial_strain")] >= 0.01);
  CHECK(rows.rows.back()[rows.column("deviator_stress")] > 0.3 * 100e3);
  const auto summary = testing::load_json(whole / "summary.json");
  CHECK(summary["peak"]["stress_ratio"].get<double>() > 0.3);

  // Killed in the compression and in the loading, resumed from restart.restart: the same history.
  const auto loading_start = static_cast<std::int64_t>(rows.rows.front()[rows.column("step")]);
  const auto loading_middle = static_cast<std::int64_t>(rows.rows[rows.rows.size() / 2][rows.column("step")]);
  for (const std::int64_t stop : {loading_start / 2 + 3, loading_middle + 3}) {
    DYNAMIC_SECTION("stopped at step " << stop) {
      const fs::path dir = fresh_dir("triaxial_" + std::to_string(stop));
      CHECK_THROWS_WITH(run_to_end(keys, dir, {}, stop), Contains("stopped"));
      REQUIRE(fs::exists(dir / "restart.restart"));
      run_to_end(keys, dir, dir / "restart.restart");
      CHECK(testing::file_text(dir / "history.csv") == testing::file_text(whole / "history.csv"));
    }
  }
  // The confining stress is fixed once the compression has begun; the target strain is not.
  io::Config other = keys;
  other.set("element.confining_stress", "2e5");
  std::ostringstream log;
  ElementTest refused(element_test_config(other), fresh_dir("triaxial_refused"), log);
  refused.record_configuration(other);
  CHECK_THROWS_WITH(refused.load_restart(whole / "consolidated.restart"), Contains("element.confining_stress = 2e+05 here, 1e+05 in the file"));
  io::Config longer = keys;
  longer.set("element.target_strain", "0.02");
  ElementTest allowed(element_test_config(longer), fresh_dir("triaxial_longer"), log);
  allowed.record_configuration(longer);
  CHECK_NOTHROW(allowed.load_restart(whole / "consolidated.restart"));

  // The compressed specimen loaded along another path: the same first row, then constant volume.
  io::Config undrained = keys;
  undrained.set("element.test", "triaxial-undrained");
  const fs::path second = fresh_dir("triaxial_second_path");
  run_to_end(undrained, second, whole / "consolidated.restart");
  const io::CsvData second_rows = io::read_csv(second / "history.csv");
  REQUIRE(second_rows.rows.size() >= 10);
  CHECK(second_rows.rows.front() == rows.rows.front());
  CHECK(std::abs(second_rows.rows.back()[second_rows.column("volumetric_strain")]) <= 1e-9);
  CHECK(second_rows.rows.back()[second_rows.column("axial_strain")] >= 0.01);
  // Mid-compression the isotropic test's rows are under way: its path is refused there.
  io::Config isotropic = keys;
  isotropic.set("element.test", "isotropic");
  const fs::path killed = fresh_dir("triaxial_killed_compressing");
  CHECK_THROWS_WITH(run_to_end(keys, killed, {}, loading_start / 2 + 3), Contains("stopped"));
  ElementTest mid(element_test_config(isotropic), fresh_dir("triaxial_to_isotropic"), log);
  mid.record_configuration(isotropic);
  CHECK_THROWS_WITH(mid.load_restart(killed / "restart.restart"), Contains("element.test") && Contains("isotropic here, triaxial-drained in the file"));
}

TEST_CASE("element test: the constant-volume paths keep the cell's volume to 1e-9", "[element-test][periodic]") {
  for (const char* test : {"triaxial-undrained", "simple-shear-undrained"}) {
    DYNAMIC_SECTION(test) {
      const fs::path dir = fresh_dir(test);
      io::Config keys = small_keys(test);
      std::ostringstream log;
      ElementTest run(element_test_config(keys), dir, log);
      run.record_configuration(keys);
      run.run();
      const io::CsvData rows = io::read_csv(dir / "history.csv", io::Missing::Allowed);  // profile_r2 of the first row
      REQUIRE(rows.rows.size() >= 10);
      for (const auto& r : rows.rows) CHECK(std::abs(r[rows.column("volumetric_strain")]) <= 1e-9);
      const std::string strain = std::string(test) == "triaxial-undrained" ? "axial_strain" : "shear_strain";
      CHECK(rows.rows.back()[rows.column(strain)] >= 0.01);
      if (strain == "axial_strain") CHECK(std::abs(rows.rows.back()[rows.column("mean_stress")] - 100e3) > 1e3);  // p moves
      else CHECK(rows.rows.back()[rows.column("shear_stress")] > 0.1 * 100e3);  // resisting the shear
      if (strain == "shear_strain") {
        // The profile's start is kept in the restart files: killed mid-shear and resumed, the
        // same history, profile_r2 included.
        CHECK(rows.rows.back()[rows.column("profile_r2")] > 0.5);
        const auto middle = static_cast<std::int64_t>(rows.rows[rows.rows.size() / 2][rows.column("step")]);
        const fs::path resumed = fresh_dir(std::string(test) + "_resumed");
        CHECK_THROWS_WITH(run_to_end(keys, resumed, {}, middle + 3), Contains("stopped"));
        run_to_end(keys, resumed, resumed / "restart.restart");
        CHECK(testing::file_text(resumed / "history.csv") == testing::file_text(dir / "history.csv"));
      }
    }
  }
}

// A cyclic simple shear of 200 balls: rows of history.csv, loading rows only (stage 1).
io::CsvData cyclic_rows(const io::Config& keys, const fs::path& dir) {
  run_to_end(keys, dir);
  io::CsvData rows = io::read_csv(dir / "history.csv");
  REQUIRE(rows.rows.size() >= 40);
  return rows;
}

io::Config cyclic_keys(const std::string& control, const std::string& path) {
  io::Config keys = small_keys("cyclic-simple-shear");
  keys.set("element.cyclic_control", control);
  keys.set("element.cyclic_path", path);
  keys.set("element.cycles", "1");
  keys.set("element.strain_amplitude", "0.002");
  keys.set("element.csr", "0.05");
  return keys;
}

TEST_CASE("element test: a drained cyclic shear follows its strain path at the confining stress; a series ends at its last row",
          "[element-test][periodic]") {
  const double amplitude = 0.002;
  io::Config keys = cyclic_keys("strain", "sine");
  keys.set("element.cyclic_drainage", "drained");
  const fs::path drained = fresh_dir("cyclic_drained");
  const io::CsvData rows = cyclic_rows(keys, drained);
  double height_change = 0.0;
  for (const auto& r : rows.rows) {
    const double cycles = r[rows.column("cycles")];
    INFO("cycles " << cycles);
    // F_zz moves with the servo: the rate of each step is set from where F_xz is, not where it should be.
    CHECK(std::abs(r[rows.column("shear_strain")] - amplitude * std::sin(2.0 * std::numbers::pi * cycles)) <= 1e-6 * amplitude);
    CHECK(std::abs(r[rows.column("cell_stress_zz")] - 100e3) <= 0.01 * 100e3);
    height_change = std::max(height_change, std::abs(r[rows.column("axial_strain")]));
  }
  CHECK(height_change > 1e-6);  // drained: the height follows the stress, unlike the constant-volume path

  // A series (cycle, x, y): F_xz, F_yz linear between its rows, from the same compressed specimen.
  const fs::path series = fresh_dir("cyclic_series") / "path.csv";
  fs::create_directories(series.parent_path());
  std::ofstream(series) << "cycle,x,y\n0,0,0\n0.5,0.002,0.001\n1.5,-0.002,0\n";
  io::Config along = cyclic_keys("strain", "series");
  along.set("element.cyclic_series_file", series.string());
  along.set("element.cycles", "5");  // the series is shorter: it ends the test
  const fs::path dir = series.parent_path() / "run";
  run_to_end(along, dir, drained / "consolidated.restart");
  const io::CsvData path = io::read_csv(dir / "history.csv");
  for (const auto& r : path.rows) {
    const double n = r[path.column("cycles")];
    if (r[path.column("stage")] != 1.0) continue;
    INFO("cycles " << n);
    const double x = n <= 0.5 ? 0.004 * n : 0.002 - 0.004 * (n - 0.5), y = n <= 0.5 ? 0.002 * n : 0.001 - 0.001 * (n - 0.5);
    CHECK(std::abs(r[path.column("shear_strain")] - std::clamp(x, -0.002, 0.002)) <= 1e-9);
    CHECK(std::abs(r[path.column("shear_strain_yz")] - std::max(y, 0.0)) <= 1e-9);
  }
  CHECK(path.rows.back()[path.column("cycles")] == Approx(1.5).margin(0.03));

  io::Config missing = cyclic_keys("strain", "series");
  CHECK_THROWS_WITH(element_test_config(missing), Contains("element.cyclic_series_file") && Contains("cyclic_path = series"));
}

TEST_CASE("element test: a strain-controlled cyclic simple shear follows its path at constant volume and resumes exactly",
          "[element-test][periodic][resume]") {
  const double amplitude = 0.002;
  const io::Config keys = cyclic_keys("strain", "sine");
  const fs::path whole = fresh_dir("cyclic_sine");
  const io::CsvData rows = cyclic_rows(keys, whole);
  double largest = 0.0, smallest = 0.0;
  for (const auto& r : rows.rows) {
    const double cycles = r[rows.column("cycles")], strain = r[rows.column("shear_strain")];
    INFO("cycles " << cycles);
    // The path a sin(2 pi N), met at every row (the rate of each step lands the strain on it).
    CHECK(std::abs(strain - amplitude * std::sin(2.0 * std::numbers::pi * cycles)) <= 1e-6 * amplitude);
    CHECK(std::abs(r[rows.column("shear_strain_yz")]) <= 1e-12);
    CHECK(std::abs(r[rows.column("volumetric_strain")]) <= 1e-9);  // every normal rate zero
    largest = std::max(largest, strain), smallest = std::min(smallest, strain);
  }
  // Rows every 1/40 cycle, two of them at the peaks: the amplitude within 2 % either way.
  CHECK(std::abs(largest - amplitude) <= 0.02 * amplitude);
  CHECK(std::abs(smallest + amplitude) <= 0.02 * amplitude);
  CHECK(rows.rows.back()[rows.column("cycles")] >= 1.0);
  // The packing resists: positive shear stress at the first peak, negative at the second.
  const auto at_cycles = [&](double n) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < rows.rows.size(); ++k)
      if (std::abs(rows.rows[k][rows.column("cycles")] - n) < std::abs(rows.rows[best][rows.column("cycles")] - n)) best = k;
    return rows.rows[best][rows.column("shear_stress")];
  };
  CHECK(at_cycles(0.25) > 0.02 * 100e3);
  CHECK(at_cycles(0.75) < -0.02 * 100e3);

  // Killed in the middle of the cycle, resumed from restart.restart: the same history.
  const auto middle = static_cast<std::int64_t>(rows.rows[rows.rows.size() / 2][rows.column("step")]);
  const fs::path dir = fresh_dir("cyclic_sine_resumed");
  CHECK_THROWS_WITH(run_to_end(keys, dir, {}, middle + 3), Contains("stopped"));
  run_to_end(keys, dir, dir / "restart.restart");
  CHECK(testing::file_text(dir / "history.csv") == testing::file_text(whole / "history.csv"));
}

TEST_CASE("element test: a circular strain path keeps its radius, a stress-controlled cycle its amplitude", "[element-test][periodic]") {
  SECTION("strain, circle") {
    const double amplitude = 0.002;
    const io::CsvData rows = cyclic_rows(cyclic_keys("strain", "circle"), fresh_dir("cyclic_circle"));
    int counted = 0;
    for (const auto& r : rows.rows) {
      const double cycles = r[rows.column("cycles")];
      CHECK(std::abs(r[rows.column("volumetric_strain")]) <= 1e-9);
      if (cycles < 0.25) continue;  // the path's ramp
      const double radius = std::hypot(r[rows.column("shear_strain")], r[rows.column("shear_strain_yz")]);
      INFO("cycles " << cycles);
      CHECK(std::abs(radius - amplitude) <= 0.02 * amplitude);
      ++counted;
    }
    CHECK(counted >= 30);
  }
  SECTION("stress, sine") {
    const double amplitude = 0.05 * 100e3;  // Pa, csr x confining stress
    const io::CsvData rows = cyclic_rows(cyclic_keys("stress", "sine"), fresh_dir("cyclic_stress"));
    double largest = 0.0, smallest = 0.0;
    for (const auto& r : rows.rows) {
      CHECK(std::abs(r[rows.column("volumetric_strain")]) <= 1e-9);
      if (r[rows.column("stage")] < 1) continue;
      largest = std::max(largest, r[rows.column("shear_stress")]);
      smallest = std::min(smallest, r[rows.column("shear_stress")]);
    }
    CHECK(std::abs(largest - amplitude) <= 0.02 * amplitude);
    CHECK(std::abs(smallest + amplitude) <= 0.02 * amplitude);
  }
}

TEST_CASE("element test: bad keys are refused, naming the key", "[element-test]") {
  io::Config keys(element_test_schema());
  CHECK_THROWS_WITH(keys.set("element.test", "cyclic"), Contains("element.test") && Contains("triaxial-drained"));
  CHECK_THROWS_WITH(keys.set("element.confining_stress", "-5"), Contains("element.confining_stress"));
  CHECK_THROWS_WITH(keys.set("element.balls", "1"), Contains("element.balls"));
  CHECK_THROWS_WITH(keys.set("element.target_strain", "0.8"), Contains("element.target_strain"));
  CHECK_THROWS_WITH(keys.set("element.inertial_number", "0"), Contains("element.inertial_number"));
  CHECK_THROWS_WITH(keys.set("element.initial_solid_fraction", "0.6"), Contains("element.initial_solid_fraction"));
  CHECK_THROWS_WITH(keys.set("element.bogus", "1"), Contains("element.bogus"));
  CHECK_THROWS_WITH(keys.set("element.cyclic_path", "square"), Contains("element.cyclic_path") && Contains("series"));
  CHECK_THROWS_WITH(keys.set("element.cyclic_drainage", "partial"), Contains("element.cyclic_drainage") && Contains("drained"));
  CHECK_THROWS_WITH(keys.set("element.direction", "sideways"), Contains("element.direction") && Contains("extension"));
  CHECK_THROWS_WITH(keys.set("element.cyclic_control", "speed"), Contains("element.cyclic_control") && Contains("strain"));
  CHECK_THROWS_WITH(keys.set("element.strain_amplitude", "0.8"), Contains("element.strain_amplitude"));
  CHECK_THROWS_WITH(keys.set("element.csr", "0"), Contains("element.csr"));
  CHECK_THROWS_WITH(keys.set("element.rows_per_cycle", "2"), Contains("element.rows_per_cycle"));
  keys.set("grading.d_min", "0.002");
  CHECK_THROWS_WITH(element_test_config(keys), Contains("grading.d_min"));
}
