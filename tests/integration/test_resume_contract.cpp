// The resume contract (docs/restart.md): a restart file records its configuration; a resumed run
// may not change what the file already holds, may change the rest (recorded in summary.json), and
// a refused resume touches nothing in its output folder. Reduced specimen (about 170 balls).
#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>
#include <dem/lab/protocols/calibration.hpp>
#include <dem/lab/protocols/cyclic_shear.hpp>
#include <dem/lab/protocols/simple_shear.hpp>
#include <dem/lab/protocols/element_test.hpp>
#include <dem/lab/protocols/triaxial.hpp>

#include "support/json.hpp"
#include "support/reduced_specimen.hpp"

using namespace dem;
using namespace dem::lab;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::file_text;

namespace {

io::Config small_config() {
  io::Config c = testing::reduced_specimen();
  c.set("shear.target_strain", "0.01");
  c.set("output.fabric_strains", "");
  c.set("output.snapshot_strains", "");
  c.set("output.restart_every_steps", "300");
  return c;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("libdem_resume_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// A consolidated specimen made once for the cases below, with its configuration recorded.
const fs::path& consolidated_specimen() {
  static const fs::path dir = [] {
    const fs::path d = fresh_dir("specimen");
    std::ostringstream log;
    SimpleShearTest test(simple_shear_config(small_config()), d, log);
    test.record_configuration(small_config());
    test.generate();
    test.consolidate();
    return d;
  }();
  return dir;
}

// Loads the consolidated specimen under `c` into a fresh folder `name`.
void load_under(const io::Config& c, const std::string& name, ResumeIntent intent = ResumeIntent::Continue) {
  std::ostringstream log;
  SimpleShearTest test(simple_shear_config(c), fresh_dir(name), log);
  test.record_configuration(c);
  test.load_restart(consolidated_specimen() / "consolidated.restart", intent);
}

using Record = std::vector<std::pair<std::string, std::string>>;

}  // namespace

TEST_CASE("resume rules: every configuration key has a rule", "[resume]") {
  for (const io::Schema& schema : {simple_shear_schema(), cyclic_shear_schema(), calibration_schema(), triaxial_schema(), element_test_schema()})
    for (const io::KeySpec& spec : schema.keys()) {
      INFO(spec.key);
      CHECK_NOTHROW(resume_rule(schema, spec.key));
    }
  // A key declared without one is a programming error, named.
  io::Schema bare;
  bare.add({.key = "new.key", .default_value = "1"});
  CHECK_THROWS_WITH(resume_rule(bare, "new.key"), Contains("new.key") && Contains("fixed column"));
}

TEST_CASE("resume rules: docs/restart.md shows the table the binding tables declare", "[resume][docs]") {
  const std::string table = resume_rules_table(cyclic_shear_schema());
  INFO(table);
  CHECK(dem::testing::file_text(std::filesystem::path(LIBDEM_SOURCE_DIR) / "docs" / "restart.md").find(table) != std::string::npos);
}

TEST_CASE("resume rules: what is done is fixed, what is to come and the outputs may change", "[resume]") {
  // key, progress of the file, reconsolidation, allowed (docs/restart.md's table).
  struct Case {
    const char* key;
    RunProgress progress;
    bool reconsolidate, allowed;
  };
  const Case cases[] = {
      {"specimen.diameter", RunProgress::Generating, false, false},
      {"grading.scale", RunProgress::Consolidated, true, false},
      {"rings.density", RunProgress::Generated, false, false},
      {"generation.friction", RunProgress::Generating, false, false},
      {"engine.local_damping", RunProgress::Consolidated, false, false},
      {"engine.time_step", RunProgress::Shearing, false, false},
      {"engine.time_step", RunProgress::Consolidated, true, true},
      {"ball_ball.effective_modulus", RunProgress::Generated, false, false},
      {"ball_ball.effective_modulus", RunProgress::Consolidated, true, true},
      {"ball_ball.effective_modulus", RunProgress::Shearing, true, false},
      {"ball_ball.friction", RunProgress::Generated, false, true},  // the generation used generation.friction
      {"ball_ball.friction", RunProgress::Consolidating, false, false},
      {"ball_pebble.friction", RunProgress::Consolidated, false, false},
      {"consolidation.vertical_stress", RunProgress::Generated, false, true},
      {"consolidation.vertical_stress", RunProgress::Consolidated, false, false},
      {"consolidation.vertical_stress", RunProgress::Consolidated, true, true},
      {"shear.mode", RunProgress::Consolidated, false, true},
      {"shear.mode", RunProgress::Shearing, false, false},
      {"shear.directions_deg", RunProgress::Shearing, false, false},
      {"shear.target_strain", RunProgress::Shearing, false, true},
      {"rings.vertical", RunProgress::Consolidated, false, true},
      {"rings.vertical", RunProgress::Shearing, false, false},
      {"measure.profile_bins", RunProgress::Consolidated, false, false},
      {"measure.profile_bins", RunProgress::Generated, false, true},
      {"output.volumetric_strain_sign", RunProgress::Shearing, false, false},
      {"output.every_strain", RunProgress::Shearing, false, true},
      {"output.restart_every_steps", RunProgress::Generating, false, true},
      {"engine.threads", RunProgress::Shearing, false, true},
      {"engine.max_overlap_ratio", RunProgress::Shearing, false, true},
      {"ball_ball.law", RunProgress::Generating, false, false},
      {"ball_ball.rolling", RunProgress::Generated, false, false},  // the law's model: as its other parameters
      {"ball_facet.rolling", RunProgress::Consolidated, true, true},
      {"cyclic.csr", RunProgress::Consolidated, false, true},  // a consolidated specimen, cycled in another way
      {"cyclic.csr", RunProgress::Shearing, false, false},     // a cyclic stage under way
      {"cyclic.max_cycles", RunProgress::Shearing, false, true},
  };
  const io::Schema schema = cyclic_shear_schema();
  for (const Case& c : cases) {
    INFO(c.key << " at " << to_string(c.progress) << (c.reconsolidate ? " (reconsolidation)" : ""));
    const Record file{{c.key, "1"}}, now{{c.key, "2"}};
    if (c.allowed) {
      const auto changes = check_resume(schema, file, now, c.progress, c.reconsolidate, "restart file f");
      REQUIRE(changes.size() == 1);
      CHECK(changes[0].key == c.key);
      CHECK(changes[0].file_value == "1");
      CHECK(changes[0].new_value == "2");
    } else {
      CHECK_THROWS_WITH(check_resume(schema, file, now, c.progress, c.reconsolidate, "restart file f"),
                        Contains(std::string(c.key) + " = 2 here, 1 in the file") && Contains("restart file f") &&
                            Contains(to_string(c.progress)));
    }
  }
  // A file written before shear.damping_frame existed sheared in the fixed frame: the new default
  // is refused mid-shear, naming the key, and allowed on a consolidated specimen.
  CHECK_THROWS_WITH(check_resume(schema, {{"shear.mode", "drained"}}, {{"shear.mode", "drained"}, {"shear.damping_frame", "plates"}},
                                 RunProgress::Shearing, false, "f"),
                    Contains("shear.damping_frame = plates here, fixed in the file"));
  CHECK(check_resume(schema, {{"shear.mode", "drained"}}, {{"shear.damping_frame", "fixed"}}, RunProgress::Shearing, false, "f").empty());
  CHECK(check_resume(schema, {{"shear.mode", "drained"}}, {{"shear.damping_frame", "plates"}}, RunProgress::Consolidated, false, "f")
            .size() == 1);
  // A file written before the rolling key existed ran epsd: cdt is refused, epsd passes.
  CHECK_THROWS_WITH(check_resume(schema, {{"ball_ball.law", "hertz-mindlin"}},
                                 {{"ball_ball.law", "hertz-mindlin"}, {"ball_ball.rolling", "cdt"}}, RunProgress::Shearing,
                                 false, "f"),
                    Contains("ball_ball.rolling = cdt here, epsd in the file"));
  CHECK(check_resume(schema, {{"ball_ball.law", "hertz-mindlin"}}, {{"ball_ball.law", "hertz-mindlin"}, {"ball_ball.rolling", "epsd"}},
                     RunProgress::Shearing, false, "f")
            .empty());
  // A file made with an earlier default (specimen.porosity 0.4 until 2026-12-07) is refused with
  // the --set that resumes it; another value in the file gets no such hint.
  CHECK_THROWS_WITH(check_resume(schema, {{"specimen.porosity", "0.4"}}, {{"specimen.porosity", "0.46"}},
                                 RunProgress::Consolidated, false, "f"),
                    Contains("specimen.porosity = 0.46 here, 0.4 in the file") &&
                        Contains("--set specimen.porosity=0.4 resumes the file"));
  CHECK_THROWS_WITH(check_resume(schema, {{"specimen.porosity", "0.42"}}, {{"specimen.porosity", "0.46"}},
                                 RunProgress::Consolidated, false, "f"),
                    !Contains("resumes the file"));
  // Unchanged keys and keys of another schema version pass without a word.
  CHECK(check_resume(schema, {{"shear.mode", "drained"}, {"old.key", "1"}}, {{"shear.mode", "drained"}, {"new.key", "2"}},
                     RunProgress::Done, false, "f")
            .empty());
}

TEST_CASE("resume: a consolidated specimen refuses changed physics and geometry, naming every key and both values",
          "[resume][simple-shear]") {
  io::Config c = small_config();
  c.set("ball_ball.friction", "0.3");
  c.set("engine.local_damping", "0.1");
  CHECK_THROWS_WITH(load_under(c, "refused_friction"),
                    Contains("ball_ball.friction = 0.3 here, 0.5 in the file") &&
                        Contains("engine.local_damping = 0.1 here, 0.7 in the file") && Contains("dem-consolidate --from"));

  // The silent doubling of the shear stress: another diameter over the same specimen.
  io::Config wider = small_config();
  wider.set("specimen.diameter", "0.042");
  CHECK_THROWS_WITH(load_under(wider, "refused_diameter"), Contains("specimen.diameter = 0.042 here, 0.03 in the file"));
  io::Config step = small_config();
  step.set("engine.time_step", "1e-6");
  CHECK_THROWS_WITH(load_under(step, "refused_step"), Contains("engine.time_step = 1e-06 here, 0 in the file"));
}

TEST_CASE("resume: the next stage's keys and the outputs may change, and summary.json lists them", "[resume][simple-shear]") {
  io::Config c = small_config();
  c.set("shear.mode", "constant-volume");
  c.set("output.every_strain", "0.0025");
  const fs::path dir = fresh_dir("allowed");
  std::ostringstream log;
  {
    SimpleShearTest test(simple_shear_config(c), dir, log);
    test.record_configuration(c);
    test.load_restart(consolidated_specimen() / "consolidated.restart");
    test.run();
    test.write_summary(c.to_json());
  }
  const auto summary = dem::testing::load_json(dir / "summary.json");
  const auto& changed = summary.at("resume_changed_keys");
  CHECK(changed.at("shear.mode").at("restart_file").get<std::string>() == "drained");
  CHECK(changed.at("shear.mode").at("this_run").get<std::string>() == "constant-volume");
  CHECK(changed.at("output.every_strain").at("this_run").get<std::string>() == "0.0025");
  CHECK_THAT(log.str(), Contains("applied shear.mode = constant-volume (the restart file had drained)"));
  // Which run it continues and where: the consolidated specimen's file and its last step.
  const auto& from = summary.at("continued_from");
  CHECK(fs::equivalent(from.at("restart_file").get<std::string>(), consolidated_specimen() / "consolidated.restart"));
  // The specimen's history ends at its consolidated state (its cells may hold nan: read as text).
  std::istringstream specimen_history(dem::testing::file_text(consolidated_specimen() / "history.csv"));
  std::string header, line, last;
  std::getline(specimen_history, header);
  while (std::getline(specimen_history, line))
    if (!line.empty()) last = line;
  const auto cell = [](const std::string& row, std::size_t k) {
    std::istringstream in(row);
    std::string value;
    for (std::size_t i = 0; i <= k; ++i) std::getline(in, value, ',');
    return value;
  };
  std::size_t step_column = 0;
  while (cell(header, step_column) != "step") ++step_column;
  CHECK(std::to_string(from.at("step").get<std::int64_t>()) == cell(last, step_column));

  // Mid-shear the shear mode is part of what is done.
  REQUIRE(fs::exists(dir / "restart.restart"));
  io::Config drained = c;
  drained.set("shear.mode", "drained");
  SimpleShearTest again(simple_shear_config(drained), fresh_dir("allowed_again"), log);
  again.record_configuration(drained);
  CHECK_THROWS_WITH(again.load_restart(dir / "restart.restart"), Contains("shear.mode = drained here, constant-volume in the file"));
}

TEST_CASE("resume: a reconsolidation may change the contact parameters and the consolidation", "[resume][simple-shear]") {
  io::Config c = small_config();
  c.set("ball_ball.effective_modulus", "2.4e7");
  c.set("consolidation.vertical_stress", "1e5");
  CHECK_THROWS_WITH(load_under(c, "reconsolidate_refused"), Contains("ball_ball.effective_modulus"));
  CHECK_NOTHROW(load_under(c, "reconsolidate", ResumeIntent::Reconsolidate));
}

TEST_CASE("resume: a folder holding another run is refused before anything in it changes", "[resume][simple-shear]") {
  const fs::path dir = fresh_dir("occupied");
  fs::create_directories(dir);
  std::ofstream(dir / "history.csv") << "time\n42\n";
  std::ostringstream log;
  SimpleShearTest test(simple_shear_config(small_config()), dir, log);
  test.record_configuration(small_config());
  test.load_restart(consolidated_specimen() / "consolidated.restart");
  CHECK_THROWS_WITH(test.open_outputs(), Contains("holds the results of another run") && Contains("--replace"));
  CHECK(file_text(dir / "history.csv") == "time\n42\n");
  CHECK_FALSE(fs::exists(dir / "fabric.csv"));

  SimpleShearTest replacing(simple_shear_config(small_config()), dir, log);
  replacing.record_configuration(small_config());
  replacing.load_restart(consolidated_specimen() / "consolidated.restart");
  replacing.open_outputs({.replace = true});
  // The specimen's own history (its consolidated row) replaces the old file's.
  CHECK(file_text(dir / "history.csv") == file_text(consolidated_specimen() / "history.csv"));
}

TEST_CASE("resume: a restart file with the key-value protocol lines of earlier versions shears as its JSON twin",
          "[resume][simple-shear]") {
  const fs::path file = consolidated_specimen() / "consolidated.restart";
  std::ostringstream log;
  // The same world with its protocol state in the line form restart files had before it was JSON.
  SimpleShearTest reader(simple_shear_config(small_config()), fresh_dir("legacy_reader"), log);
  const auto state = nlohmann::ordered_json::parse(io::load_checkpoint(file, reader.world()));
  REQUIRE(state.at("profile_reference").size() > 0);
  std::ostringstream lines;
  const auto number = [](const nlohmann::ordered_json& v) {
    return v.is_null() ? std::string("nan") : v.is_boolean() ? std::string(v.get<bool>() ? "1" : "0") : v.dump();
  };
  for (const auto& [key, value] : state.items()) {
    if (key == "configuration") {
      lines << "configuration " << value.size() << "\n";
      for (const auto& [k, v] : value.items()) lines << k << " = " << v.get<std::string>() << "\n";
    } else if (key == "profile_reference") {
      lines << "profile_reference " << value.size() << "\n";
      for (const auto& x : value) lines << number(x[0]) << " " << number(x[1]) << " " << number(x[2]) << "\n";
    } else {
      lines << key << " " << number(value) << "\n";
    }
  }
  const fs::path legacy_dir = fresh_dir("legacy_file");
  fs::create_directories(legacy_dir);
  io::save_checkpoint(legacy_dir / "consolidated.restart", reader.world(), lines.str());
  fs::copy_file(consolidated_specimen() / "history.csv", legacy_dir / "history.csv");

  std::string histories[2];
  const fs::path sources[2] = {file, legacy_dir / "consolidated.restart"};
  for (int k = 0; k < 2; ++k) {
    const fs::path out = fresh_dir("legacy_shear_" + std::to_string(k));
    SimpleShearTest test(simple_shear_config(small_config()), out, log);
    test.record_configuration(small_config());
    test.load_restart(sources[k]);
    test.run();
    histories[k] = file_text(out / "history.csv");
  }
  CHECK(histories[0].size() > 1000);
  CHECK(histories[0] == histories[1]);
}

TEST_CASE("triaxial: the protocol's keys, a drained test that holds the confining stress, and a resume in each stage",
          "[resume][triaxial]") {
  io::Config keys(triaxial_schema());
  keys.set("specimen.balls_per_side", "6");
  keys.set("axial.target_strain", "0.01");
  keys.set("axial.every_strain", "0.001");
  keys.set("output.restart_every_steps", "10");  // a restart file at every chunk: the row of the chunk it ends must be in it
  keys.set("engine.threads", "1");
  const TriaxialConfig config = triaxial_config(keys);
  const auto run_to_end = [&](const std::filesystem::path& dir, const std::filesystem::path& from, std::int64_t stop_at_step) {
    std::ostringstream log;
    TriaxialTest test(config, dir, log);
    test.record_configuration(keys);
    if (stop_at_step > 0)  // a kill at that step, as far as the files can tell
      test.world().add_controller([stop_at_step](World& w) {
        if (w.step_count() == stop_at_step) throw std::runtime_error("stopped");
      });
    if (!from.empty()) test.load_restart(from);
    test.run();
    test.write_summary(keys.to_json());
  };
  const std::filesystem::path whole = fresh_dir("triaxial_whole");
  run_to_end(whole, {}, 0);
  const io::CsvData rows = io::read_csv(whole / "history.csv");
  REQUIRE(rows.rows.size() >= 8);
  // Drained: the lateral walls hold the confining stress within the servo's tolerance while the
  // axial stress rises; p and q as defined from the walls' stresses.
  for (const auto& r : rows.rows) {
    CHECK(r[rows.column("sigma_radial")] == Approx(100e3).epsilon(0.05));
    const double a = r[rows.column("sigma_axial")], lateral = r[rows.column("sigma_radial")];
    CHECK(r[rows.column("mean_stress")] == Approx((a + 2 * lateral) / 3).epsilon(1e-12));
    CHECK(r[rows.column("deviator_stress")] == Approx(a - lateral).epsilon(1e-12).margin(1e-9));
  }
  CHECK(rows.rows.back()[rows.column("axial_strain")] >= 0.01);
  CHECK(rows.rows.back()[rows.column("deviator_stress")] > 0.3 * 100e3);
  // Stopped in the isotropic and in the axial stage, resumed from restart.restart: the same history.
  const std::int64_t isotropic_end = static_cast<std::int64_t>(rows.rows.front()[rows.column("step")]);
  const std::int64_t axial_middle = static_cast<std::int64_t>(rows.rows[rows.rows.size() / 2][rows.column("step")]);
  for (const std::int64_t stop : {isotropic_end / 2 + 3, axial_middle + 3}) {
    DYNAMIC_SECTION("stopped at step " << stop) {
      const std::filesystem::path dir = fresh_dir("triaxial_" + std::to_string(stop));
      CHECK_THROWS_WITH(run_to_end(dir, {}, stop), Contains("stopped"));
      REQUIRE(std::filesystem::exists(dir / "restart.restart"));
      run_to_end(dir, dir / "restart.restart", 0);
      CHECK(dem::testing::file_text(dir / "history.csv") == dem::testing::file_text(whole / "history.csv"));
    }
  }
  // The confining stress is fixed once the isotropic stage has begun: a resume that changes it is refused.
  io::Config other = keys;
  other.set("isotropic.confining_stress", "2e5");
  std::ostringstream log;
  TriaxialTest test(triaxial_config(other), fresh_dir("triaxial_refused"), log);
  test.record_configuration(other);
  CHECK_THROWS_WITH(test.load_restart(whole / "consolidated.restart"),
                    Contains("isotropic.confining_stress = 2e+05 here, 1e+05 in the file") && !Contains("dem-consolidate"));
}

TEST_CASE("resume: a restart file whose cursor holds an absurd value is refused naming the key", "[resume][simple-shear]") {
  const fs::path file = consolidated_specimen() / "consolidated.restart";
  std::ostringstream log;
  SimpleShearTest reader(simple_shear_config(small_config()), fresh_dir("absurd_reader"), log);
  const auto state = nlohmann::ordered_json::parse(io::load_checkpoint(file, reader.world()));
  // Each with a valid checksum: what a program (or a hand) could write into a file.
  struct Case {
    const char* key;
    double value;
    const char* expect;
  };
  const Case cases[] = {{"stage", 7, "restart file: stage = 7"},
                        {"leg", 99, "restart file: leg = 99"},
                        {"path_strain", 1e308, "restart file: path_strain = 1e+308"},
                        {"ball_count", -5, "restart file: ball_count = -5"},
                        {"consolidation_start_step", 0.5, "restart file: consolidation_start_step = 0.5"}};
  for (const Case& c : cases) {
    nlohmann::ordered_json changed = state;
    REQUIRE(changed.contains(c.key));
    changed[c.key] = c.value;
    const fs::path dir = fresh_dir(std::string("absurd_") + c.key);
    fs::create_directories(dir);
    io::save_checkpoint(dir / "consolidated.restart", reader.world(), changed.dump());
    fs::copy_file(consolidated_specimen() / "history.csv", dir / "history.csv");
    SimpleShearTest test(simple_shear_config(small_config()), fresh_dir(std::string("absurd_out_") + c.key), log);
    test.record_configuration(small_config());
    CHECK_THROWS_WITH(test.load_restart(dir / "consolidated.restart"), Contains(c.expect));
  }
}
