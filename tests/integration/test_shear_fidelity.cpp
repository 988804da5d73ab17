// The simple-shear specimen's kinematics and guards on a reduced specimen (30 mm x 12 mm, 4D
// balls: about 170): rings that follow the height between the plates, the generation's friction
// schedule, the history's uniformity columns, and the keys a restart file carries on --from.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <vector>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

#include "support/reduced_specimen.hpp"
#include "support/temp_dir.hpp"

using namespace dem;
using namespace dem::lab;
using Catch::Matchers::Contains;

namespace {

io::Config reduced_specimen() {
  io::Config c = testing::reduced_specimen();
  c.set("shear.target_strain", "0.02");
  c.set("output.every_strain", "0.005");
  c.set("output.fabric_strains", "0");
  c.set("output.snapshot_strains", "0");
  return c;
}

// Each ring's height as a fraction of the plate gap: s_k = (z_k - z_bottom) / H.
std::vector<double> ring_fractions(const SimpleShearTest& test) {
  const World& w = test.world();
  const double z_bottom = w.walls()[0].displacement.z();
  const double z_top = test.config().specimen.height + w.walls()[1].displacement.z();
  std::vector<double> s;
  for (const Clump& ring : w.clumps()) s.push_back((ring.x.z() - z_bottom) / (z_top - z_bottom));
  return s;
}

}  // namespace

TEST_CASE("shear fidelity: following rings keep their height fraction between the plates exactly", "[simple-shear][rings]") {
  dem::testing::TempDir dir("rings_follow");
  io::Config c = reduced_specimen();
  std::ostringstream log;
  SimpleShearTest test(simple_shear_config(c), dir.path, log);
  test.generate();
  const std::vector<double> generated = ring_fractions(test);
  const double height_generated = test.generated_state().height;
  test.consolidate();
  // Consolidation moved the top plate (by some tenths of a millimetre); each ring moved by its
  // fraction of that, so the fractions are unchanged to rounding (1e-12 of a fraction ~ 1e-14 m).
  REQUIRE(std::abs(test.consolidated_height() - height_generated) > 1e-5);
  const std::vector<double> consolidated = ring_fractions(test);
  REQUIRE(consolidated.size() == generated.size());
  for (std::size_t k = 0; k < generated.size(); ++k) CHECK(consolidated[k] == Approx(generated[k]).margin(1e-12));
  CHECK(generated.front() > 0.0);
  CHECK(test.balls_outside() == 0);
}

TEST_CASE("shear fidelity: fixed rings stay at their heights while the plate moves", "[simple-shear][rings]") {
  dem::testing::TempDir dir("rings_fixed");
  io::Config c = reduced_specimen();
  c.set("rings.vertical", "fixed");
  std::ostringstream log;
  SimpleShearTest test(simple_shear_config(c), dir.path, log);
  test.generate();
  std::vector<double> before;
  for (const Clump& ring : test.world().clumps()) before.push_back(ring.x.z());
  test.consolidate();
  for (std::size_t k = 0; k < before.size(); ++k) CHECK(test.world().clumps()[k].x.z() == before[k]);
  // Built 1.1 x the specimen height, with room for dilation above the plate.
  double top = 0.0;
  for (const Clump& ring : test.world().clumps()) top = std::max(top, ring.x.z());
  CHECK(top > c.real("specimen.height"));
}

TEST_CASE("shear fidelity: the servo generation ends near the target porosity at the generation stress", "[simple-shear][generation]") {
  // A cell 2.5 balls high at a porosity near what frictionless spheres pack to in it (0.45):
  // one step of the friction schedule may compact the specimen by more than the tolerance band,
  // past the target and onto the plate's lowest position (specimen.height, where the ball count
  // gives the target porosity), where the plate no longer holds it. Which packings do that depends
  // on their trajectories (measured on seeds 1-8: two of eight), so each of three packings is held
  // to the protocol's promise rather than to one outcome.
  for (const int seed : {1, 2, 3}) {
    dem::testing::TempDir dir("generation_servo");
    io::Config c = reduced_specimen();
    c.set("specimen.seed", std::to_string(seed));
    c.set("specimen.porosity", "0.47");  // looser than frictionless spheres pack in so low a cell (0.45)
    // Each schedule step settles until the plate holds the generation stress (or this many steps).
    c.set("generation.steps_per_stage", "20000");
    std::ostringstream log;
    SimpleShearTest test(simple_shear_config(c), dir.path, log);
    test.generate();
    const SpecimenState& g = test.generated_state();
    INFO("seed " << seed << "\n" << log.str());
    // The plate never sinks below the specimen height, so the porosity is at least the target's
    // (the count is drawn for it: up to one ball off); the schedule stops within the tolerance.
    CHECK(g.porosity >= c.real("specimen.porosity") - 0.005);
    CHECK(g.porosity <= c.real("specimen.porosity") + c.real("generation.porosity_tolerance") + 1e-9);
    CHECK(g.height >= c.real("specimen.height") * (1 - 1e-12));
    // Held by the servo at 5 kPa, within the 10 % its settling asks for; or settled onto the
    // plate's lowest position, below the stress, and said so.
    const bool on_floor = g.height <= c.real("specimen.height") * (1 + 1e-9);
    if (on_floor && g.vertical_stress < 0.9 * 5e3) {
      CHECK_THAT(log.str(), Contains("settled onto the top plate's lowest position"));
    } else {
      CHECK(g.vertical_stress == Approx(5e3).epsilon(0.1));
    }
  }
}

TEST_CASE("shear fidelity: history counts contacts two ways and measures the profile of each interval", "[simple-shear][uniformity]") {
  dem::testing::TempDir dir("uniformity_columns");
  io::Config c = reduced_specimen();
  std::ostringstream log;
  SimpleShearTest test(simple_shear_config(c), dir.path, log);
  test.run();
  const io::CsvData h = io::read_csv(dir.path / "history.csv", io::Missing::Allowed);
  REQUIRE(h.rows.size() >= 4);
  // The row after consolidation starts the first interval: no profile yet.
  CHECK(std::isnan(h.rows.front()[h.column("profile_r2")]));
  for (std::size_t r = 1; r < h.rows.size(); ++r) {
    const auto& row = h.rows[r];
    // Contacts within the detection gap include the touching ones.
    CHECK(row[h.column("contacts_within_detection")] >= row[h.column("contacts")]);
    CHECK(row[h.column("balls_outside")] == 0.0);
    // A profile bounded by the plates: at most 1 (uniform), finite once the bottom plate has moved.
    CHECK(row[h.column("profile_r2")] <= 1.0);
    CHECK(std::isfinite(row[h.column("profile_r2")]));
  }
  // Equal slabs that split every ball exactly between them average to the specimen porosity.
  for (const auto& row : h.rows) {
    double mean = 0;
    for (int b = 1; b <= 12; ++b) mean += row[h.column("profile_porosity_" + std::to_string(b))] / 12;
    CHECK(mean == Approx(row[h.column("specimen_porosity")]).epsilon(1e-12));
  }
  // Bins next to the plates hold no ball centre in a specimen 2.5 balls high (NaN); the lowest
  // bin with balls moves further than the highest, as the bottom plate does.
  const auto& last = h.rows.back();
  std::vector<double> bins;
  for (int b = 1; b <= 12; ++b)
    if (const double u = last[h.column("profile_u_" + std::to_string(b))]; std::isfinite(u)) bins.push_back(u);
  REQUIRE(bins.size() >= 3);
  CHECK(bins.front() > bins.back());
  CHECK_NOTHROW(h.column("ring_1_dx"));
  CHECK_NOTHROW(h.column("non_coaxiality_deg"));
}

TEST_CASE("shear fidelity: keys a restart file carries are applied from the configuration on --from, or refused", "[simple-shear][restart]") {
  dem::testing::TempDir dir("restart_keys");
  io::Config c = reduced_specimen();
  c.set("shear.target_strain", "0.005");
  std::ostringstream log;
  {
    SimpleShearTest test(simple_shear_config(c), dir.path / "specimen", log);
    test.generate();
    test.consolidate();
  }
  const auto restart = dir.path / "specimen" / "consolidated.restart";
  SECTION("engine.local_damping and rings.density are applied") {
    io::Config changed = c;
    changed.set("engine.local_damping", "0.3");
    changed.set("rings.density", "5400");
    SimpleShearTest test(simple_shear_config(changed), dir.path / "applied", log);
    test.load_restart(restart);
    CHECK(test.world().settings().local_damping == 0.3);
    SimpleShearTest reference(simple_shear_config(c), dir.path / "reference", log);
    reference.load_restart(restart);
    for (std::size_t k = 0; k < test.world().clumps().size(); ++k)
      CHECK(test.world().clumps()[k].mass == Approx(2.0 * reference.world().clumps()[k].mass).epsilon(1e-12));
    CHECK_THAT(log.str(), Contains("applied engine.local_damping = 0.3") && Contains("applied rings.density = 5400"));
    test.shear();
  }
  SECTION("a fixed engine.time_step is applied") {
    io::Config changed = c;
    changed.set("engine.time_step", "1e-7");
    SimpleShearTest test(simple_shear_config(changed), dir.path / "dt", log);
    test.load_restart(restart);
    CHECK(test.world().time_step() == 1e-7);
  }
  SECTION("keys that describe the specimen are refused, naming the key") {
    const std::vector<std::pair<std::string, std::string>> refused = {
        {"specimen.density", "2000"}, {"specimen.diameter", "0.031"}, {"specimen.height", "0.013"},
        {"rings.gap", "0.0005"}, {"engine.time_step_safety", "0.5"}};
    for (const auto& [key, value] : refused) {
      io::Config changed = c;
      changed.set(key, value);
      SimpleShearTest test(simple_shear_config(changed), dir.path / ("refused_" + key), log);
      CHECK_THROWS_WITH(test.load_restart(restart), Contains(key));
    }
  }
}
