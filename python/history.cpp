// A protocol's history from Python (lab/toolkit/history_log.hpp, lab/toolkit/uniformity_probe.hpp): a script
// registers its columns by name with the Python function that measures each, the C++ parts add
// theirs (the uniformity probe, the rings), and record() writes the row and saves the file. The
// parts keep references to the World and the cell they measure, so the log keeps them alive.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <dem/core/world.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/uniformity_probe.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

void bind_history(py::module_& m) {
  py::class_<lab::HistoryLog>(m, "HistoryLog", "history.csv whose columns the parts register by name (lab/toolkit/history_log.hpp)")
      .def(py::init<std::filesystem::path>(), py::arg("file"),
           "A log of the CSV file `file`, written by every record(); nothing is written before the first")
      .def("add", py::overload_cast<std::string, std::function<double()>>(&lab::HistoryLog::add), py::arg("name"), py::arg("value"),
           "One column: value() is called at every row (SI units by convention; ValueError for a name in use or with a comma)")
      .def("add",
           [](lab::HistoryLog& log, std::vector<std::string> names, const std::function<std::vector<double>()>& values) {
             log.add(std::move(names), [values](std::vector<double>& row) {
               const std::vector<double> v = values();
               row.insert(row.end(), v.begin(), v.end());
             });
           },
           py::arg("names"), py::arg("values"), "A group of columns: values() returns one number per name, in order")
      .def("before_row", &lab::HistoryLog::before_row, py::arg("prepare"),
           "prepare() is called once before the columns of every row (a measurement several columns read)")
      .def("record", &lab::HistoryLog::record, "Measures every column, appends the row and saves the file")
      .def("resume", &lab::HistoryLog::resume, py::arg("written"), py::arg("rows"),
           "Keeps the first `rows` rows of the history file `written` earlier, by column name (a column it lacks is NaN)")
      .def_property_readonly("columns", &lab::HistoryLog::columns, "The column names, in order")
      .def_property_readonly("rows", &lab::HistoryLog::rows, "Rows recorded (and resumed) so far")
      .def("last", &lab::HistoryLog::last, py::arg("column"), py::arg("fallback") = 0.0, "The named column of the last row")
      .def("table",
           [](const lab::HistoryLog& log) {
             const io::CsvTable& table = log.table();
             py::dict d;
             for (std::size_t c = 0; c < table.columns().size(); ++c) {
               py::array_t<double> a(static_cast<py::ssize_t>(table.rows().size()));
               for (std::size_t r = 0; r < table.rows().size(); ++r) a.mutable_at(static_cast<py::ssize_t>(r)) = table.rows()[r][c];
               d[py::str(table.columns()[c])] = a;
             }
             return d;
           },
           "The rows so far: {column: array}");

  py::class_<lab::UniformityProbe>(m, "UniformityProbe",
                                   "Displacement profile, its R^2 against uniform simple shear, layers and bin porosities (docs/model.md 8.1)")
      .def(py::init<const World&, const lab::ShearCell&, int>(), py::arg("world"), py::arg("cell"), py::arg("bins"),
           py::keep_alive<1, 2>(), py::keep_alive<1, 3>(), "A probe of `bins` height bins (>= 3) between the plates of `cell`")
      .def("add_columns", &lab::UniformityProbe::add_columns, py::arg("log"), py::arg("direction"), py::keep_alive<2, 1>(),
           "Adds profile_r2, the thirds' strains, plate displacements, layers, profile_u_* and profile_porosity_*; "
           "direction() gives the shear direction (a unit vector in x-y) at a row");
  m.def("add_ring_columns", &lab::add_ring_columns, py::arg("log"), py::arg("world"), py::arg("cell"), py::keep_alive<1, 2>(),
        py::keep_alive<1, 3>(), "ring_k_dx, ring_k_dy: each ring's horizontal displacement (m)");
}

}  // namespace dem::python
