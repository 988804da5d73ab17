// The history log whose columns the parts register by name (lab/toolkit/history_log.hpp), and the
// uniformity probe's columns (lab/toolkit/uniformity_probe.hpp) on a specimen moved exactly as uniform
// simple shear: free balls (no contacts, no gravity, no damping) whose velocities fall linearly
// from the bottom plate's to zero at the held top plate.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <dem/contact/linear_law.hpp>
#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/uniformity_probe.hpp>

#include "../support/temp_dir.hpp"

using namespace dem;
using namespace dem::lab;
using Catch::Matchers::Contains;

TEST_CASE("history log: columns in the order registered, one measurement per row, the file as the table",
          "[lab][history]") {
  dem::testing::TempDir dir("history_log");
  HistoryLog log(dir.path / "history.csv");
  double now = 0.0;
  int measured = 0;
  log.before_row([&] { ++measured; });
  log.add("time", [&] { return now; });
  log.add({"a", "b"}, [&](std::vector<double>& row) { row.insert(row.end(), {2 * now, 3 * now}); });
  log.add("missing", [] { return std::nan(""); });
  CHECK(log.columns() == std::vector<std::string>{"time", "a", "b", "missing"});
  for (now = 1.0; now <= 3.0; now += 1.0) log.record();
  CHECK(measured == 3);
  CHECK(log.last("b") == 9.0);

  const io::CsvData file = io::read_csv(dir.path / "history.csv", io::Missing::Allowed);
  CHECK(file.columns == log.columns());
  REQUIRE(file.rows.size() == 3);
  CHECK(file.rows[1][1] == 4.0);
  CHECK(std::isnan(file.rows[2][3]));
  CHECK_THROWS_WITH(log.add("late", [] { return 0.0; }), Contains("late") && Contains("after 3 row(s)"));
}

TEST_CASE("history log: bad columns are refused naming them", "[lab][history]") {
  dem::testing::TempDir dir("history_log");
  HistoryLog log(dir.path / "history.csv");
  CHECK_THROWS_WITH(log.record(), Contains("no columns"));
  log.add("time", [] { return 0.0; });
  CHECK_THROWS_WITH(log.add("time", [] { return 1.0; }), Contains("time"));
  CHECK_THROWS_WITH(log.add("a,b", [] { return 1.0; }), Contains("a,b"));
  CHECK(log.columns() == std::vector<std::string>{"time"});
  log.add({"x", "y"}, [](std::vector<double>& row) { row.push_back(1.0); });  // one value short
  CHECK_THROWS_WITH(log.record(), Contains("'x'") && Contains("1 values") && Contains("2, one per column"));
}

TEST_CASE("history log: a resumed log keeps the rows up to the restart point, by column name", "[lab][history]") {
  dem::testing::TempDir dir("history_log");
  {
    io::CsvTable old({"b", "time"});  // another order, and no column "c"
    for (double t = 1; t <= 4; ++t) old.add_row({10 * t, t});
    old.save(dir.path / "old.csv");
  }
  HistoryLog log(dir.path / "history.csv");
  log.add("time", [] { return 5.0; });
  log.add("b", [] { return 50.0; });
  log.add("c", [] { return 7.0; });
  log.resume(dir.path / "old.csv", 2);
  CHECK(log.rows() == 2);
  CHECK(log.table().rows()[1][0] == 2.0);
  CHECK(log.table().rows()[1][1] == 20.0);
  CHECK(std::isnan(log.table().rows()[1][2]));
  log.record();
  const io::CsvData file = io::read_csv(dir.path / "history.csv", io::Missing::Allowed);
  REQUIRE(file.rows.size() == 3);
  CHECK(file.rows[2] == std::vector<double>{5.0, 50.0, 7.0});
  CHECK_THROWS_WITH(log.resume(dir.path / "old.csv", 5), Contains(">= 5"));
}

TEST_CASE("uniformity probe: uniform simple shear gives R^2 = 1 and the plate strain in every third",
          "[lab][history]") {
  dem::testing::TempDir dir("history_log");
  WorldSettings settings;
  settings.time_step = 1e-5;  // s
  settings.local_damping = 0.0;
  World world(settings);
  ShearCellSpec spec;
  spec.diameter = 0.012;
  spec.height = 0.006;
  spec.pebble_diameter = 1.4e-3;
  spec.ring_gap = 0.07e-3;
  const ShearCell cell = build_shear_cell(world, spec);
  const auto law = LinearLaw::Params::deformable(1e7, 1.0, 0.5);
  for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble})
    world.set_contact_model(kind, make_contact_model<LinearLaw>(law, "law"));
  // Small balls well apart and away from the plates and rings: nothing touches.
  const double speed = 0.02, height = spec.height;  // m/s of the bottom plate, m
  for (int k = 0; k < 12; ++k)
    for (int i = -2; i <= 2; ++i)
      for (int j = -2; j <= 2; ++j) {
        const double z = 0.25e-3 + k * 0.5e-3;  // m, two layers per 1 mm bin, none on an edge
        world.add_ball({.position = Vec3(1e-3 * i, 1e-3 * j, z),
                        .radius = 1e-4,
                        .density = 2650.0,
                        .velocity = Vec3(speed * (1 - z / height), 0, 0)});
      }
  world.wall(cell.bottom).velocity = Vec3(speed, 0, 0);

  HistoryLog log(dir.path / "history.csv");
  log.add("time", [&] { return world.time(); });
  UniformityProbe probe(world, cell, 6);
  probe.add_columns(log, [] { return Vec3(1, 0, 0); });
  add_ring_columns(log, world, cell);
  log.record();  // the first row has no profile: it starts the first interval
  const io::CsvTable& t = log.table();
  CHECK(std::isnan(t.rows()[0][t.column_index("profile_r2")]));
  world.step(200);
  log.record();
  const auto& row = t.rows()[1];
  auto at = [&](const std::string& name) { return row[t.column_index(name)]; };
  const double strain = speed * world.time() / height;
  CHECK(at("profile_r2") == Approx(1.0).margin(1e-9));
  for (const char* third : {"strain_bottom_third", "strain_middle_third", "strain_top_third"})
    CHECK(at(third) == Approx(strain).epsilon(1e-9));
  CHECK(at("top_bottom_strain_ratio") == Approx(1.0).epsilon(1e-9));
  CHECK(at("bottom_dx") == Approx(speed * world.time()).epsilon(1e-12));
  CHECK(at("top_dx") == 0.0);
  // Each 1 mm bin holds two of the 12 layers of balls: its mean displacement is that of uniform
  // shear at their mean height, the bin's centre.
  for (int b = 1; b <= 6; ++b) {
    const double z_mean = (b - 0.5) * 1e-3;
    CHECK(at("profile_u_" + std::to_string(b)) == Approx(speed * world.time() * (1 - z_mean / height)).epsilon(1e-9));
  }
  CHECK(at("ring_1_dx") == 0.0);  // the rings are still held: the probe reads, never moves them
  CHECK(t.columns().back() == "ring_" + std::to_string(cell.ring_count) + "_dy");

  // The interval restarts at each row: a third row after a pause has no profile.
  world.wall(cell.bottom).velocity = Vec3::Zero();
  log.record();
  CHECK(std::isnan(t.rows()[2][t.column_index("profile_r2")]));
}
