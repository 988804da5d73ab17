// dem::io::Config: defaults, INI and JSON files, --set precedence, error messages and the
// to_ini()/to_json() round trip. Values are compared exactly: the printed form of a real is the
// shortest text that std::from_chars reads back as the same double.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>


#include <cmath>
#include <fstream>

#include "dem/core/errors.hpp"
#include "dem/io/config.hpp"

#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using dem::io::Config;
using dem::io::KeySpec;
using dem::io::ValueType;

namespace {

using dem::testing::TempDir;

dem::io::Schema test_schema() {
  dem::io::Schema schema;
  schema
      .add({.key = "contact.normal_stiffness", .type = ValueType::Real, .default_value = "1e6",
            .unit = "N/m", .help = "normal spring stiffness", .min = 0.0, .min_exclusive = true})
      .add({.key = "run.steps", .type = ValueType::Integer, .default_value = "1000",
            .help = "number of time steps", .min = 1.0})
      // Out of section order on purpose: output must still give one [contact] section.
      .add({.key = "contact.friction", .type = ValueType::Real, .default_value = "0.5",
            .unit = "-", .help = "sliding friction coefficient", .min = 0.0, .max = 10.0})
      .add({.key = "run.verbose", .type = ValueType::Boolean, .default_value = "off",
            .help = "print progress"})
      .add({.key = "run.integrator", .type = ValueType::Text, .default_value = "verlet",
            .help = "time integrator", .choices = {"verlet", "euler"}})
      .add({.key = "run.output_dir", .type = ValueType::Text, .default_value = "out",
            .help = "where results go"})
      .add({.key = "wall.stress_path", .type = ValueType::RealList, .default_value = "1e5, 2e5",
            .unit = "Pa", .help = "target stresses", .min = 0.0});
  return schema;
}

// The InputError message thrown by `action`, or "no error".
template <class F>
std::string error_of(F action) {
  try {
    action();
  } catch (const dem::InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("Config starts with every key at its default", "[io][config]") {
  const Config config(test_schema());
  CHECK(config.real("contact.normal_stiffness") == 1e6);
  CHECK(config.real("contact.friction") == 0.5);
  CHECK(config.integer("run.steps") == 1000);
  CHECK_FALSE(config.boolean("run.verbose"));
  CHECK(config.text("run.integrator") == "verlet");
  CHECK(config.real_list("wall.stress_path") == std::vector<double>{1e5, 2e5});

  const std::string help = test_schema().help_text();
  CHECK_THAT(help, Contains("contact.normal_stiffness") && Contains("N/m") && Contains("> 0") &&
                   Contains("normal spring stiffness") && Contains("in [0, 10]") &&
                   Contains("'verlet' 'euler'"));
  CHECK(std::count(help.begin(), help.end(), '\n') == 7);
}

TEST_CASE("Config reads INI and JSON files", "[io][config]") {
  const TempDir dir("files");
  Config ini(test_schema());
  ini.load_file(dir.write("run.ini", "; comment\n# comment\n[contact]\nfriction = 0.3\n\n"
                                      "[run]\nsteps=20\nverbose = Yes\nintegrator = euler\n"
                                      "[wall]\nstress_path = 1 , 2.5,3e5\n"));
  CHECK(ini.real("contact.friction") == 0.3);
  CHECK(ini.real("contact.normal_stiffness") == 1e6);  // not in the file: default kept
  CHECK(ini.integer("run.steps") == 20);
  CHECK(ini.boolean("run.verbose"));
  CHECK(ini.text("run.integrator") == "euler");
  CHECK(ini.real_list("wall.stress_path") == std::vector<double>{1.0, 2.5, 3e5});

  Config json(test_schema());
  json.load_file(dir.write("run.JSON", R"({"contact": {"normal_stiffness": 2.5e7},
      "run": {"steps": "30", "verbose": true, "output_dir": "runs/a b"},
      "wall": {"stress_path": [0, 1e5, 4e5]}})"));
  CHECK(json.real("contact.normal_stiffness") == 2.5e7);
  CHECK(json.integer("run.steps") == 30);
  CHECK(json.boolean("run.verbose"));
  CHECK(json.text("run.output_dir") == "runs/a b");
  CHECK(json.real_list("wall.stress_path") == std::vector<double>{0.0, 1e5, 4e5});
}

TEST_CASE("config: --set overrides the file, and the last setting wins", "[io][config]") {
  const TempDir dir("precedence");
  Config config(test_schema());
  config.load_file(dir.write("base.ini", "[run]\nsteps = 20\nverbose = on\n"));
  config.set("run.steps=500");
  config.set(" run.verbose = 0 ");
  config.set("wall.stress_path", "");
  CHECK(config.integer("run.steps") == 500);
  CHECK_FALSE(config.boolean("run.verbose"));
  CHECK(config.real_list("wall.stress_path").empty());
  config.load_file(dir.write("later.ini", "[run]\nsteps = 7\n"));
  CHECK(config.integer("run.steps") == 7);
}

TEST_CASE("Config errors name the key, the value and what is allowed", "[io][config]") {
  const TempDir dir("errors");
  Config config(test_schema());
  const auto set = [&](const std::string& assignment) {
    return error_of([&] { config.set(assignment); });
  };
  CHECK_THAT(set("contact.frition=0.2"), Contains("'contact.frition'") &&
                                              Contains("did you mean 'contact.friction'"));
  CHECK_THAT(set("run.friction=0.2"), Contains("'contact.friction'"));  // same name, other section
  CHECK_THAT(set("zzz.qqq=1"), Contains("'zzz.qqq'") && Contains("[contact] [run] [wall]"));
  CHECK_THAT(set("contact.normal_stiffness=abc"),
             Contains("'contact.normal_stiffness'") && Contains("'abc'") && Contains("N/m"));
  CHECK_THAT(set("contact.normal_stiffness=0"), Contains("'0'") && Contains("> 0"));
  CHECK_THAT(set("contact.normal_stiffness=nan"), Contains("'nan'") && Contains("finite"));
  CHECK_THAT(set("contact.normal_stiffness=inf"), Contains("'inf'") && Contains("finite"));
  CHECK_THAT(set("contact.friction=-0.1"), Contains("'-0.1'") && Contains("in [0, 10]"));
  CHECK_THAT(set("run.steps=1.5"), Contains("'run.steps'") && Contains("'1.5'") &&
                                       Contains("an integer >= 1"));
  CHECK_THAT(set("run.steps=0"), Contains("'0'") && Contains(">= 1"));
  CHECK_THAT(set("run.steps=+-5"), Contains("'+-5'"));
  CHECK_THAT(set("run.verbose=maybe"), Contains("'maybe'") && Contains("yes/no"));
  CHECK_THAT(set("run.integrator=rk4"), Contains("'rk4'") && Contains("'verlet' 'euler'"));
  CHECK_THAT(set("wall.stress_path=1,x"), Contains("'1,x'") && Contains("Pa"));
  CHECK_THAT(set("wall.stress_path=1,-2"), Contains("'1,-2'") && Contains("each >= 0"));
  CHECK_THAT(set("wall.stress_path=1,2,"), Contains("'1,2,'"));
  CHECK_THAT(set("run.steps"), Contains("'run.steps'") && Contains("section.key=value"));

  const auto load = [&](const fs::path& file) { return error_of([&] { config.load_file(file); }); };
  const fs::path bad = dir.write("bad.ini", "[run]\nsteps = 5\n[contact]\nfriction = lots\n");
  CHECK_THAT(load(bad), Contains(bad.string()) && Contains("'contact.friction'") &&
                            Contains("'lots'"));
  CHECK(config.integer("run.steps") == 1000);  // the bad file changed nothing
  CHECK_THAT(load(dir.write("x.yaml", "")), Contains("x.yaml") && Contains(".ini or .json"));
  CHECK_THAT(load(dir.path / "absent.ini"), Contains("absent.ini") &&
                                               Contains("does not exist"));
  CHECK_THAT(load(dir.write("broken.json", "{\n\"run\": {\"steps\": 1,\n}")),
             Contains("broken.json") && Contains("line"));
  CHECK_THAT(load(dir.write("deep.json", R"({"run": {"steps": {"x": 1}}})")),
             Contains("'run.steps.x'"));
}

TEST_CASE("Config misuse by the programmer is a logic_error", "[io][config]") {
  const Config config(test_schema());
  CHECK_THROWS_AS(config.real("run.steps"), std::logic_error);
  CHECK_THROWS_AS(config.text("run.nothing"), std::logic_error);
  CHECK_THROWS_WITH(config.integer("contact.friction"), Contains("real") && Contains("integer"));
  dem::io::Schema schema;
  CHECK_THROWS_AS(schema.add({.key = "nosection", .default_value = "1"}), std::logic_error);
  CHECK_THROWS_AS(schema.add({.key = "a.b.c", .default_value = "1"}), std::logic_error);
  CHECK_THROWS_WITH(schema.add({.key = "a.b", .default_value = "x"}), Contains("default"));
  CHECK_THROWS_AS(schema.add({.key = "a.b", .type = ValueType::Boolean, .default_value = "1",
                              .min = 0.0}), std::logic_error);
  schema.add({.key = "a.b", .default_value = "1"});
  CHECK_THROWS_WITH(schema.add({.key = "a.b", .default_value = "2"}), Contains("twice"));
  CHECK(schema.keys().size() == 1);
}

TEST_CASE("to_ini and to_json read back to identical values", "[io][config]") {
  const TempDir dir("round_trip");
  Config original(test_schema());
  original.set("contact.normal_stiffness", "0.1");  // not exactly representable
  original.set("contact.friction", std::to_string(1.0 / 3.0));
  original.set("contact.friction", "0.33333333333333331");  // 1/3 to the last bit
  original.set("run.steps=123456789");
  original.set("run.verbose=yes");
  original.set("run.output_dir", R"(runs/a "b" \c;#1, x)");
  original.set("wall.stress_path", "1e-300, 4.9e-324, 123456.789");

  for (const auto& [name, text] : {std::pair{std::string("round.ini"), original.to_ini()},
                                   std::pair{std::string("round.json"), original.to_json()}}) {
    INFO(text);
    Config copy(test_schema());
    copy.load_file(dir.write(name, text));
    CHECK(copy.real("contact.normal_stiffness") == original.real("contact.normal_stiffness"));
    CHECK(copy.real("contact.friction") == 1.0 / 3.0);
    CHECK(copy.integer("run.steps") == 123456789);
    CHECK(copy.boolean("run.verbose"));
    CHECK(copy.text("run.integrator") == "verlet");
    CHECK(copy.text("run.output_dir") == original.text("run.output_dir"));
    CHECK(copy.real_list("wall.stress_path") == original.real_list("wall.stress_path"));
    CHECK(copy.to_ini() == original.to_ini());
  }
  const std::string ini = original.to_ini();
  CHECK(ini.find("[contact]") == ini.rfind("[contact]"));  // one section despite schema order
  // JSON types, not quoted numbers: integers stay integers, reals print their shortest exact form.
  const auto json = nlohmann::json::parse(original.to_json());
  CHECK(json["run"]["steps"].is_number_integer());
  CHECK(json["run"]["steps"] == 123456789);
  CHECK(json["run"]["verbose"] == true);
  CHECK(json["wall"]["stress_path"] == nlohmann::json::array({1e-300, 5e-324, 123456.789}));
  CHECK_THAT(original.to_json(), Contains("1e-300") && Contains("5e-324") && Contains("123456.789"));
}

TEST_CASE("config: deep, large and repeated-key files are refused with a message", "[io][config]") {
  const TempDir dir("limits");
  Config config(test_schema());
  config.set("run.steps=42");
  const auto load = [&](const fs::path& file) { return error_of([&] { config.load_file(file); }); };

  // Boost's JSON reader recurses per level: 50,000 levels overflowed the stack (exit 139).
  const std::string deep = R"({"run": {"steps": )" + std::string(50000, '[') + std::string(50000, ']') + "}}";
  const fs::path deep_file = dir.write("deep.json", deep);
  CHECK_THAT(load(deep_file), Contains(deep_file.string()) && Contains("nesting depth 50002") &&
                                  Contains("at most 64"));
  const std::string limit = std::string(dem::io::max_config_depth, '[') +
                            std::string(dem::io::max_config_depth, ']');
  CHECK_THAT(load(dir.write("limit.json", limit)), !Contains("nesting"));  // refused as a list only

  const fs::path twice = dir.write("twice.json", "{\"run\": {\"steps\": 1,\n \"steps\": 2}}");
  CHECK_THAT(load(twice), Contains(twice.string()) && Contains("line 2: duplicate key name 'run.steps'"));
  CHECK_THAT(load(dir.write("sections.json", R"({"run": {"steps": 1}, "run": {"verbose": true}})")),
             Contains("line 1: duplicate section name 'run'"));
  // The same key in two forms (or with an escaped letter) is found in the parsed tree.
  CHECK_THAT(load(dir.write("forms.json", R"({"run.steps": 1, "run": {"st\u0065ps": 2}})")),
             Contains("duplicate key name 'run.steps'"));
  CHECK_THAT(load(dir.write("twice.ini", "[run]\nsteps = 1\nsteps = 2\n")),
             Contains("line 3: duplicate key name 'run.steps'"));
  CHECK_THAT(load(dir.write("sections.ini", "[run]\nsteps = 1\n[contact]\nfriction = 1\n[run]\nverbose = 1\n")),
             Contains("line 5: duplicate section name 'run'"));

  const std::size_t most = dem::io::max_config_file_bytes;
  const std::string comment = "# " + std::string(61, '-') + "\n";  // 64 bytes
  std::string big;
  while (big.size() < most) big += comment;
  big.resize(most);
  big.back() = '\n';
  CHECK(load(dir.write("most.ini", big)) == "no error");
  const fs::path large = dir.write("large.ini", big + "\n");
  CHECK_THAT(load(large), Contains(large.string()) && Contains("size 1048577 bytes") &&
                              Contains("at most 1048576 bytes"));
  CHECK(config.integer("run.steps") == 42);  // no refused file changed anything
}

TEST_CASE("config: a refused value is quoted as a short, escaped excerpt", "[config]") {
  dem::io::Schema schema;
  schema.add({.key = "specimen.diameter", .type = ValueType::Real, .default_value = "0.07", .min = 0.0});
  dem::io::Config config(schema);
  const std::string huge(100000, '7');
  try {
    config.set("specimen.diameter", huge + "x");
    FAIL("a 100 KB value was accepted");
  } catch (const dem::InputError& e) {
    const std::string message = e.what();
    CHECK(message.size() < 600);
    CHECK_THAT(message, Contains("specimen.diameter") && Contains("... (100001 bytes)"));
  }
  std::string binary = "\xef\xbb\xbf";
  binary += "0.5";
  binary += std::string(1, '\0');
  binary += "\x1b[31m";
  CHECK_THROWS_WITH(config.set("specimen.diameter", binary), Contains("'\\xef\\xbb\\xbf0.5\\x00\\x1b[31m'"));
  CHECK_THROWS_WITH(config.set(std::string("spec\x07imen.x"), "1"), Contains("spec\\x07imen.x"));
}
