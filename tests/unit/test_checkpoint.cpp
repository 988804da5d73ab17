// Restart files: a run resumed from a checkpoint continues bit for bit; damaged files are refused.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <dem/io/checkpoint.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

void set_models(World& world) {
  auto p = RollingLinearLaw::Params::deformable(modulus_ball, 1.0, 0.5, 0.2);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(p, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(p, "ball-facet"));
}

World falling_pile() {
  WorldSettings s;
  s.gravity = Vec3(0, 0, -2000.0);
  s.sort_every = 3;  // re-sorting in the run must not break resuming
  World world(s);
  for (auto b : separated_balls(200, 4e-3, 0.25e-3, 0.4e-3, 8)) {
    b.position.z() += 0.5e-3;
    world.add_ball(b);
  }
  world.add_wall(floor_wall(0.0, 0.01));
  set_models(world);
  return world;
}

fs::path temp_file(const std::string& name) { return fs::temp_directory_path() / ("libdem_test_" + name); }

}  // namespace

TEST_CASE("checkpoint: a resumed run equals the uninterrupted one bit for bit", "[checkpoint]") {
  World world = falling_pile();
  world.step(3000);
  const fs::path file = temp_file("resume.ckpt");
  io::save_checkpoint(file, world, "stage=consolidation");
  world.step(2000);

  World resumed(WorldSettings{});
  set_models(resumed);
  CHECK(io::load_checkpoint(file, resumed) == "stage=consolidation");
  resumed.step(2000);
  REQUIRE(resumed.particles().size() == world.particles().size());
  CHECK(resumed.step_count() == world.step_count());
  CHECK(resumed.time() == world.time());
  CHECK(resumed.particles().x == world.particles().x);  // exact equality of every coordinate
  CHECK(resumed.particles().w == world.particles().w);
  CHECK(world.contact_count(ContactKind::BallBall) > 50);
  fs::remove(file);
}

TEST_CASE("checkpoint: truncated, corrupted and mismatched files are refused clearly", "[checkpoint]") {
  World world = falling_pile();
  world.step(200);
  const fs::path file = temp_file("damaged.ckpt");
  io::save_checkpoint(file, world, "");
  const auto size = fs::file_size(file);

  World target(WorldSettings{});
  set_models(target);
  fs::resize_file(file, size - 100);
  CHECK_THROWS_WITH(io::load_checkpoint(file, target), Contains("truncated") && Contains(file.string()));

  io::save_checkpoint(file, world, "");
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
  }
  CHECK_THROWS_WITH(io::load_checkpoint(file, target), Contains("checksum"));

  io::save_checkpoint(file, world, "");
  World other_law(WorldSettings{});
  other_law.set_contact_model(ContactKind::BallBall,
                              make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1, 0.5), "ball-ball"));
  CHECK_THROWS_WITH(io::load_checkpoint(file, other_law), Contains("ball-ball law") && Contains("rolling-linear"));
  CHECK_THROWS_WITH(io::load_checkpoint(temp_file("missing.ckpt"), target), Contains("cannot be opened"));
  fs::remove(file);
}
