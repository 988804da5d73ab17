// lab::SimpleShearConfig: one declaration per key. The schema's defaults are the default struct,
// a preset read through its keys is the struct the preset makes in C++, and the presets hold the
// study's Table 1 values (typed here from the study, not from the code).
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "dem/core/errors.hpp"
#include "dem/io/config.hpp"
#include "dem/lab/toolkit/simple_shear_config.hpp"

using Catch::Matchers::Contains;
using namespace dem;
using namespace dem::lab;

namespace {

io::Config preset_config(const std::string& preset) {
  io::Config config(simple_shear_schema());
  for (const auto& [key, value] : preset_values(preset)) config.set(key, value);
  return config;
}

}  // namespace

TEST_CASE("simple-shear keys: the schema's defaults are SimpleShearConfig{}, the study's 4D specimen", "[lab][config]") {
  const SimpleShearConfig from_schema = simple_shear_config(io::Config(simple_shear_schema()));
  CHECK(from_schema == SimpleShearConfig{});
  // A struct built in C++ makes the same specimen as the command line's defaults: 4D balls of
  // 0.7-1.2 mm x 4 with the Leighton Buzzard sieve curve for mass sampling.
  const SimpleShearConfig d;
  CHECK(d.grading.scale == 4.0);
  CHECK(d.grading.d_min == 0.7e-3);
  CHECK(d.grading.d_max == 1.2e-3);
  CHECK(d.grading.sieve_diameters == std::vector<double>{0.60e-3, 0.65e-3, 0.82e-3, 0.897e-3, 1.20e-3});
  CHECK(d.grading.passing_fraction == std::vector<double>{0.0, 0.10, 0.50, 0.60, 1.0});
  CHECK(d.generation.plate == GenerationPlate::Servo);
  CHECK(d.generation_friction() == d.ball_ball.friction());  // "ball-ball" by default
  // Every key of the schema is one field: the values of the struct name every key, in order.
  const auto values = simple_shear_values(d);
  const io::Schema schema = simple_shear_schema();
  const auto& keys = schema.keys();
  REQUIRE(values.size() == keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) CHECK(values[k].first == keys[k].key);
}

TEST_CASE("simple-shear keys: each preset read from its keys is the struct made in C++", "[lab][config]") {
  struct TableRow {
    std::string preset;
    double scale, modulus, friction, rolling_friction;
    long settle_steps;
  };
  // The study's Table 1, ball-ball row per size scale; the settle of the friction schedule is as
  // long in seconds at 1D as at 2D (its time step is 0.45 of 2D's).
  const std::vector<TableRow> table = {
      {"1D", 1.0, 5.3e7, 0.45, 0.18, 26000}, {"2D", 2.0, 4.4e7, 0.5, 0.17, 12000}, {"4D", 4.0, 1.2e7, 0.5, 0.4, 12000}};
  for (const TableRow& row : table) {
    INFO(row.preset);
    const SimpleShearConfig made = simple_shear_preset(row.preset);
    CHECK(simple_shear_config(preset_config(row.preset)) == made);
    CHECK(made.grading.scale == row.scale);
    CHECK(made.ball_ball.stiffness() == row.modulus);
    CHECK(made.ball_ball.friction() == row.friction);
    CHECK(made.ball_ball.rolling_friction() == row.rolling_friction);
    CHECK(made.generation.steps_per_stage == row.settle_steps);
    // The generation friction is the number itself, so a calibration that varies the ball-ball
    // friction keeps making the same specimen.
    CHECK(made.generation.friction == row.friction);
    CHECK(made.generation.rolling_friction == row.rolling_friction);
    // Plates and rings are the same at every scale.
    CHECK(made.ball_facet == ContactTypeConfig::rolling_linear(2e7, 1.0, 0.9, 0.9));
    CHECK(made.ball_pebble == ContactTypeConfig::rolling_linear(2e7, 1.0, 0.1, 0.1));
  }
  CHECK_THROWS_WITH(simple_shear_preset("3D"), Contains("--preset = 3D") && Contains("1D, 2D, 4D"));
}

TEST_CASE("simple-shear keys: key = field name, and a struct's values read back to the same struct", "[lab][config]") {
  io::Config c(simple_shear_schema());
  c.set("consolidation.tolerance", "0.02");
  c.set("generation.steps_per_stage", "777");
  c.set("measure.sphere_radius_ratio", "0.6");
  c.set("rings.vertical", "sand");
  c.set("shear.mode", "constant-volume");
  c.set("output.volumetric_strain_sign", "contraction-positive");
  c.set("generation.friction", "frictionless");
  c.set("generation.rolling_friction", "0.25");
  c.set("shear.directions_deg", "0,90");
  c.set("shear.leg_strains", "0.1,0.05");
  const SimpleShearConfig s = simple_shear_config(c);
  CHECK(s.consolidation.tolerance == 0.02);
  CHECK(s.generation.steps_per_stage == 777);
  CHECK(s.measure.sphere_radius_ratio == 0.6);
  CHECK(s.rings.vertical == RingVertical::Sand);
  CHECK(s.shear.mode == ShearMode::ConstantVolume);
  CHECK(s.output.volumetric_strain_sign == VolumeSign::ContractionPositive);
  CHECK(s.generation_friction() == 0.0);
  CHECK(s.generation_rolling_friction() == 0.25);
  REQUIRE(s.shear.legs().size() == 2);
  CHECK(s.shear.legs()[1].direction_deg == 90.0);
  CHECK(s.shear.total_strain() == Approx(0.15).epsilon(1e-15));

  io::Config again(simple_shear_schema());
  for (const auto& [key, value] : simple_shear_values(s)) again.set(key, value);
  CHECK(simple_shear_config(again) == s);
}

TEST_CASE("simple-shear keys: each contact type names its law by keyword and reads that law's parameters", "[lab][config][law]") {
  // The default is the study's rolling-resistance linear law, with every one of its parameters.
  const SimpleShearConfig d;
  CHECK(d.ball_ball.law == "rrlinear");
  CHECK(d.ball_ball.model("ball_ball")->law_name() == std::string("rolling-linear"));
  io::Config c(simple_shear_schema());
  c.set("ball_facet.law", "linear");
  c.set("ball_facet.friction", "0.3");
  const SimpleShearConfig s = simple_shear_config(c);
  CHECK(s.ball_facet.law == "linear");
  CHECK(s.ball_facet.friction() == 0.3);
  CHECK(s.ball_facet.rolling_friction() == 0.0);  // the linear law has none
  CHECK_FALSE(s.ball_facet.parameters.has("rolling_friction"));
  CHECK(s.ball_facet.model("ball_facet")->law_name() == std::string("linear"));
  CHECK(s.ball_ball.law == "rrlinear");
  // Its values read back to the same struct, the law included.
  io::Config again(simple_shear_schema());
  for (const auto& [key, value] : simple_shear_values(s)) again.set(key, value);
  CHECK(simple_shear_config(again) == s);
  // A keyword that is not a law is refused with the key, the value and the laws there are.
  CHECK_THROWS_WITH(c.set("ball_ball.law", "hertz"), Contains("ball_ball.law") && Contains("hertz") && Contains("rrlinear") &&
                                                         Contains("linear"));
  // A role the law does not have cannot be set from C++ either.
  ContactTypeConfig linear = s.ball_facet;
  CHECK_THROWS_WITH(linear.set_rolling_friction(0.1), Contains("rolling friction") && Contains("linear"));
  // The registry's rows: unique keywords, each with the parameters its roles name.
  std::vector<std::string> seen;
  for (const LawEntry& law : contact_laws()) {
    INFO(law.keyword);
    CHECK(std::find(seen.begin(), seen.end(), law.keyword) == seen.end());
    seen.push_back(law.keyword);
    const LawValues values(law.parameters);
    for (const std::string& role : {law.roles.stiffness, law.roles.friction, law.roles.rolling_friction})
      if (!role.empty()) CHECK(values.has(role));
    CHECK(law.bind(values, "test") != nullptr);
  }
}

TEST_CASE("simple-shear keys: hertz-mindlin reads its material, its damping and rolling models by name",
          "[lab][config][law]") {
  io::Config c(simple_shear_schema());
  CHECK(c.text("ball_ball.rolling") == "epsd");  // the model before the key existed
  c.set("ball_ball.law", "hertz-mindlin");
  c.set("ball_ball.youngs_modulus", "7e10");
  c.set("ball_ball.poissons_ratio", "0.3");
  c.set("ball_ball.restitution", "0.6");
  c.set("ball_ball.damping_model", "tsuji");
  c.set("ball_ball.rolling", "cdt");
  const SimpleShearConfig s = simple_shear_config(c);
  CHECK(s.ball_ball.law == "hertz-mindlin");
  CHECK(s.ball_ball.parameters.at("damping_model") == 1.0);
  CHECK(s.ball_ball.parameters.at("rolling") == 1.0);
  CHECK(s.ball_ball.stiffness() == 7e10);  // the stiffness role: Young's modulus
  CHECK(s.ball_ball.model("ball_ball")->law_name() == std::string("hertz-mindlin"));
  // written back by name, and read to the same struct
  int written_by_name = 0;
  io::Config again(simple_shear_schema());
  for (const auto& [key, value] : simple_shear_values(s)) {
    again.set(key, value);
    if (key == "ball_ball.damping_model" && value == "tsuji") ++written_by_name;
    if (key == "ball_ball.rolling" && value == "cdt") ++written_by_name;
  }
  CHECK(written_by_name == 2);
  CHECK(simple_shear_config(again) == s);
  // a model that is not one of them, or a restitution out of range, named
  CHECK_THROWS_WITH(c.set("ball_ball.damping_model", "hooke"),
                    Contains("ball_ball.damping_model") && Contains("hooke") && Contains("liggghts") && Contains("tsuji"));
  CHECK_THROWS_WITH(c.set("ball_ball.rolling", "bogus"), Contains("ball_ball.rolling") && Contains("bogus") &&
                                                             Contains("'epsd' 'cdt' 'none'"));
  // the laws' own tables refuse it too (the Python module's path), and `none` leaves no rolling resistance
  const LawEntry& hertz = contact_law("hertz-mindlin");
  const LawParameter* rolling = nullptr;
  for (const LawParameter& p : hertz.parameters)
    if (p.name == "rolling") rolling = &p;
  REQUIRE(rolling != nullptr);
  CHECK_THROWS_WITH(rolling->choice_index("bogus", "ball_facet.rolling"),
                    Contains("ball_facet.rolling = bogus") && Contains("epsd, cdt, none"));
  CHECK(rolling->choice_index("none", "ball_facet.rolling") == 2.0);
  ContactKinematics k{};
  k.effective_radius = 1e-3;
  c.set("ball_ball.rolling_friction", "0.3");
  c.set("ball_ball.rolling", "epsd");
  CHECK(simple_shear_config(c).ball_ball.model("ball_ball")->stiffness(k).rolling > 0.0);
  c.set("ball_ball.rolling", "none");
  CHECK(simple_shear_config(c).ball_ball.model("ball_ball")->stiffness(k).rolling == 0.0);
  CHECK_THROWS_WITH(c.set("ball_ball.restitution", "1.5"), Contains("ball_ball.restitution") && Contains("1.5"));
}

TEST_CASE("simple-shear keys: a key of a law that is not chosen is refused by name, with the law and its keys",
          "[lab][config][law]") {
  io::Config c(simple_shear_schema());
  c.set("ball_ball.youngs_modulus", "2e9");  // ball_ball.law stays rrlinear
  CHECK_THROWS_WITH(simple_shear_config(c), Contains("ball_ball.youngs_modulus") && Contains("hertz-mindlin") &&
                                                Contains("ball_ball.law = rrlinear") && Contains("effective_modulus") &&
                                                Contains("stiffness_ratio"));
  io::Config h(simple_shear_schema());
  h.set("ball_facet.law", "hertz-mindlin");
  h.set("ball_facet.surface_energy", "0.05");  // hertz-dmt's, not hertz-mindlin's
  CHECK_THROWS_WITH(simple_shear_config(h), Contains("ball_facet.surface_energy") && Contains("hertz-dmt") &&
                                                Contains("ball_facet.law = hertz-mindlin") && Contains("youngs_modulus"));
  // A key at its declared default passes: a printed configuration lists every law's keys.
  h.set("ball_facet.surface_energy", h.schema().find("ball_facet.surface_energy")->default_value);
  CHECK(simple_shear_config(h).ball_facet.law == "hertz-mindlin");
  h.set("ball_facet.law", "hertz-dmt");
  h.set("ball_facet.surface_energy", "0.05");
  CHECK(simple_shear_config(h).ball_facet.parameters.at("surface_energy") == 0.05);
  h.set("ball_ball.rolling", "cdt");  // ball_ball.law stays rrlinear, whose spring is its own
  CHECK_THROWS_WITH(simple_shear_config(h), Contains("ball_ball.rolling = cdt") && Contains("hertz-mindlin, hertz-dmt") &&
                                                Contains("ball_ball.law = rrlinear"));
}

TEST_CASE("simple-shear keys: the checks across keys apply to a struct built in C++", "[lab][config]") {
  SimpleShearConfig c;
  c.rings.stack_height = 0.5 * c.specimen.height;
  CHECK_THROWS_WITH(c.validate(), Contains("rings.stack_height") && Contains("specimen.height"));
  c = SimpleShearConfig{};
  c.shear.directions_deg = {0.0, 90.0};
  CHECK_THROWS_WITH(c.validate(), Contains("shear.leg_strains"));
  c.shear.leg_strains = {0.1};
  CHECK_THROWS_WITH(c.validate(), Contains("shear.leg_strains") && Contains("as many entries"));
  c = SimpleShearConfig{};
  c.grading.d_max = 0.5 * c.grading.d_min;
  CHECK_THROWS_WITH(c.validate(), Contains("grading.d_max"));
  io::Config text(simple_shear_schema());
  text.set("generation.friction", "sticky");
  CHECK_THROWS_WITH(simple_shear_config(text), Contains("generation.friction") && Contains("sticky"));
}

TEST_CASE("engine keys: threads is auto or a count from 1 to 256, and a bad one is refused by name", "[lab][config]") {
  io::Config c(simple_shear_schema());
  CHECK(c.text("engine.threads") == "auto");
  CHECK(simple_shear_config(c).engine.threads == 0);
  CHECK(simple_shear_config(c).engine.adapt_threads);
  c.set("engine.threads", "3");
  CHECK(simple_shear_config(c).engine.threads == 3);
  c.set("engine.threads", "0");  // how earlier files wrote auto
  CHECK(simple_shear_config(c).engine.threads == 0);
  for (const char* bad : {"two", "2.5", "-1", "257", ""}) {
    c.set("engine.threads", bad);
    CHECK_THROWS_WITH(simple_shear_config(c), Contains("engine.threads") && Contains("auto or a whole number"));
  }
}

TEST_CASE("simple-shear keys: absurd physical values are refused at the door with the key and its range", "[lab][config]") {
  // The audit's cases: each started work or failed later without naming the key.
  const std::pair<const char*, const char*> cases[] = {{"rings.pebble_diameter", "1.5"},
                                                       {"shear.strain_rate", "1e308"},
                                                       {"specimen.density", "1e-300"},
                                                       {"consolidation.vertical_stress", "1e12"},
                                                       {"engine.time_step", "10"},
                                                       {"specimen.diameter", "50"},
                                                       // the laws' parameters: a modulus in the wrong unit, a typo
                                                       {"ball_ball.effective_modulus", "1e300"},
                                                       {"ball_facet.youngs_modulus", "7e15"},
                                                       {"ball_ball.friction", "5e3"},
                                                       {"ball_pebble.rolling_friction", "1e9"},
                                                       {"ball_ball.stiffness_ratio", "1e6"}};
  for (const auto& [key, value] : cases) {
    io::Config c(simple_shear_schema());
    CHECK_THROWS_WITH(c.set(key, value), Contains(key) && Contains(value) && Contains("must be"));
  }
}
