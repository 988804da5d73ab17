// The lab toolkit from Python: the parts a protocol is written from (lab/toolkit/shear_cell.hpp,
// lab/toolkit/radius_expansion.hpp, lab/toolkit/friction_schedule.hpp, lab/toolkit/consolidation.hpp, lab/toolkit/shear_leg.hpp,
// lab/toolkit/grading.hpp, lab/toolkit/cyclic_path.hpp), on a World the script owns. The names and fields are the C++ ones; random
// draws go through libdem.Random, the generator the C++ parts take, so that a script and a C++
// program with the same seed make the same specimen. consolidate() releases the GIL and takes it back only for its callback.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <random>

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/toolkit/consolidation.hpp>
#include <dem/lab/toolkit/cyclic_path.hpp>
#include <dem/lab/toolkit/friction_schedule.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/horizontal_drive.hpp>
#include <dem/lab/toolkit/radius_expansion.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/shear_leg.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

namespace {

std::vector<double> doubles(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  return std::vector<double>(a.data(), a.data() + a.size());
}

py::array_t<double> rows(const std::vector<Vec3>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (py::ssize_t a = 0; a < 3; ++a) r(static_cast<py::ssize_t>(i), a) = points[i][a];
  return out;
}

void bind_cell(py::module_& m) {
  py::enum_<lab::RingVertical>(m, "RingVertical", "How the rings move vertically once the specimen is made (docs/model.md 4)")
      .value("FIXED", lab::RingVertical::Fixed)
      .value("FOLLOW", lab::RingVertical::Follow)
      .value("PRESCRIBED", lab::RingVertical::Prescribed)
      .value("FREE", lab::RingVertical::Free)
      .value("SAND", lab::RingVertical::Sand);
  py::class_<lab::ShearCellSpec>(m, "ShearCellSpec", "Geometry of an NGI cell (m, kg/m^3); z up, bottom plate at z = 0")
      .def(py::init<>())
      .def_readwrite("diameter", &lab::ShearCellSpec::diameter)
      .def_readwrite("height", &lab::ShearCellSpec::height)
      .def_readwrite("pebble_diameter", &lab::ShearCellSpec::pebble_diameter)
      .def_readwrite("ring_gap", &lab::ShearCellSpec::ring_gap)
      .def_readwrite("ring_density", &lab::ShearCellSpec::ring_density)
      .def_readwrite("stack_height", &lab::ShearCellSpec::stack_height)
      .def_readwrite("max_opening", &lab::ShearCellSpec::max_opening)
      .def_readwrite("rings", &lab::ShearCellSpec::rings);
  py::class_<lab::ShearCell>(m, "ShearCell", "The plates and rings of a cell in a World")
      .def_readonly("bottom", &lab::ShearCell::bottom)
      .def_readonly("top", &lab::ShearCell::top)
      .def_readonly("first_ring", &lab::ShearCell::first_ring)
      .def_readonly("ring_count", &lab::ShearCell::ring_count)
      .def_readonly("radius", &lab::ShearCell::radius)
      .def_readonly("built_height", &lab::ShearCell::built_height)
      .def_readonly("area", &lab::ShearCell::area)
      .def_readonly("pebble_radius", &lab::ShearCell::pebble_radius)
      .def_readonly("rings", &lab::ShearCell::rings)
      .def("plate_gap", &lab::ShearCell::plate_gap, py::arg("world"), "m, top minus bottom plate height now");
  m.def("build_shear_cell", &lab::build_shear_cell, py::arg("world"), py::arg("spec"), "Adds the plates and the ring stack (rings held)");
  m.def("move_rings", &lab::move_rings, py::arg("world"), py::arg("cell"), py::arg("specimen_made"),
        "Sets the rings' velocities for this step from the plates' (call it from a controller, after the servo)");
  m.def("release_rings", &lab::release_rings, py::arg("world"), py::arg("cell"));
  m.def("plate_damping_frame", &lab::plate_damping_frame, py::arg("world"), py::arg("cell"),
        "the plates' affine field, for World.set_damping_frame while the plates shear");
  m.def("ring_lateral_stress", &lab::ring_lateral_stress, py::arg("world"), py::arg("cell"), "Pa, radial push of the sand on the rings");
  m.def("keep_plate_gap", &lab::keep_plate_gap, py::arg("world"), py::arg("cell"), py::arg("min_gap"),
        "Caps the top plate's downward velocity so that the plates stay min_gap (m) apart (after the servo)");
  m.def("specimen_porosity", &lab::specimen_porosity, py::arg("world"), py::arg("cell"), "1 - ball volume / (area x plate gap)");
}

void bind_specimen(py::module_& m) {
  py::class_<std::mt19937_64>(m, "Random", "The 64-bit Mersenne Twister the C++ parts draw from")
      .def(py::init<std::uint64_t>(), py::arg("seed"));
  py::class_<lab::Grading>(m, "Grading", "Diameters uniform by number on [d_min, d_max] x scale (m)")
      .def(py::init<>())
      .def_readwrite("d_min", &lab::Grading::d_min)
      .def_readwrite("d_max", &lab::Grading::d_max)
      .def_readwrite("scale", &lab::Grading::scale)
      .def("smallest", &lab::Grading::smallest)
      .def("largest", &lab::Grading::largest);
  m.def("sample_diameters", [](const lab::Grading& g, double solid_volume, std::mt19937_64& rng) {
          const std::vector<double> d = lab::sample_diameters(g, solid_volume, rng);
          return py::array_t<double>(static_cast<py::ssize_t>(d.size()), d.data());
        }, py::arg("grading"), py::arg("solid_volume"), py::arg("rng"), "Diameters (m) until their volume reaches solid_volume (m^3)");
  py::class_<lab::Cylinder>(m, "Cylinder", "A vertical cylinder on z = 0 about the z axis (m)")
      .def(py::init([](double radius, double height) { return lab::Cylinder{radius, height}; }), py::arg("radius"), py::arg("height"))
      .def_readwrite("radius", &lab::Cylinder::radius)
      .def_readwrite("height", &lab::Cylinder::height);
  m.def("place_without_overlap",
        [](const lab::Cylinder& cavity, const py::array_t<double, py::array::c_style | py::array::forcecast>& radii,
           std::mt19937_64& rng) { return rows(lab::place_without_overlap(cavity, doubles(radii), rng)); },
        py::arg("cavity"), py::arg("radii"), py::arg("rng"), "N x 3 centres, none overlapping, inside the cavity");
  py::class_<lab::RadiusExpansion>(m, "RadiusExpansion", "Balls grown from start_factor to full size in stages")
      .def(py::init<>())
      .def_readwrite("balls", &lab::RadiusExpansion::balls)
      .def_readwrite("diameters", &lab::RadiusExpansion::diameters)
      .def_readwrite("start_factor", &lab::RadiusExpansion::start_factor)
      .def_readwrite("stages", &lab::RadiusExpansion::stages)
      .def_readwrite("increments", &lab::RadiusExpansion::increments)
      .def_readwrite("steps_per_increment", &lab::RadiusExpansion::steps_per_increment)
      .def("factor", &lab::RadiusExpansion::factor, py::arg("stage"), py::arg("increment"));
  py::class_<lab::Friction>(m, "Friction", "Sliding and rolling friction coefficients")
      .def(py::init([](double sliding, double rolling) { return lab::Friction{sliding, rolling}; }), py::arg("sliding"), py::arg("rolling"))
      .def_readwrite("sliding", &lab::Friction::sliding)
      .def_readwrite("rolling", &lab::Friction::rolling);
  py::class_<lab::FrictionSchedule>(m, "FrictionSchedule", "Friction lowered step by step to a target porosity (docs/model.md 7.1)")
      .def(py::init([](double target_porosity, double porosity_tolerance, double reduction, double floor) {
             return lab::FrictionSchedule{target_porosity, porosity_tolerance, reduction, floor};
           }),
           py::arg("target_porosity"), py::arg("porosity_tolerance") = 0.005, py::arg("reduction") = 0.5, py::arg("floor") = 0.0);
  m.def("next_friction", &lab::next_friction, py::arg("schedule"), py::arg("porosity"), py::arg("now"),
        "The friction of the next step, or None when the schedule is over");
  m.def("set_radii", &lab::set_radii, py::arg("world"), py::arg("expansion"), py::arg("factor"));
  m.def("add_expanding_balls",
        [](World& w, const lab::Cylinder& cavity, const py::array_t<double, py::array::c_style | py::array::forcecast>& diameters,
           double density, int stages, std::mt19937_64& rng) {
          return lab::add_expanding_balls(w, cavity, doubles(diameters), density, stages, rng);
        },
        py::arg("world"), py::arg("cavity"), py::arg("diameters"), py::arg("density"), py::arg("stages"), py::arg("rng"));
}

void bind_loading(py::module_& m) {
  py::class_<lab::ConsolidationTarget>(m, "ConsolidationTarget")
      .def(py::init([](double stress, double servo_max_speed, double equilibrium_ratio, std::int64_t max_steps, std::int64_t chunk_steps) {
             return lab::ConsolidationTarget{stress, servo_max_speed, equilibrium_ratio, max_steps, chunk_steps};
           }),
           py::arg("stress"), py::arg("servo_max_speed") = 0.05, py::arg("equilibrium_ratio") = 1e-2,
           py::arg("max_steps") = 400000, py::arg("chunk_steps") = 10)
      .def_readwrite("stress", &lab::ConsolidationTarget::stress)
      .def_readwrite("servo_max_speed", &lab::ConsolidationTarget::servo_max_speed)
      .def_readwrite("equilibrium_ratio", &lab::ConsolidationTarget::equilibrium_ratio)
      .def_readwrite("max_steps", &lab::ConsolidationTarget::max_steps)
      .def_readwrite("chunk_steps", &lab::ConsolidationTarget::chunk_steps);
  py::class_<lab::ConsolidationReport>(m, "ConsolidationReport")
      .def_readonly("settled", &lab::ConsolidationReport::settled)
      .def_readonly("steps", &lab::ConsolidationReport::steps)
      .def_readonly("stress", &lab::ConsolidationReport::stress)
      .def_readonly("unbalanced_ratio", &lab::ConsolidationReport::unbalanced_ratio);
  m.def("start_consolidation", &lab::start_consolidation, py::arg("servo"), py::arg("target"));
  m.def("consolidate",
        [](World& w, const ServoWall& servo, const lab::ConsolidationTarget& target, std::int64_t start_step, py::object between_chunks) {
          std::function<void()> call;
          if (!between_chunks.is_none())
            call = [&] {
              py::gil_scoped_acquire gil;
              between_chunks();
            };
          py::gil_scoped_release release;
          return lab::consolidate(w, servo, target, start_step, call);
        },
        py::arg("world"), py::arg("servo"), py::arg("target"), py::arg("start_step"), py::arg("between_chunks") = py::none(),
        "Steps until the servo has settled and the packing is near equilibrium, or max_steps since start_step");

  py::enum_<lab::ShearMode>(m, "ShearMode").value("DRAINED", lab::ShearMode::Drained).value("CONSTANT_VOLUME", lab::ShearMode::ConstantVolume);
  py::enum_<lab::MovingPlate>(m, "MovingPlate").value("BOTTOM", lab::MovingPlate::Bottom).value("BOTH", lab::MovingPlate::Both);
  py::class_<lab::ShearLegMotion>(m, "ShearLegMotion", "How the plates move during one shear leg")
      .def(py::init([](double direction_deg, double speed, lab::ShearMode mode, lab::MovingPlate moving_plate, double servo_max_speed) {
             return lab::ShearLegMotion{direction_deg, speed, mode, moving_plate, servo_max_speed};
           }),
           py::arg("direction_deg"), py::arg("speed"), py::arg("mode") = lab::ShearMode::Drained,
           py::arg("moving_plate") = lab::MovingPlate::Bottom, py::arg("servo_max_speed") = 0.05)
      .def("direction", &lab::ShearLegMotion::direction);
  m.def("start_shear_leg", &lab::start_shear_leg, py::arg("world"), py::arg("cell"), py::arg("servo"), py::arg("motion"));
  m.def("stop_shear", &lab::stop_shear, py::arg("world"), py::arg("cell"));
  m.def("plate_offset", &lab::plate_offset, py::arg("world"), py::arg("cell"), "m, bottom minus top plate, horizontal");
  py::class_<lab::ShearPath>(m, "ShearPath", "The strain of a path of legs: |d offset| / height summed")
      .def(py::init<const World&, const lab::ShearCell&, double>(), py::arg("world"), py::arg("cell"), py::arg("height"))
      .def("advance", &lab::ShearPath::advance, py::arg("world"), py::arg("cell"))
      .def_property_readonly("strain", &lab::ShearPath::strain)
      .def_property_readonly("offset", &lab::ShearPath::offset)
      .def_property_readonly("height", &lab::ShearPath::height);

  py::enum_<lab::CyclicShape>(m, "CyclicShape", "The cyclic paths in the horizontal plane (lab/toolkit/cyclic_path.hpp)")
      .value("SINE", lab::CyclicShape::Sine)
      .value("CIRCLE", lab::CyclicShape::Circle)
      .value("ELLIPSE", lab::CyclicShape::Ellipse)
      .value("FIGURE8", lab::CyclicShape::Figure8)
      .value("SERIES", lab::CyclicShape::Series);
  py::class_<lab::CyclicPath>(m, "CyclicPath", "Where a cyclic path is at N cycles, in units of its amplitude (a series: absolute)")
      .def(py::init<lab::CyclicShape, double, double>(), py::arg("shape"), py::arg("direction_deg") = 0.0, py::arg("minor_ratio") = 0.5)
      .def_static("from_csv", &lab::CyclicPath::from_csv, py::arg("file"), py::arg("period"),
                  "A series: columns cycle (or time, s, over period) then x and y")
      .def("at", &lab::CyclicPath::at, py::arg("cycles"))
      .def("length_cycles", &lab::CyclicPath::length_cycles)
      .def_property_readonly("absolute", &lab::CyclicPath::absolute)
      .def_property_readonly("shape", &lab::CyclicPath::shape);

  py::class_<lab::HorizontalDriveSettings>(m, "HorizontalDriveSettings", "Plates, area (m^2), height (m), servo gain and cap")
      .def(py::init([](WallId top, WallId bottom, double area, double height, double stiffness_ratio, double relaxation, double max_speed) {
             return lab::HorizontalDriveSettings{top, bottom, area, height, stiffness_ratio, relaxation, max_speed};
           }),
           py::arg("top"), py::arg("bottom"), py::arg("area"), py::arg("height"), py::arg("stiffness_ratio") = 1.0,
           py::arg("relaxation") = 1.0, py::arg("max_speed"));
  py::class_<lab::HorizontalDrive, std::shared_ptr<lab::HorizontalDrive>>(
      m, "HorizontalDrive", "The plates' horizontal motion of a cyclic or monotonic stage (lab/toolkit/horizontal_drive.hpp); call it from a controller")
      .def(py::init<const lab::HorizontalDriveSettings&>(), py::arg("settings"))
      .def("hold", &lab::HorizontalDrive::hold)
      .def("servo_stress", &lab::HorizontalDrive::servo_stress, py::arg("target"), py::arg("start_step"), py::arg("steps_per_cycle"),
           "target(N) -> horizontal stress (Pa) the top plate's servo follows")
      .def("follow_strain", &lab::HorizontalDrive::follow_strain, py::arg("target"), py::arg("start_step"), py::arg("steps_per_cycle"),
           "target(N) -> horizontal shear strain the bottom plate is moved to")
      .def("move_bottom", &lab::HorizontalDrive::move_bottom, py::arg("velocity"))
      .def("__call__", &lab::HorizontalDrive::operator(), py::arg("world"))
      .def("cycles_at", &lab::HorizontalDrive::cycles_at, py::arg("step"))
      .def("target", &lab::HorizontalDrive::target, py::arg("cycles"))
      .def_property_readonly("work", &lab::HorizontalDrive::work, "J/m^3")
      .def("reset_work", &lab::HorizontalDrive::reset_work);
}

}  // namespace

void bind_toolkit(py::module_& m) {
  bind_cell(m);
  bind_specimen(m);
  bind_loading(m);
}

}  // namespace dem::python
