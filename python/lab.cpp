// The lab protocols from Python: the NGI simple-shear test, the cyclic test and the periodic
// cell's element tests, configured from a dict (nested {"specimen": {"diameter": 0.03}} or flat {"specimen.diameter": 0.03}) over a preset,
// exactly as the apps read --preset and --set; results as NumPy arrays. Stages run with the GIL
// released; progress lines go to Python's sys.stdout, to a callable or nowhere (progress.hpp).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/cyclic_shear.hpp>
#include <dem/lab/protocols/element_test.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

#include "bindings.hpp"
#include "progress.hpp"

namespace py = pybind11;

namespace dem::python {

namespace {

// A Python value as the text a configuration file would hold (reals exactly: repr round-trips).
std::string config_text(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) return py::repr(v).cast<std::string>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v) || py::isinstance<py::array>(v)) {
    std::string out;
    for (const py::handle item : v) out += (out.empty() ? "" : ",") + config_text(py::float_(py::reinterpret_borrow<py::object>(item)));
    return out;
  }
  throw InputError("configuration value " + py::repr(v).cast<std::string>() + ": allowed a number, a boolean, a string or a list of numbers");
}

void apply(io::Config& config, const py::dict& values, const std::string& section) {
  for (const auto& [k, v] : values) {
    const std::string key = section.empty() ? k.cast<std::string>() : section + "." + k.cast<std::string>();
    if (py::isinstance<py::dict>(v) && section.empty()) apply(config, v.cast<py::dict>(), key);
    else config.set(key, config_text(v));
  }
}

// A preset is the simple-shear app's; a protocol with fewer keys (the element test) takes the ones
// it has (its material), as its app does.
io::Config configuration(io::Schema schema, const std::string& preset, const py::dict& values) {
  io::Config config(schema);
  if (!preset.empty())
    for (const auto& [key, value] : lab::preset_values(preset))
      if (config.schema().find(key) != nullptr) config.set(key, value);
  apply(config, values, "");
  return config;
}

py::dict columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& rows) {
  py::dict d;
  for (std::size_t c = 0; c < names.size(); ++c) {
    py::array_t<double> a(static_cast<py::ssize_t>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) a.mutable_at(static_cast<py::ssize_t>(r)) = rows[r][c];
    d[py::str(names[c])] = a;
  }
  return d;
}

/// Runs `f` (a stage of a test) with the GIL released, its progress lines going to `log`.
template <class F>
void released(ProgressStream& log, F f) {
  log.stream();  // ready again if an exception stopped the last stage
  {
    py::gil_scoped_release release;
    f();
  }
  log.finish();
}

struct SimpleShear {
  io::Config config;
  ProgressStream log;
  std::unique_ptr<lab::SimpleShearTest> test;
  SimpleShear(const py::dict& values, const std::filesystem::path& out, const std::string& preset, bool quiet,
              const py::object& progress)
      : config(configuration(lab::simple_shear_schema(), preset, values)), log(progress, quiet, "SimpleShear") {
    test = std::make_unique<lab::SimpleShearTest>(lab::simple_shear_config(config), out, log.stream());
    test->record_configuration(config);
  }
};

struct CyclicShear {
  io::Config config;  // the specimen's keys and the [cyclic] ones, for summary.json
  ProgressStream log;
  std::unique_ptr<lab::CyclicShearTest> test;
  CyclicShear(SimpleShear& specimen, const py::dict& values, bool quiet, const py::object& progress)
      : config(lab::cyclic_shear_schema()), log(progress, quiet, "CyclicShear") {
    const io::Schema specimen_keys = lab::simple_shear_schema();
    for (const io::KeySpec& k : specimen_keys.keys()) config.set(k.key, specimen.config.exact_text(k.key));
    py::dict cyclic;
    for (const auto& [k, v] : values) {
      const std::string key = k.cast<std::string>();
      cyclic[py::str(key.rfind("cyclic.", 0) == 0 ? key : "cyclic." + key)] = v;
    }
    apply(config, cyclic, "");
    // The cyclic stages on the specimen's run and parts; its lines (and the specimen's after it) go
    // to this test's progress.
    test = std::make_unique<lab::CyclicShearTest>(specimen.test->resumable_run(), specimen.test->specimen(),
                                                  lab::cyclic_shear_config(config), &log.stream());
  }
};

struct ElementTest {
  io::Config config;
  ProgressStream log;
  std::unique_ptr<lab::ElementTest> test;
  ElementTest(const py::dict& values, const std::filesystem::path& out, const std::string& preset, const py::object& progress)
      : config(configuration(lab::element_test_schema(), preset, values)), log(progress, false, "ElementTest") {
    test = std::make_unique<lab::ElementTest>(lab::element_test_config(config), out, log.stream());
    test->record_configuration(config);
  }
};

}  // namespace

void bind_lab(py::module_& m) {
  py::class_<SimpleShear>(m, "SimpleShear",
                          "The NGI-type simple-shear test of the study, as dem-simple-shear runs it: a specimen made by radius\n"
                          "expansion in a stack of rings, consolidated by the top plate's servo, then sheared; history.csv,\n"
                          "summary.json and the restart files go to the output folder. Each stage runs with the GIL released.")
      .def(py::init<const py::dict&, const std::filesystem::path&, const std::string&, bool, const py::object&>(),
           py::arg("config") = py::dict(), py::arg("out") = "runs/simple-shear", py::arg("preset") = "4D", py::arg("quiet") = false,
           py::arg("progress") = py::none(),
           "Sets up the test; nothing is simulated yet.\n\n"
           "Args:\n"
           "    config: keys of `dem-simple-shear --print-config` over the preset, nested ({\"shear\": {\"target_strain\": 0.1}})\n"
           "        or flat ({\"shear.target_strain\": 0.1}); values in the keys' units (SI: m, kg, s, N, Pa).\n"
           "    out: the output folder.\n"
           "    preset: '1D', '2D' or '4D' (the study's particle-size scales), or '' for the keys' defaults.\n"
           "    quiet: True is progress=False (the older spelling).\n"
           "    progress: where the progress lines go (stage, strain, rate, time left, as the apps print them):\n"
           "        None (the default) sys.stdout unless quiet, True sys.stdout, False nowhere, or a callable taking\n"
           "        each line (str). Ctrl-C, or an exception the callable raises, stops the stage at a line.\n\n"
           "Raises:\n"
           "    ValueError: an unknown key or a bad value, named with what is allowed.")
      .def("open_outputs", [](SimpleShear& s, bool replace) { s.test->open_outputs({.replace = replace, .program = "libdem (Python)",
                                                                                   .more_run_files = lab::CyclicShearTest::run_files()}); },
           py::arg("replace") = false,
           "Claims the output folder (the first stage does it otherwise).\n\n"
           "Args:\n"
           "    replace: remove another run's results from the folder instead of refusing it.")
      .def("load_restart", [](SimpleShear& s, const std::filesystem::path& f) { s.test->load_restart(f); }, py::arg("file"),
           "Continues from a restart file, anywhere in the generation, consolidation or shear; once, before any stage.\n\n"
           "Args:\n"
           "    file: a .restart file of dem-simple-shear or of this class (keys that would change what is done are refused).")
      .def("generate", [](SimpleShear& s) { released(s.log, [&] { s.test->generate(); }); },
           "Makes the specimen: radius expansion in the ring stack, then the friction schedule (docs/model.md 7).")
      .def("consolidate", [](SimpleShear& s) { released(s.log, [&] { s.test->consolidate(); }); },
           "Servo consolidation to the vertical stress, until stress and kinetic energy have settled.")
      .def("shear", [](SimpleShear& s) { released(s.log, [&] { s.test->shear(); }); },
           "All shear legs, with history, fabric, snapshots and restart files in the output folder.")
      .def("run", [](SimpleShear& s) { released(s.log, [&] { s.test->run(); }); }, "Whatever remains of generate, consolidate and shear")
      .def("write_summary", [](SimpleShear& s) { s.test->write_summary(s.config.to_json()); },
           "Writes summary.json: counts, porosity, ASTM D6528 ratios, peak and final values, timing, the configuration.")
      .def("history", [](SimpleShear& s) {
             const io::CsvData d = io::read_csv(s.test->output_folder() / "history.csv", io::Missing::Allowed);
             return columns(d.columns, d.rows);
           }, "history.csv as {column: array}, in the columns' units (SI; strains and ratios dimensionless)")
      .def_property_readonly("stage", [](const SimpleShear& s) { return static_cast<int>(s.test->stage()); },
                             "0 empty, 1 generated, 2 consolidated, 3 shearing, 4 done")
      .def_property_readonly("consolidated_height", [](const SimpleShear& s) { return s.test->consolidated_height(); },
                             "m, the specimen's height after consolidation (0 before)")
      .def_property_readonly("ball_count", [](const SimpleShear& s) { return s.test->ball_count(); }, "balls in the specimen")
      .def_property_readonly("world", [](SimpleShear& s) -> World& { return s.test->world(); }, py::return_value_policy::reference_internal,
                             "the test's World (its plates, servo and rings stay the test's)")
      .def_property_readonly("configuration", [](const SimpleShear& s) { return s.config.to_ini(); }, "every key, as INI text");

  py::class_<CyclicShear>(m, "CyclicShear",
                          "Cyclic simple shear on a consolidated SimpleShear specimen, as dem-cyclic-shear runs it: a static\n"
                          "stage, the cyclic stage (stress or strain control along a path), a post-cyclic shear; outputs go to\n"
                          "the specimen's folder (docs/cyclic-shear.md).")
      .def(py::init<SimpleShear&, const py::dict&, bool, const py::object&>(), py::arg("specimen"), py::arg("config") = py::dict(),
           py::arg("quiet") = false, py::arg("progress") = py::none(), py::keep_alive<1, 2>(),
           "Sets up the cyclic test on a consolidated specimen (stage 2).\n\n"
           "Args:\n"
           "    specimen: a SimpleShear after consolidate().\n"
           "    config: the [cyclic] keys of `dem-cyclic-shear --print-config`, with or without the 'cyclic.' prefix\n"
           "        (csr, max_cycles, path, ...), in the keys' units (SI).\n"
           "    quiet: True is progress=False (the older spelling).\n"
           "    progress: None (the default) sys.stdout unless quiet, True sys.stdout, False nowhere, or a callable\n"
           "        taking each line (str). Ctrl-C, or an exception the callable raises, stops the run at a line.\n\n"
           "Raises:\n"
           "    ValueError: an unknown key or a bad value, named with what is allowed.")
      .def("run", [](CyclicShear& c) { released(c.log, [&] { c.test->run(); }); }, "The static, cyclic and post-cyclic stages with their outputs, then final.restart.")
      .def("write_summary", [](CyclicShear& c) { c.test->write_summary(c.config.to_json()); },
           "Writes summary.json: the specimen, the cyclic settings, the outcome, timing and the configuration.")
      .def("history", [](const CyclicShear& c) { return columns(c.test->history().columns(), c.test->history().rows()); },
           "cyclic_history.csv so far as {column: array} (SI units; phase 0 static, 1 cyclic, 2 post-cyclic)")
      .def("cycles", [](const CyclicShear& c) {
             std::vector<std::vector<double>> rows;
             for (const lab::CycleRow& r : c.test->cycles().cycles()) rows.push_back(lab::CycleLog::values(r));
             return columns(lab::CycleLog::columns(), rows);
           }, "One row per cycle begun as {column: array}: cycle, stress_max/min (Pa), strain_max/min and\n"
              "double_amplitude_strain (-), pore_pressure_ratio_max/end (-), energy (J/m^3), coordination numbers,\n"
              "vertical_stress (Pa), non_coaxiality_deg (deg), complete (1 when the cycle has ended)")
      .def_property_readonly("outcome", [](const CyclicShear& c) {
             const lab::CyclicOutcome& o = c.test->outcome();
             py::dict d;
             d["cycles"] = o.cycles, d["stop"] = o.stop, d["cycles_to_ru"] = o.cycles_to_ru;
             d["cycles_to_da_strain"] = o.cycles_to_da_strain, d["vertical_stress_initial"] = o.vertical_stress_initial;
             d["consolidated_height"] = o.consolidated_height, d["period"] = o.period;
             return d;
           }, "How the cyclic stage ended: cycles (N), stop (the criterion), cycles_to_ru and cycles_to_da_strain (N, NaN:\n"
              "never), vertical_stress_initial (Pa), consolidated_height (m), period (s)");

  py::class_<ElementTest>(m, "ElementTest",
                          "An element test in a periodic cell, as dem-element-test runs it (docs/periodic.md): a specimen of a\n"
                          "preset's balls compressed isotropically by the cell, then the test's path (isotropic, triaxial drained\n"
                          "or undrained, simple shear drained or at constant volume, cyclic simple shear) by the cell's velocity\n"
                          "gradient; history.csv, summary.json and the restart files go to the output folder. Runs with the GIL\n"
                          "released.")
      .def(py::init<const py::dict&, const std::filesystem::path&, const std::string&, const py::object&>(),
           py::arg("config") = py::dict(), py::arg("out") = "runs/element-test", py::arg("preset") = "4D",
           py::arg("progress") = py::none(),
           "Sets up the test; nothing is simulated yet.\n\n"
           "Args:\n"
           "    config: keys of `dem-element-test --print-config` over the preset's material, nested\n"
           "        ({\"element\": {\"test\": \"triaxial-drained\"}}) or flat ({\"element.balls\": 500}); SI units.\n"
           "    out: the output folder.\n"
           "    preset: '1D', '2D' or '4D' (the study's grading scale and ball-ball contact set), or '' for the keys' defaults.\n"
           "    progress: where the progress lines go: None (the default) or True sys.stdout, False nowhere, or a\n"
           "        callable taking each line (str). Ctrl-C, or an exception the callable raises, stops the run at a line.\n\n"
           "Raises:\n"
           "    ValueError: an unknown key or a bad value, named with what is allowed.")
      .def("open_outputs", [](ElementTest& e, bool replace) { e.test->open_outputs({.replace = replace, .program = "libdem (Python)"}); },
           py::arg("replace") = false,
           "Claims the output folder (run() does it otherwise).\n\n"
           "Args:\n"
           "    replace: remove the files another run wrote there (its manifest.json) instead of refusing the folder.")
      .def("load_restart", [](ElementTest& e, const std::filesystem::path& f) { e.test->load_restart(f); }, py::arg("file"),
           "Continues from a restart file of this test, in any stage; once, before run().\n\n"
           "Args:\n"
           "    file: a .restart file of dem-element-test or of this class (keys that would change what is done are refused).")
      .def("run", [](ElementTest& e) { released(e.log, [&] { e.test->run(); }); }, "Whatever remains of the compaction and the test's path, with its outputs, then final.restart.")
      .def("write_summary", [](ElementTest& e) { e.test->write_summary(e.config.to_json()); },
           "Writes summary.json: the specimen, the peak and the end (q/p, void ratio, coordination), timing, the configuration.")
      .def("history", [](const ElementTest& e) {
             if (e.test->history().rows() == 0) return py::dict();
             const io::CsvTable& table = e.test->history().table();
             return columns(table.columns(), table.rows());
           },
           "history.csv so far as {column: array}, in the columns' units (SI; stresses compression positive, Pa)")
      .def_property_readonly("strain_rate", [](const ElementTest& e) { return e.test->strain_rate(); },
                             "1/s, the path's axial or shear rate (element.strain_rate, or from the inertial number)")
      .def_property_readonly("world", [](ElementTest& e) -> World& { return e.test->world(); }, py::return_value_policy::reference_internal,
                             "the test's World (its periodic cell and servo stay the test's)")
      .def_property_readonly("configuration", [](const ElementTest& e) { return e.config.to_ini(); }, "every key, as INI text");
}

}  // namespace dem::python
