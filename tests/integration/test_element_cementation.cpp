// Cementation in the element-test app (docs/cementation.md): bonds installed on the compressed
// specimen before the loading, counted in history.csv; the same consolidated specimen loaded plain
// and cemented; a cemented run killed mid-loading resumes to the same history; bad keys refused
// by name, value and range.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>

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
  const fs::path dir = fs::temp_directory_path() / ("libdem_cemented_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

io::Config cemented_keys() {
  io::Config keys(element_test_schema());
  keys.set("element.test", "triaxial-drained");
  keys.set("element.balls", "200");
  keys.set("element.target_strain", "0.01");
  keys.set("element.every_strain", "0.001");
  keys.set("output.restart_every_steps", "10");
  keys.set("engine.threads", "1");
  keys.set("cementation.after", "consolidation");
  keys.set("cementation.gap_ratio", "0.02");
  keys.set("cementation.radius_multiplier", "0.5");
  keys.set("cementation.normal_stiffness", "2e10");
  keys.set("cementation.shear_stiffness", "1e10");
  keys.set("cementation.tensile_strength", "3e5");
  keys.set("cementation.tensile_strength_std", "1e5");
  keys.set("cementation.cohesion", "4e5");
  keys.set("cementation.cohesion_std", "1e5");
  keys.set("cementation.friction_angle", "30");
  return keys;
}

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

}  // namespace

TEST_CASE("element test: a cemented specimen counts its bonds, and resumes", "[element-test][periodic][bond]") {
  const io::Config keys = cemented_keys();
  const fs::path whole = fresh_dir("whole");
  run_to_end(keys, whole);
  const io::CsvData rows = io::read_csv(whole / "history.csv");
  REQUIRE(rows.rows.size() >= 10);
  const auto at = [&](std::size_t r, const char* name) { return rows.rows[r][rows.column(name)]; };
  CHECK(at(0, "bonds_intact") == 0.0);  // the consolidated row, before the bonds
  const double made = at(1, "bonds_intact") + at(1, "bonds_broken_tension") + at(1, "bonds_broken_shear");
  INFO(made << " bonds, at the end " << at(rows.rows.size() - 1, "bonds_intact") << " intact");
  CHECK(made > 100.0);  // most of the compressed specimen's contacts
  const std::size_t last = rows.rows.size() - 1;
  CHECK(at(last, "bonds_intact") + at(last, "bonds_broken_tension") + at(last, "bonds_broken_shear") == made);
  // summary.json: the bonds at the end, as the last row counts them.
  const auto summary = testing::load_json(whole / "summary.json");
  CHECK(summary["bonds"]["installed"].get<double>() == made);
  CHECK(summary["bonds"]["intact"].get<double>() == at(last, "bonds_intact"));
  CHECK(summary["bonds"]["broken_shear"].get<double>() == at(last, "bonds_broken_shear"));
  CHECK(summary["bonds"]["energy_released_J"].get<double>() == Approx(at(last, "bond_energy_released_J")).epsilon(1e-12));
  // broken_bonds.vtp: a point for each broken bond, with the test's strain it broke at.
  const double broken = at(last, "bonds_broken_tension") + at(last, "bonds_broken_shear");
  REQUIRE(broken > 0.0);
  const std::string vtp = testing::file_text(whole / "broken_bonds.vtp");
  CHECK_THAT(vtp, Contains("NumberOfPoints=\"" + std::to_string(static_cast<int>(broken)) + "\"") &&
                      Contains("test_strain_broken") && Contains("energy_released_J"));
  CHECK_THAT(testing::file_text(whole / "manifest.json"), Contains("broken_bonds.vtp"));

  // The same consolidated specimen loaded without cement: no bond columns, another curve.
  io::Config plain = keys;
  plain.set("cementation.after", "none");
  const fs::path uncemented = fresh_dir("plain");
  run_to_end(plain, uncemented, whole / "consolidated.restart");
  const io::CsvData plain_rows = io::read_csv(uncemented / "history.csv");
  CHECK(std::find(plain_rows.columns.begin(), plain_rows.columns.end(), "bonds_intact") == plain_rows.columns.end());
  CHECK_FALSE(testing::load_json(uncemented / "summary.json").contains("bonds"));
  CHECK(plain_rows.rows.back()[plain_rows.column("deviator_stress")] != rows.rows.back()[rows.column("deviator_stress")]);

  // Killed mid-loading, resumed from restart.restart: the same history byte for byte.
  const auto middle = static_cast<std::int64_t>(at(rows.rows.size() / 2, "step"));
  const fs::path killed = fresh_dir("killed");
  CHECK_THROWS_WITH(run_to_end(keys, killed, {}, middle + 3), Contains("stopped"));
  run_to_end(keys, killed, killed / "restart.restart");
  CHECK(testing::file_text(killed / "history.csv") == testing::file_text(whole / "history.csv"));
  CHECK(testing::file_text(killed / "broken_bonds.vtp") == vtp);
}

TEST_CASE("element test: bad cementation keys are refused by key, value and range", "[element-test][bond]") {
  io::Config keys(element_test_schema());
  CHECK_THROWS_WITH(keys.set("cementation.after", "curing"), Contains("cementation.after"));
  CHECK_THROWS_WITH(keys.set("cementation.friction_angle", "95"), Contains("cementation.friction_angle"));
  CHECK_THROWS_WITH(keys.set("cementation.normal_stiffness", "0"), Contains("cementation.normal_stiffness"));
  CHECK_THROWS_WITH(keys.set("cementation.tensile_strength", "-1"), Contains("cementation.tensile_strength"));
  CHECK_THROWS_WITH(keys.set("cementation.radius_multiplier", "1.5"), Contains("cementation.radius_multiplier"));
}
