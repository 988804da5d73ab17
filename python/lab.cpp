// The lab protocols from Python: the NGI simple-shear test and the cyclic test, configured from a
// dict (nested {"specimen": {"diameter": 0.03}} or flat {"specimen.diameter": 0.03}) over a preset,
// exactly as the apps read --preset and --set; results as NumPy arrays. Stages run with the GIL
// released; progress lines go to the process's standard output (or nowhere with quiet=True).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <iostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/csv.hpp>
#include <dem/lab/protocols/cyclic_shear.hpp>
#include <dem/lab/protocols/simple_shear.hpp>

#include "bindings.hpp"

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

io::Config configuration(io::Schema schema, const std::string& preset, const py::dict& values) {
  io::Config config(schema);
  if (!preset.empty())
    for (const auto& [key, value] : lab::preset_values(preset)) config.set(key, value);
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

struct SimpleShear {
  io::Config config;
  std::ostringstream quiet_log;
  std::unique_ptr<lab::SimpleShearTest> test;
  SimpleShear(const py::dict& values, const std::filesystem::path& out, const std::string& preset, bool quiet)
      : config(configuration(lab::simple_shear_schema(), preset, values)) {
    test = std::make_unique<lab::SimpleShearTest>(lab::simple_shear_config(config), out, quiet ? static_cast<std::ostream&>(quiet_log) : std::cout);
    test->record_configuration(config);
  }
  template <class F>
  void released(F f) {
    py::gil_scoped_release release;
    f();
  }
};

struct CyclicShear {
  io::Config config;  // the specimen's keys and the [cyclic] ones, for summary.json
  std::ostringstream quiet_log;
  std::unique_ptr<lab::CyclicShearTest> test;
  CyclicShear(SimpleShear& specimen, const py::dict& values, bool quiet) : config(lab::cyclic_shear_schema()) {
    const io::Schema specimen_keys = lab::simple_shear_schema();
    for (const io::KeySpec& k : specimen_keys.keys()) config.set(k.key, specimen.config.exact_text(k.key));
    py::dict cyclic;
    for (const auto& [k, v] : values) {
      const std::string key = k.cast<std::string>();
      cyclic[py::str(key.rfind("cyclic.", 0) == 0 ? key : "cyclic." + key)] = v;
    }
    apply(config, cyclic, "");
    (void)quiet;  // the specimen's run holds the log
    test = std::make_unique<lab::CyclicShearTest>(specimen.test->resumable_run(), specimen.test->specimen(),
                                                  lab::cyclic_shear_config(config));
  }
};

}  // namespace

void bind_lab(py::module_& m) {
  py::class_<SimpleShear>(m, "SimpleShear", "The NGI-type simple-shear test of the study (dem-simple-shear)")
      .def(py::init<const py::dict&, const std::filesystem::path&, const std::string&, bool>(), py::arg("config") = py::dict(),
           py::arg("out") = "runs/simple-shear", py::arg("preset") = "4D", py::arg("quiet") = false,
           "config: keys of dem-simple-shear --print-config over the preset; out: the output folder")
      .def("open_outputs", [](SimpleShear& s, bool replace) { s.test->open_outputs({.replace = replace, .program = "libdem (Python)",
                                                                                   .more_run_files = lab::CyclicShearTest::run_files()}); },
           py::arg("replace") = false, "Claims the output folder (replace: remove another run's results)")
      .def("load_restart", [](SimpleShear& s, const std::filesystem::path& f) { s.test->load_restart(f); }, py::arg("file"))
      .def("generate", [](SimpleShear& s) { s.released([&] { s.test->generate(); }); })
      .def("consolidate", [](SimpleShear& s) { s.released([&] { s.test->consolidate(); }); })
      .def("shear", [](SimpleShear& s) { s.released([&] { s.test->shear(); }); })
      .def("run", [](SimpleShear& s) { s.released([&] { s.test->run(); }); }, "Whatever remains of generate, consolidate and shear")
      .def("write_summary", [](SimpleShear& s) { s.test->write_summary(s.config.to_json()); })
      .def("history", [](SimpleShear& s) {
             const io::CsvData d = io::read_csv(s.test->output_folder() / "history.csv", io::Missing::Allowed);
             return columns(d.columns, d.rows);
           }, "history.csv as {column: array}")
      .def_property_readonly("stage", [](const SimpleShear& s) { return static_cast<int>(s.test->stage()); },
                             "0 empty, 1 generated, 2 consolidated, 3 shearing, 4 done")
      .def_property_readonly("consolidated_height", [](const SimpleShear& s) { return s.test->consolidated_height(); })
      .def_property_readonly("ball_count", [](const SimpleShear& s) { return s.test->ball_count(); })
      .def_property_readonly("world", [](SimpleShear& s) -> World& { return s.test->world(); }, py::return_value_policy::reference_internal)
      .def_property_readonly("configuration", [](const SimpleShear& s) { return s.config.to_ini(); }, "every key, as INI text");

  py::class_<CyclicShear>(m, "CyclicShear", "Cyclic simple shear on a consolidated SimpleShear specimen (dem-cyclic-shear)")
      .def(py::init<SimpleShear&, const py::dict&, bool>(), py::arg("specimen"), py::arg("config") = py::dict(),
           py::arg("quiet") = false, py::keep_alive<1, 2>(), "config: the [cyclic] keys, with or without the 'cyclic.' prefix")
      .def("run", [](CyclicShear& c) {
             py::gil_scoped_release release;
             c.test->run();
           })
      .def("write_summary", [](CyclicShear& c) { c.test->write_summary(c.config.to_json()); })
      .def("history", [](const CyclicShear& c) { return columns(c.test->history().columns(), c.test->history().rows()); })
      .def("cycles", [](const CyclicShear& c) {
             std::vector<std::vector<double>> rows;
             for (const lab::CycleRow& r : c.test->cycles().cycles()) rows.push_back(lab::CycleLog::values(r));
             return columns(lab::CycleLog::columns(), rows);
           })
      .def_property_readonly("outcome", [](const CyclicShear& c) {
             const lab::CyclicOutcome& o = c.test->outcome();
             py::dict d;
             d["cycles"] = o.cycles, d["stop"] = o.stop, d["cycles_to_ru"] = o.cycles_to_ru;
             d["cycles_to_da_strain"] = o.cycles_to_da_strain, d["vertical_stress_initial"] = o.vertical_stress_initial;
             d["consolidated_height"] = o.consolidated_height, d["period"] = o.period;
             return d;
           });
}

}  // namespace dem::python
