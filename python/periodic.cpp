// The periodic cell through Python: the cell, the World's methods that set it, its stress, strain
// and packing, and its servo (docs/model.md 13). A component of the servo is named by a string,
// "xx" "yy" "zz" "yz" "xz" "xy".
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <dem/base/errors.hpp>
#include <dem/boundary/periodic_cell.hpp>
#include <dem/control/cell_servo.hpp>
#include <dem/core/world.hpp>
#include <dem/measure/cell_state.hpp>
#include <dem/measure/cell_stress.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

namespace {

CellComponent component_named(const std::string& name) {
  for (int a = 0; a < 6; ++a)
    if (name == to_string(static_cast<CellComponent>(a))) return static_cast<CellComponent>(a);
  require(false, "cell component", name, "one of xx, yy, zz, yz, xz, xy");
  return CellComponent::xx;
}

/// A Python callable of the time as a target path, called with the GIL (the World steps without it).
std::function<double(double)> path_of(py::function f) {
  auto fn = std::make_shared<py::object>(std::move(f));
  return [fn](double time) {
    py::gil_scoped_acquire gil;
    return (*fn)(time).cast<double>();
  };
}

}  // namespace

void bind_periodic(py::module_& m, py::class_<World>& world) {
  py::class_<PeriodicCell>(m, "PeriodicCell",
                           "A periodic cell (docs/model.md 13): edge vectors as the columns of its matrix h (m), from "
                           "its origin, deformed by its velocity gradient L (1/s), h' = L h")
      .def(py::init<const Mat3&, const Vec3&>(), py::arg_v("matrix", Mat3::Identity(), "identity"), py::arg_v("origin", Vec3::Zero(), "(0, 0, 0)"),
           "A cell with edge vectors the columns of `matrix` (m, det > 0) from `origin` (m), at rest")
      .def_static("box", &PeriodicCell::box, py::arg("low"), py::arg("high"), "An axis-aligned box from low to high (m)")
      .def_property_readonly("matrix", &PeriodicCell::matrix, "h (m), edge vectors as columns")
      .def_property_readonly("inverse", &PeriodicCell::inverse, "h^-1 (1/m)")
      .def_property_readonly("origin", &PeriodicCell::origin, "The corner the edges start from (m)")
      .def_property_readonly("volume", &PeriodicCell::volume, "det h (m^3)")
      .def_property_readonly("widths", &PeriodicCell::widths, "The distances between opposite faces (m)")
      .def("set_matrix", &PeriodicCell::set_matrix, py::arg("matrix"), "Replaces h (m, det > 0)")
      .def_property("velocity_gradient", &PeriodicCell::velocity_gradient, &PeriodicCell::set_velocity_gradient,
                    "L (1/s): the cell deforms as h' = L h")
      .def_property("tilt_remap", &PeriodicCell::tilt_remap, &PeriodicCell::set_tilt_remap,
                    "Whether a World re-maps the cell when sheared past its tilt limit (default True)")
      .def("reduced", &PeriodicCell::reduced, py::arg("x"), "Reduced coordinates h^-1 (x - origin) of a point x (m)")
      .def("wrapped", &PeriodicCell::wrapped, py::arg("x"), "The point x (m) brought into the cell by whole cells")
      .def("image_shift", &PeriodicCell::image_shift, py::arg("n"), "h n (m), the shift of image n (three integers)")
      .def("image_velocity_shift", &PeriodicCell::image_velocity_shift, py::arg("n"),
           "L h n (m/s), the velocity shift of image n (Lees-Edwards)");

  world
      .def("set_periodic_cell", &World::set_periodic_cell, py::arg("cell"),
           "Puts the particles in a periodic cell (docs/model.md 13); refused with walls, clumps or several processes")
      .def_property_readonly("periodic_cell",
                             [](const World& w) -> std::optional<PeriodicCell> {
                               if (const PeriodicCell* cell = w.periodic_cell()) return *cell;
                               return std::nullopt;
                             },
                             "A copy of the World's periodic cell, or None")
      .def("set_velocity_gradient", &World::set_velocity_gradient, py::arg("velocity_gradient"),
           "The periodic cell's velocity gradient L (1/s) from the next step on");

  m.def("cell_stress",
        [](const World& w) {
          const measure::CellStress s = measure::cell_stress(w);
          py::dict d;
          d["stress"] = s.stress, d["contact_part"] = s.contact_part, d["kinetic_part"] = s.kinetic_part;
          d["volume"] = s.volume;
          return d;
        },
        py::arg("world"),
        "The periodic cell's stress over the last step's contacts (docs/model.md 13), as a dict: stress, "
        "contact_part, kinetic_part (Pa, 3 x 3, tension positive) and volume (m^3)");
  m.def("cell_strain",
        [](const Mat3& reference, const Mat3& now) {
          const measure::CellStrain s = measure::cell_strain(reference, now);
          py::dict d;
          d["deformation_gradient"] = s.deformation_gradient, d["small_strain"] = s.small_strain;
          d["logarithmic_strain"] = s.logarithmic_strain, d["rotation"] = s.rotation;
          d["volumetric_strain"] = s.volumetric_strain;
          return d;
        },
        py::arg("reference"), py::arg("now"),
        "The strain from the cell matrix `reference` to `now` (m), as a dict: deformation_gradient F, small_strain, "
        "logarithmic_strain (ln V, F = V R), rotation R and volumetric_strain ln det F (extension positive)");
  m.def("cell_packing",
        [](const World& w) {
          const measure::CellPacking s = measure::cell_packing(w);
          py::dict d;
          d["balls"] = s.balls, d["volume"] = s.volume, d["porosity"] = s.porosity, d["void_ratio"] = s.void_ratio;
          d["contacts"] = s.contacts, d["coordination_number"] = s.coordination_number;
          d["mechanical_coordination_number"] = s.mechanical_coordination_number;
          return d;
        },
        py::arg("world"),
        "The periodic cell's packing, as a dict: balls, volume (m^3), porosity, void_ratio, contacts, "
        "coordination_number and mechanical_coordination_number (without rattlers)");

  py::class_<CellServo, std::shared_ptr<CellServo>>(
      m, "CellServo", "Holds stresses or rates on the periodic cell's six components (docs/model.md 13)")
      .def("set_stress", [](CellServo& s, const std::string& c, double stress) { s.set_stress(component_named(c), stress); },
           py::arg("component"), py::arg("stress"), "Holds component ('xx' ... 'xy') at stress (Pa, compression positive)")
      .def("set_rate", [](CellServo& s, const std::string& c, double rate) { s.set_rate(component_named(c), rate); },
           py::arg("component"), py::arg("rate"), "Prescribes component's rate L_ab (1/s)")
      .def("set_stress_path",
           [](CellServo& s, const std::string& c, py::function f) { s.set_stress_path(component_named(c), path_of(std::move(f))); },
           py::arg("component"), py::arg("stress"), "Holds component at stress(time) (Pa, time in s), evaluated every step")
      .def("set_rate_path",
           [](CellServo& s, const std::string& c, py::function f) { s.set_rate_path(component_named(c), path_of(std::move(f))); },
           py::arg("component"), py::arg("rate"), "Prescribes component's rate rate(time) (1/s, time in s)")
      .def("hold_volume", [](CellServo& s, const std::string& c) { s.hold_volume(component_named(c)); },
           py::arg("component"), "The normal component ('xx', 'yy' or 'zz') whose rate keeps the volume")
      .def_property_readonly("settled", &CellServo::settled,
                             "True once every stress-controlled component has been held for settle_steps steps")
      .def_property_readonly("stress", [](const CellServo& s) { return s.stress().stress; },
                             "The cell stress of the last step (Pa, tension positive)");

  m.def("add_cell_servo",
        [](World& w, const std::map<std::string, double>& stress, const std::map<std::string, double>& rate,
           double max_rate, double relaxation, double settle_tolerance, int settle_steps) {
          CellServoSettings s;
          for (const auto& [name, value] : stress) {
            const auto a = static_cast<std::size_t>(component_named(name));
            s.stress_controlled[a] = true, s.target[a] = value;
          }
          for (const auto& [name, value] : rate) {
            const auto a = static_cast<std::size_t>(component_named(name));
            require(!s.stress_controlled[a], "cell component " + name, "given a stress and a rate", "one of the two");
            s.target[a] = value;
          }
          s.max_rate = max_rate, s.relaxation = relaxation, s.settle_tolerance = settle_tolerance;
          s.settle_steps = settle_steps;
          return add_cell_servo(w, s);
        },
        py::arg("world"), py::arg("stress") = std::map<std::string, double>{},
        py::arg("rate") = std::map<std::string, double>{}, py::arg("max_rate"), py::arg("relaxation") = 0.5,
        py::arg("settle_tolerance") = 0.01, py::arg("settle_steps") = 100,
        "A servo on the World's periodic cell, run every step.\n\n"
        "Args:\n"
        "    world: a World with a periodic cell.\n"
        "    stress: {component: stress (Pa, compression positive)} for the components held at a stress.\n"
        "    rate: {component: rate L_ab (1/s)}; components in neither dict have rate 0.\n"
        "    max_rate: cap on a stress-held component's rate (1/s, > 0).\n"
        "    relaxation: fraction of a stress error removed per step, in (0, 1].\n"
        "    settle_tolerance: relative error counted as held.\n"
        "    settle_steps: steps held in a row for settled.");
}

}  // namespace dem::python
