// Output writers of the simple-shear app: JSON summaries, the fabric CSV and the snapshot files.
// The worlds are hand-built pairs of fixed balls with a chosen overlap and normal direction, so
// every contact, its bin in each rose plane and its force kn * overlap are known in advance.
#include <catch2/catch.hpp>


#include <cmath>
#include <complex>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/fabric_log.hpp>
#include <dem/lab/toolkit/snapshots.hpp>

#include "support/scenes.hpp"

#include "support/temp_dir.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

using dem::testing::TempDir;

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The integer in attribute `name="..."` of the first tag that has it.
long attribute(const std::string& xml, const std::string& name) {
  const auto at = xml.find(name + "=\"");
  if (at == std::string::npos) return -1;
  return std::stol(xml.substr(at + name.size() + 2));
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

constexpr double kn = 1.0e5;  // N/m, constant normal stiffness of every contact
constexpr double deg = pi / 180.0;

// One contact: two fixed balls of radius `radius` around `centre`, along `direction`, overlapping
// by `overlap`. Pairs are 5 mm apart, ten radii: no ball touches another pair.
struct Pair {
  Vec3 direction;              // unit, ball 1 -> ball 2
  double overlap;              // m
  Vec3 centre = Vec3::Zero();  // m, contact point (set by add_pairs)
};

std::vector<Pair> known_pairs() {
  const auto unit = [](double x, double y, double z) { return Vec3(x, y, z).normalized(); };
  // Angles (degrees) in the x-z plane atan2(z, x) and the x-y plane atan2(y, x), folded to [0, 180):
  return {
      {unit(std::cos(5 * deg), 0, std::sin(5 * deg)), 1e-5},    // xz 5 (bin 0), xy 0 (bin 0)
      {unit(1, std::tan(25 * deg), std::tan(65 * deg)), 2e-5},  // xz 65 (bin 6), xy 25 (bin 2)
      {unit(-1, 1, std::tan(85 * deg)), 3e-5},                  // xz 95 (bin 9), xy 135 (bin 13)
      {unit(1, -1, -std::tan(85 * deg)), 5e-5},                 // the reverse: same bins after folding
      {unit(0, 1, 0), 4e-6},  // xz: no angle (skipped); xy: 90, on the edge of bins 8 and 9
  };
}

void set_linear_models(World& world) {
  const auto params = LinearParams::constant(kn, kn, 0.5);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<LinearLaw>(params, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<LinearLaw>(params, "ball-facet"));
  world.set_contact_model(ContactKind::BallPebble, make_contact_model<LinearLaw>(params, "ball-pebble"));
}

BallSpec fixed_ball(const Vec3& x) {
  BallSpec b = ball_at(x);
  b.fixed = dof_all;
  return b;
}

// Adds the pairs (filling in their centres) and returns the ids of their balls in pair order.
std::vector<ParticleId> add_pairs(World& world, std::vector<Pair>& pairs) {
  std::vector<ParticleId> ids;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    Pair& p = pairs[k];
    p.centre = Vec3(5e-3 * static_cast<double>(k), 0, 0);
    const double half = radius - 0.5 * p.overlap;  // m, centre to contact point
    ids.push_back(world.add_ball(fixed_ball(p.centre - half * p.direction)));
    ids.push_back(world.add_ball(fixed_ball(p.centre + half * p.direction)));
  }
  return ids;
}

World pairs_world(std::vector<Pair>& pairs) {
  World world(dynamic_settings(1e-7));
  add_pairs(world, pairs);
  set_linear_models(world);
  world.step(1);
  return world;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// JSON
// ------------------------------------------------------------------------------------------------

TEST_CASE("fabric log: rows hold the known bins, forces and totals of hand-built contacts", "[outputs]") {
  TempDir dir("fabric");
  std::vector<Pair> pairs = known_pairs();
  World world = pairs_world(pairs);
  REQUIRE(world.contact_count(ContactKind::BallBall) == pairs.size());

  lab::FabricLog log(dir.path / "fabric.csv");
  log.record(world, "consolidated", 0.0);
  log.record(world, "shear_20", 0.2);
  CHECK(log.states() == 2);

  const auto lines = lines_of(dir.path / "fabric.csv");
  REQUIRE(lines.size() == 1 + 2 * 2 * 18);
  CHECK(lines[0] ==
        "label,shear_strain,plane,bin_lo_deg,bin_hi_deg,contact_count,contact_fraction,mean_normal_force_N,"
        "a,theta_a_deg,f0_N,a_n,theta_n_deg,a_direct,theta_a_direct_deg,contacts_total,mean_force_all_N");

  // Forces kn * overlap: positions are exact to ~1e-19 m against overlaps >= 4e-6 m.
  const auto force = [&](std::size_t k) { return kn * pairs[k].overlap; };
  const double mean_all = (force(0) + force(1) + force(2) + force(3) + force(4)) / 5.0;
  struct Expected {
    long count;
    double mean_force;
  };
  std::vector<Expected> xz(18, {0, 0.0}), xy(18, {0, 0.0});
  xz[0] = {1, force(0)};
  xz[6] = {1, force(1)};
  xz[9] = {2, 0.5 * (force(2) + force(3))};
  xy[0] = {1, force(0)};
  xy[2] = {1, force(1)};
  xy[13] = {2, 0.5 * (force(2) + force(3))};

  // Bin-free anisotropy of the x-z angles 5, 65, 95, 95 degrees (docs/model.md 9.2).
  std::complex<double> sum = 0.0;
  for (const double theta : {5.0, 65.0, 95.0, 95.0}) sum += std::polar(1.0, 2.0 * theta * deg);
  const double a_direct_xz = 2.0 * std::abs(sum) / 4.0;
  const double theta_direct_xz = std::fmod(0.5 * std::arg(sum) / deg + 180.0, 180.0);

  for (std::size_t row = 1; row < lines.size(); ++row) {
    INFO(lines[row]);
    const auto c = cells_of(lines[row]);
    REQUIRE(c.size() == 17);
    const std::size_t state = (row - 1) / 36, plane = (row - 1) / 18 % 2, bin = (row - 1) % 18;
    CHECK(c[0] == (state == 0 ? "consolidated" : "shear_20"));
    CHECK(std::stod(c[1]) == (state == 0 ? 0.0 : 0.2));
    CHECK(c[2] == (plane == 0 ? "xz" : "xy"));
    CHECK(std::stod(c[3]) == Approx(10.0 * static_cast<double>(bin)).margin(1e-9));
    CHECK(std::stod(c[4]) == Approx(10.0 * static_cast<double>(bin + 1)).margin(1e-9));
    CHECK(std::stol(c[15]) == 5);
    CHECK(std::stod(c[16]) == Approx(mean_all).epsilon(1e-9));
    if (plane == 0) {
      CHECK(std::stol(c[5]) == xz[bin].count);
      CHECK(std::stod(c[6]) == Approx(static_cast<double>(xz[bin].count) / 4.0).epsilon(1e-12));
      CHECK(std::stod(c[7]) == Approx(xz[bin].mean_force).epsilon(1e-9));
      CHECK(std::stod(c[13]) == Approx(a_direct_xz).epsilon(1e-9));
      CHECK(std::stod(c[14]) == Approx(theta_direct_xz).epsilon(1e-9));
    } else if (bin == 8 || bin == 9) {
      CHECK(std::stol(c[5]) <= 1);  // the contact at exactly 90 degrees sits in one of them
    } else {
      CHECK(std::stol(c[5]) == xy[bin].count);
      CHECK(std::stod(c[7]) == Approx(xy[bin].mean_force).epsilon(1e-9));
    }
  }
  // Bins 8 and 9 of the x-y rose together hold the y-normal contact with its force.
  const auto& roses = log.last_roses();
  REQUIRE(roses.size() == 2);
  CHECK(roses[0].plane == measure::RosePlane::ShearXZ);
  CHECK(roses[0].contacts_skipped == 1);
  CHECK(roses[1].plane == measure::RosePlane::HorizontalXY);
  CHECK(roses[1].count[8] + roses[1].count[9] == 1);
  CHECK(roses[1].mean_normal_force[8] + roses[1].mean_normal_force[9] == Approx(force(4)).epsilon(1e-9));
  // The Fourier columns are those of the roses.
  const auto first_xy = cells_of(lines[1 + 36 + 18]);
  CHECK(std::stod(first_xy[8]) == roses[1].a);
  CHECK(std::stod(first_xy[10]) == roses[1].f0);
  CHECK(std::stod(first_xy[11]) == roses[1].a_n);
}

TEST_CASE("fabric log: a state without contacts leaves the fits empty, bad input is refused", "[outputs]") {
  TempDir dir("fabric_empty");
  World world(dynamic_settings(1e-7));
  world.add_ball(fixed_ball(Vec3::Zero()));
  set_linear_models(world);
  world.step(1);
  lab::FabricLog log(dir.path / "fabric.csv");
  log.record(world, "start", 0.0);
  const auto c = cells_of(lines_of(dir.path / "fabric.csv").at(1));
  REQUIRE(c.size() == 17);
  CHECK(c[5] == "0");
  CHECK(c[8].empty());   // a
  CHECK(c[10].empty());  // f0
  CHECK(c[15] == "0");
  CHECK(c[16].empty());  // mean force over no contacts

  CHECK_THROWS_WITH(log.record(world, "a,b", 0.0), Contains("label") && Contains("a,b"));
  CHECK_THROWS_AS(log.record(world, "", 0.0), InputError);
  CHECK_THROWS_WITH(log.record(world, "ok", std::nan("")), Contains("shear_strain"));
  CHECK(log.states() == 1);
  CHECK_THROWS_WITH(lab::FabricLog(dir.path / "f.csv", 7.0), Contains("bin_width_deg"));
}

TEST_CASE("fabric log: resume keeps the first states of an earlier run", "[outputs]") {
  TempDir dir("fabric_resume");
  std::vector<Pair> pairs = known_pairs();
  World world = pairs_world(pairs);
  {
    lab::FabricLog log(dir.path / "fabric.csv");
    for (const char* label : {"s0", "s1", "s2"}) log.record(world, label, 0.1);
  }
  lab::FabricLog resumed(dir.path / "fabric.csv");
  CHECK_THROWS_WITH(resumed.resume(4), Contains("3 complete states"));
  resumed.resume(1);
  CHECK(resumed.states() == 1);
  CHECK(lines_of(dir.path / "fabric.csv").size() == 1 + 36);
  resumed.record(world, "s1b", 0.2);
  const auto lines = lines_of(dir.path / "fabric.csv");
  REQUIRE(lines.size() == 1 + 72);
  CHECK(cells_of(lines[36])[0] == "s0");
  CHECK(cells_of(lines[37])[0] == "s1b");
  CHECK_THROWS_WITH(lab::FabricLog(dir.path / "fabric.csv", 20.0).resume(1), Contains("20 degrees wide"));
}

// ------------------------------------------------------------------------------------------------
// Snapshots
// ------------------------------------------------------------------------------------------------

namespace {

// Known pairs, plus: a ball on a floor wall, a ball on a pebble of a fixed two-pebble clump, and
// a free ball without contacts (`loner`), which the test moves between snapshots.
struct SnapshotScene {
  std::vector<Pair> pairs = known_pairs();
  World world{dynamic_settings(1e-7)};
  ParticleId loner = -1;

  SnapshotScene() {
    loner = world.add_ball(fixed_ball(Vec3(30e-3, 10e-3, 0)));  // added first: re-sorting moves it
    add_pairs(world, pairs);
    world.add_wall(floor_wall(-10e-3, 2e-3));
    world.add_ball(fixed_ball(Vec3(0, 0, -10e-3 + radius - 1e-5)));
    ClumpSpec ring;
    ring.pebbles = {{Vec3(0, 10e-3, 0), radius}, {Vec3(0, 10e-3 + 1.5 * radius, 0), radius}};
    ring.with_pebble_mass(density);
    ring.fixed = dof_all;
    world.add_clump(ring);
    world.add_ball(fixed_ball(Vec3(0, 10e-3 - 2 * radius + 1e-5, 0)));
    set_linear_models(world);
    world.step(1);
  }
};

}  // namespace

TEST_CASE("snapshots: files hold the known balls, contacts, walls and pebbles", "[outputs]") {
  TempDir dir("snap");
  SnapshotScene scene;
  World& world = scene.world;
  REQUIRE(world.contact_count(ContactKind::BallFacet) == 1);   // the scene is what it claims:
  REQUIRE(world.contact_count(ContactKind::BallPebble) == 1);  // these two must not be written
  const fs::path out = dir.path / "snapshots";
  lab::SnapshotWriter writer(out);
  writer.write(world, "consolidated", 0.5, 0.0);

  // Balls: 10 in pairs + loner + wall ball + pebble ball, sorted by id; nothing moved yet.
  const std::size_t balls = 13;
  const io::CsvData b = io::read_csv(out / "balls_consolidated.csv");
  CHECK(b.columns == std::vector<std::string>{"id", "x", "y", "z", "radius", "ux", "uy", "uz", "vx", "vy", "vz"});
  REQUIRE(b.rows.size() == balls);
  for (std::size_t r = 0; r < balls; ++r) {
    const auto id = static_cast<ParticleId>(b.rows[r][0]);
    const std::size_t i = world.particles().index_of(id);
    CHECK(Vec3(b.rows[r][1], b.rows[r][2], b.rows[r][3]) == world.particles().x[i]);
    CHECK(b.rows[r][4] == radius);
    for (std::size_t k = 5; k < 11; ++k) CHECK(b.rows[r][k] == 0.0);
    if (r > 0) CHECK(b.rows[r][0] > b.rows[r - 1][0]);
  }

  // Contacts: ball-ball only, F_n = kn * overlap, at the pair's contact point, force on ball 2
  // along the normal from ball 1 to ball 2 (no tangential motion, no damping).
  const io::CsvData c = io::read_csv(out / "contacts_consolidated.csv");
  REQUIRE(c.rows.size() == scene.pairs.size());
  std::vector<int> seen(scene.pairs.size(), 0);
  for (const auto& row : c.rows) {
    const auto k = static_cast<std::size_t>(std::lround(row[c.column("cx")] / 5e-3));
    REQUIRE(k < scene.pairs.size());
    ++seen[k];
    const Pair& p = scene.pairs[k];
    const Vec3 x1(row[0], row[1], row[2]), x2(row[3], row[4], row[5]), point(row[6], row[7], row[8]);
    const Vec3 f(row[10], row[11], row[12]);
    CHECK((point - p.centre).norm() < 1e-12);  // m; rounding of 1e-3 m coordinates is ~1e-19 m
    CHECK((x2 - x1).norm() == Approx(2 * radius - p.overlap).epsilon(1e-12));
    CHECK(row[9] == Approx(kn * p.overlap).epsilon(1e-9));
    CHECK((f - row[9] * (x2 - x1).normalized()).norm() < 1e-9 * row[9]);
  }
  CHECK(seen == std::vector<int>(scene.pairs.size(), 1));

  // VTK files: counts in their headers, data arrays named as documented.
  const std::string balls_vtp = slurp(out / "balls_consolidated.vtp");
  CHECK(attribute(balls_vtp, "NumberOfPoints") == static_cast<long>(balls));
  for (const char* name : {"\"radius\"", "\"id\"", "\"velocity\"", "\"displacement\""})
    CHECK(Contains(name).match(balls_vtp));
  const std::string contacts_vtp = slurp(out / "contacts_consolidated.vtp");
  CHECK(attribute(contacts_vtp, "NumberOfPoints") == 10);
  CHECK(attribute(contacts_vtp, "NumberOfLines") == 5);
  CHECK(Contains("\"normal_force\"").match(contacts_vtp));
  CHECK(Contains("\"force_magnitude\"").match(contacts_vtp));
  const std::string walls_vtp = slurp(out / "walls_consolidated.vtp");
  CHECK(attribute(walls_vtp, "NumberOfPoints") == 4);  // the floor rectangle
  CHECK(attribute(walls_vtp, "NumberOfPolys") == 2);
  CHECK(Contains("Name=\"wall\"").match(walls_vtp));
  CHECK(occurrences(walls_vtp, "<DataArray") == occurrences(walls_vtp, "</DataArray>"));
  const std::string pebbles_vtp = slurp(out / "pebbles_consolidated.vtp");
  CHECK(attribute(pebbles_vtp, "NumberOfPoints") == 2);
  CHECK(Contains("\"clump\"").match(pebbles_vtp));

  const auto index = lines_of(out / "snapshots.csv");
  REQUIRE(index.size() == 2);
  CHECK(index[0] == "label,time_s,shear_strain,balls,contacts");
  CHECK(index[1] == "consolidated,0.5,0,13,5");
}

TEST_CASE("snapshots: displacements follow ball ids across re-sorting, pvd lists the series", "[outputs]") {
  TempDir dir("snap_move");
  SnapshotScene scene;
  World& world = scene.world;
  const fs::path out = dir.path / "snapshots";
  lab::SnapshotWriter writer(out);
  writer.write(world, "a", 0.5, 0.0);

  // Past the scene's lowest corner on every axis: the loner's cell comes first in any order of
  // the cells, where before it came after the balls below and beside it.
  const Vec3 offset(-60e-3, -30e-3, -30e-3);  // m
  const std::size_t before = world.particles().index_of(scene.loner);
  world.particles().x[before] += offset;
  world.rebuild_now(true);
  REQUIRE(before != 0);
  REQUIRE(world.particles().index_of(scene.loner) == 0);  // storage really was re-sorted
  world.step(1);
  writer.write(world, "b", 0.75, 0.2);
  CHECK(writer.snapshots() == 2);

  const io::CsvData b = io::read_csv(out / "balls_b.csv");
  REQUIRE(b.rows.size() == 13);
  for (const auto& row : b.rows) {
    const Vec3 u(row[5], row[6], row[7]);
    if (static_cast<ParticleId>(row[0]) == scene.loner)
      CHECK((u - offset).norm() < 1e-12 * offset.norm());  // (x + o) - x: rounding ~1e-18 m
    else
      CHECK(u == Vec3::Zero());  // fixed balls do not move at all
  }

  for (const char* kind : {"balls", "contacts", "walls", "pebbles"}) {
    const std::string pvd = slurp(out / (std::string(kind) + ".pvd"));
    CHECK(occurrences(pvd, "<DataSet") == 2);
    CHECK(Contains("timestep=\"0.5\" group=\"\" part=\"0\" file=\"" + std::string(kind) + "_a.vtp\"").match(pvd));
    CHECK(Contains("timestep=\"0.75\" group=\"\" part=\"0\" file=\"" + std::string(kind) + "_b.vtp\"").match(pvd));
  }
  CHECK(lines_of(out / "snapshots.csv").back() == "b,0.75,0.20000000000000001,13,5");

  // A resumed run keeps "a", forgets "b" and measures the next displacement from "a".
  lab::SnapshotWriter resumed(out);
  CHECK_THROWS_WITH(resumed.resume(3), Contains("lists 2 snapshots"));
  resumed.resume(1);
  CHECK(resumed.snapshots() == 1);
  CHECK_FALSE(fs::exists(out / "balls_b.vtp"));
  CHECK_FALSE(fs::exists(out / "contacts_b.csv"));
  CHECK(occurrences(slurp(out / "walls.pvd"), "<DataSet") == 1);
  world.particles().x[world.particles().index_of(scene.loner)] += offset;
  world.step(1);
  resumed.write(world, "c", 1.0, 0.4);
  for (const auto& row : io::read_csv(out / "balls_c.csv").rows)
    if (static_cast<ParticleId>(row[0]) == scene.loner)
      CHECK((Vec3(row[5], row[6], row[7]) - 2 * offset).norm() < 1e-12 * offset.norm());
  CHECK(lines_of(out / "snapshots.csv").size() == 3);
}

TEST_CASE("snapshots: bad labels, repeated labels and time going back are refused", "[outputs]") {
  TempDir dir("snap_bad");
  std::vector<Pair> pairs = known_pairs();
  World world = pairs_world(pairs);
  lab::SnapshotWriter writer(dir.path);
  for (const std::string label : {"", "a b", "../up", "x/y", "a,b", "tab\t", "caf\xc3\xa9"}) {
    INFO(label);
    CHECK_THROWS_WITH(writer.write(world, label, 0.0, 0.0), Contains("snapshot label"));
  }
  CHECK(fs::is_empty(dir.path));  // refused before writing anything
  writer.write(world, "gamma_0.20-ok", 1.0, 0.2);
  CHECK_THROWS_WITH(writer.write(world, "gamma_0.20-ok", 2.0, 0.2), Contains("earlier snapshot"));
  CHECK_THROWS_WITH(writer.write(world, "later", 0.5, 0.2), Contains("previous snapshot's time"));
  CHECK_THROWS_WITH(writer.write(world, "later", 2.0, std::nan("")), Contains("shear_strain"));
  CHECK(writer.snapshots() == 1);
  CHECK_THROWS_AS(lab::SnapshotWriter(""), InputError);
}
