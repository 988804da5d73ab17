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

void bind_cell(py::module_& m) {
  py::enum_<lab::RingVertical>(m, "RingVertical", "How the rings move vertically once the specimen is made (docs/model.md 4)")
      .value("FIXED", lab::RingVertical::Fixed, "held at their generation heights")
      .value("FOLLOW", lab::RingVertical::Follow, "each ring's height interpolated between the plates")
      .value("PRESCRIBED", lab::RingVertical::Prescribed, "follow, and the horizontal displacement prescribed linear in height")
      .value("FREE", lab::RingVertical::Free, "free in z too: each ring rides on the sand next to it")
      .value("SAND", lab::RingVertical::Sand, "each ring moves with the mean vertical velocity of the balls touching it");
  py::class_<lab::ShearCellSpec>(m, "ShearCellSpec", "Geometry of an NGI cell (m, kg/m^3); z up, bottom plate at z = 0")
      .def(py::init<>(), "The study's cell: 70 mm across, 22 mm high, 0.7 mm pebbles, rings that follow")
      .def_readwrite("diameter", &lab::ShearCellSpec::diameter, "Specimen diameter (m)")
      .def_readwrite("height", &lab::ShearCellSpec::height, "Plate gap as built (m)")
      .def_readwrite("pebble_diameter", &lab::ShearCellSpec::pebble_diameter, "Ring pebble diameter (m), also one ring's height")
      .def_readwrite("ring_gap", &lab::ShearCellSpec::ring_gap, "Vertical gap between rings (m)")
      .def_readwrite("ring_density", &lab::ShearCellSpec::ring_density, "Density of the solid ring the pebbles stand for (kg/m^3)")
      .def_readwrite("stack_height", &lab::ShearCellSpec::stack_height, "Height the ring stack covers (m); 0: height")
      .def_readwrite("max_opening", &lab::ShearCellSpec::max_opening, "If > 0, every opening of the stack must be smaller (m)")
      .def_readwrite("rings", &lab::ShearCellSpec::rings, "How the rings move vertically (RingVertical)");
  py::class_<lab::ShearCell>(m, "ShearCell", "The plates and rings of a cell in a World")
      .def_readonly("bottom", &lab::ShearCell::bottom, "The bottom plate's wall id")
      .def_readonly("top", &lab::ShearCell::top, "The top plate's wall id")
      .def_readonly("first_ring", &lab::ShearCell::first_ring, "Index of the bottom ring among the World's clumps; the others follow it")
      .def_readonly("ring_count", &lab::ShearCell::ring_count, "Rings in the stack")
      .def_readonly("radius", &lab::ShearCell::radius, "Specimen radius (m)")
      .def_readonly("built_height", &lab::ShearCell::built_height, "Plate gap as built (m)")
      .def_readonly("area", &lab::ShearCell::area, "Specimen cross-section, the plates' loaded area (m^2)")
      .def_readonly("pebble_radius", &lab::ShearCell::pebble_radius, "Ring pebble radius (m)")
      .def_readonly("rings", &lab::ShearCell::rings, "How the rings move vertically (RingVertical)")
      .def("plate_gap", &lab::ShearCell::plate_gap, py::arg("world"), "Top minus bottom plate height now (m)");
  m.def("build_shear_cell", &lab::build_shear_cell, py::arg("world"), py::arg("spec"),
        "Adds the plates and the ring stack (rings held in every DOF until release_rings) to `world`; returns the ShearCell");
  m.def("move_rings", &lab::move_rings, py::arg("world"), py::arg("cell"), py::arg("specimen_made"),
        "Sets the rings' velocities (m/s) for this step from the plates' (call it from a controller, after the servo).\n\n"
        "Args:\n"
        "    world: the World.\n"
        "    cell: its ShearCell.\n"
        "    specimen_made: False while the specimen is made (every mode but FIXED follows the plates).");
  m.def("release_rings", &lab::release_rings, py::arg("world"), py::arg("cell"),
        "Frees the rings for the test, never in rotation: x and y (and z for FREE); PRESCRIBED rings stay held");
  m.def("plate_damping_frame", &lab::plate_damping_frame, py::arg("world"), py::arg("cell"),
        "The plates' affine velocity field, a DampingFrame for World.set_damping_frame while the plates shear");
  m.def("ring_lateral_stress", &lab::ring_lateral_stress, py::arg("world"), py::arg("cell"),
        "Radial push of the sand on the rings (Pa): the ball-pebble forces over the specimen's lateral surface");
  m.def("keep_plate_gap", &lab::keep_plate_gap, py::arg("world"), py::arg("cell"), py::arg("min_gap"),
        "Caps the top plate's downward velocity so that the plates stay min_gap (m) apart (after the servo)");
  m.def("specimen_porosity", &lab::specimen_porosity, py::arg("world"), py::arg("cell"),
        "The specimen's porosity (-): 1 - ball volume / (area x plate gap), overlaps ignored");
}

void bind_specimen(py::module_& m) {
  py::class_<std::mt19937_64>(m, "Random", "The 64-bit Mersenne Twister the C++ parts draw from")
      .def(py::init<std::uint64_t>(), py::arg("seed"), "A generator seeded with `seed` (0 to 2^64 - 1)");
  py::class_<lab::Grading>(m, "Grading", "Diameters uniform by number on [d_min, d_max] x scale (m)")
      .def(py::init<>(), "The study's grading: 0.7 to 1.2 mm, scale 1")
      .def_readwrite("d_min", &lab::Grading::d_min, "Smallest diameter before scaling (m)")
      .def_readwrite("d_max", &lab::Grading::d_max, "Largest diameter before scaling (m)")
      .def_readwrite("scale", &lab::Grading::scale, "Size multiplier (-; 1D, 2D, 4D = 1, 2, 4)")
      .def("smallest", &lab::Grading::smallest, "Smallest diameter that can be drawn, after scaling (m)")
      .def("largest", &lab::Grading::largest, "Largest diameter that can be drawn, after scaling (m)");
  m.def("sample_diameters", [](const lab::Grading& g, double solid_volume, std::mt19937_64& rng) {
          const std::vector<double> d = lab::sample_diameters(g, solid_volume, rng);
          return py::array_t<double>(static_cast<py::ssize_t>(d.size()), d.data());
        }, py::arg("grading"), py::arg("solid_volume"), py::arg("rng"), "Diameters (m) until their volume reaches solid_volume (m^3)");
  py::class_<lab::Cylinder>(m, "Cylinder", "A vertical cylinder on z = 0 about the z axis (m)")
      .def(py::init([](double radius, double height) { return lab::Cylinder{radius, height}; }), py::arg("radius"), py::arg("height"),
           "A cylinder of this radius (m) and height (m)")
      .def_readwrite("radius", &lab::Cylinder::radius, "Radius (m)")
      .def_readwrite("height", &lab::Cylinder::height, "Height (m)");
  m.def("place_without_overlap",
        [](const lab::Cylinder& cavity, const py::array_t<double, py::array::c_style | py::array::forcecast>& radii,
           std::mt19937_64& rng) { return vec3_rows(lab::place_without_overlap(cavity, doubles(radii), rng)); },
        py::arg("cavity"), py::arg("radii"), py::arg("rng"),
        "Centres (m, N x 3) for balls of the given radii (m), drawn one after the other inside the cavity, none\n"
        "overlapping (ValueError when a ball finds no room in 100000 draws).\n\n"
        "Args:\n"
        "    cavity: a Cylinder on z = 0 about the z axis.\n"
        "    radii: (m), N.\n"
        "    rng: the Random generator drawn from.");
  py::class_<lab::RadiusExpansion>(m, "RadiusExpansion", "Balls grown from start_factor to full size in stages")
      .def(py::init<>(), "No balls; 8 stages of 10 increments of 50 steps from half size")
      .def_readwrite("balls", &lab::RadiusExpansion::balls, "The growing balls' ids, in the order of diameters")
      .def_readwrite("diameters", &lab::RadiusExpansion::diameters, "Full-size diameters (m)")
      .def_readwrite("start_factor", &lab::RadiusExpansion::start_factor, "Fraction of the full radii when placed (-)")
      .def_readwrite("stages", &lab::RadiusExpansion::stages, "Stages of growth")
      .def_readwrite("increments", &lab::RadiusExpansion::increments, "Increments per stage")
      .def_readwrite("steps_per_increment", &lab::RadiusExpansion::steps_per_increment, "Steps cycled after each increment")
      .def("factor", &lab::RadiusExpansion::factor, py::arg("stage"), py::arg("increment"),
           "Radius over full radius (-) after `increment` increments of stage `stage` (1-based; 0 of stage 1 is the start)");
  py::class_<lab::Friction>(m, "Friction", "Sliding and rolling friction coefficients")
      .def(py::init([](double sliding, double rolling) { return lab::Friction{sliding, rolling}; }), py::arg("sliding"), py::arg("rolling"),
           "Sliding mu (-) and rolling mu_r (-) coefficients")
      .def_readwrite("sliding", &lab::Friction::sliding, "Sliding friction mu (-)")
      .def_readwrite("rolling", &lab::Friction::rolling, "Rolling friction mu_r (-)");
  py::class_<lab::FrictionSchedule>(m, "FrictionSchedule", "Friction lowered step by step to a target porosity (docs/model.md 7.1)")
      .def(py::init([](double target_porosity, double porosity_tolerance, double reduction, double floor) {
             return lab::FrictionSchedule{target_porosity, porosity_tolerance, reduction, floor};
           }),
           py::arg("target_porosity"), py::arg("porosity_tolerance") = 0.005, py::arg("reduction") = 0.5, py::arg("floor") = 0.0,
           "Args:\n"
           "    target_porosity: (-).\n"
           "    porosity_tolerance: the schedule ends within this of the target (-).\n"
           "    reduction: factor on both coefficients per step (-).\n"
           "    floor: both coefficients become 0 once the larger is below this (-).");
  m.def("next_friction", &lab::next_friction, py::arg("schedule"), py::arg("porosity"), py::arg("now"),
        "The Friction of the next step, or None when the schedule is over.\n\n"
        "Args:\n"
        "    schedule: a FrictionSchedule.\n"
        "    porosity: the specimen's porosity now (-).\n"
        "    now: the Friction in use.");
  m.def("set_radii", &lab::set_radii, py::arg("world"), py::arg("expansion"), py::arg("factor"),
        "Sets each growing ball's radius to factor (-) x its full radius and readies the World for the new sizes");
  m.def("add_expanding_balls",
        [](World& w, const lab::Cylinder& cavity, const py::array_t<double, py::array::c_style | py::array::forcecast>& diameters,
           double density, int stages, std::mt19937_64& rng) {
          return lab::add_expanding_balls(w, cavity, doubles(diameters), density, stages, rng);
        },
        py::arg("world"), py::arg("cavity"), py::arg("diameters"), py::arg("density"), py::arg("stages"), py::arg("rng"),
        "Adds balls at half their size at random places in the cavity; returns their RadiusExpansion.\n\n"
        "Args:\n"
        "    world: the World.\n"
        "    cavity: a Cylinder on z = 0.\n"
        "    diameters: full-size diameters (m).\n"
        "    density: (kg/m^3).\n"
        "    stages: stages of growth.\n"
        "    rng: the Random generator drawn from.");
}

void bind_loading(py::module_& m) {
  py::class_<lab::ConsolidationTarget>(m, "ConsolidationTarget", "Where to take the servo plate, and when to stop")
      .def(py::init([](double vertical_stress, double servo_max_speed, double equilibrium_ratio, std::int64_t max_steps, std::int64_t chunk_steps) {
             return lab::ConsolidationTarget{vertical_stress, servo_max_speed, equilibrium_ratio, max_steps, chunk_steps};
           }),
           py::arg("vertical_stress"), py::arg("servo_max_speed") = 0.05, py::arg("equilibrium_ratio") = 1e-2,
           py::arg("max_steps") = 400000, py::arg("chunk_steps") = 10,
           "Args:\n"
           "    vertical_stress: on the servo plate (Pa), the key consolidation.vertical_stress.\n"
           "    servo_max_speed: cap of the plate's speed (m/s).\n"
           "    equilibrium_ratio: unbalanced over mean contact force at which the packing counts as settled (-).\n"
           "    max_steps: steps after which the consolidation stops unsettled.\n"
           "    chunk_steps: steps between two checks.")
      .def_readwrite("vertical_stress", &lab::ConsolidationTarget::vertical_stress, "Stress on the servo plate (Pa)")
      .def_readwrite("servo_max_speed", &lab::ConsolidationTarget::servo_max_speed, "Cap of the plate's speed (m/s)")
      .def_readwrite("equilibrium_ratio", &lab::ConsolidationTarget::equilibrium_ratio,
                     "Unbalanced over mean contact force at which the packing counts as settled (-)")
      .def_readwrite("max_steps", &lab::ConsolidationTarget::max_steps, "Steps after which the consolidation stops unsettled")
      .def_readwrite("chunk_steps", &lab::ConsolidationTarget::chunk_steps, "Steps between two checks (and two between_chunks calls)");
  py::class_<lab::ConsolidationReport>(m, "ConsolidationReport", "How a consolidation ended")
      .def_readonly("settled", &lab::ConsolidationReport::settled, "False: max_steps ran out first")
      .def_readonly("steps", &lab::ConsolidationReport::steps, "Steps since the consolidation started")
      .def_readonly("stress", &lab::ConsolidationReport::stress, "Stress on the servo plate in the last step (Pa)")
      .def_readonly("unbalanced_ratio", &lab::ConsolidationReport::unbalanced_ratio, "Unbalanced over mean contact force (-)");
  m.def("start_consolidation", &lab::start_consolidation, py::arg("servo"), py::arg("target"),
        "Gives the servo the target's stress (Pa) and speed cap (m/s): the start of a consolidation");
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
        "Steps until the servo has settled and the packing is near equilibrium, or max_steps since start_step;\n"
        "returns a ConsolidationReport. The GIL is released meanwhile.\n\n"
        "Args:\n"
        "    world: the World, whose controller runs the servo.\n"
        "    servo: the plate's ServoWall.\n"
        "    target: a ConsolidationTarget.\n"
        "    start_step: the step the consolidation started at (world.step_count, or a restart's).\n"
        "    between_chunks: called after every chunk that does not end it (outputs, progress), or None.");

  py::enum_<lab::ShearMode>(m, "ShearMode", "What the top plate's servo holds while the plates shear")
      .value("DRAINED", lab::ShearMode::Drained, "the vertical stress")
      .value("CONSTANT_VOLUME", lab::ShearMode::ConstantVolume, "the height");
  py::enum_<lab::MovingPlate>(m, "MovingPlate", "Which plates move horizontally in a shear leg")
      .value("BOTTOM", lab::MovingPlate::Bottom, "the bottom plate, the top one at rest")
      .value("BOTH", lab::MovingPlate::Both, "each plate half, oppositely");
  py::class_<lab::ShearLegMotion>(m, "ShearLegMotion", "How the plates move during one shear leg")
      .def(py::init([](double direction_deg, double speed, lab::ShearMode mode, lab::MovingPlate moving_plate, double servo_max_speed) {
             return lab::ShearLegMotion{direction_deg, speed, mode, moving_plate, servo_max_speed};
           }),
           py::arg("direction_deg"), py::arg("speed"), py::arg("mode") = lab::ShearMode::Drained,
           py::arg("moving_plate") = lab::MovingPlate::Bottom, py::arg("servo_max_speed") = 0.05,
           "Args:\n"
           "    direction_deg: of the bottom plate's motion relative to the top, from +x towards +y (deg).\n"
           "    speed: of the bottom plate relative to the top (m/s).\n"
           "    mode: a ShearMode.\n"
           "    moving_plate: a MovingPlate.\n"
           "    servo_max_speed: cap of the top plate's vertical servo while shearing (m/s).")
      .def("direction", &lab::ShearLegMotion::direction, "The unit horizontal vector of direction_deg");
  m.def("start_shear_leg", &lab::start_shear_leg, py::arg("world"), py::arg("cell"), py::arg("servo"), py::arg("motion"),
        "Sets the plates' horizontal velocities (m/s) for the leg and the servo's mode and speed cap");
  m.def("stop_shear", &lab::stop_shear, py::arg("world"), py::arg("cell"), "Stops the plates horizontally (the servo keeps its mode)");
  m.def("plate_offset", &lab::plate_offset, py::arg("world"), py::arg("cell"),
        "Horizontal displacement of the bottom plate relative to the top one (m)");
  py::class_<lab::ShearPath>(m, "ShearPath", "The strain of a path of legs: |d offset| / height summed")
      .def(py::init<const World&, const lab::ShearCell&, double>(), py::arg("world"), py::arg("cell"), py::arg("height"),
           "A path from the plates' offset now; height is the consolidated height (m)")
      .def("advance", &lab::ShearPath::advance, py::arg("world"), py::arg("cell"),
           "Adds the offset change since the last call; returns the strain so far (-)")
      .def_property_readonly("strain", &lab::ShearPath::strain, "Strain of the path so far (-)")
      .def_property_readonly("offset", &lab::ShearPath::offset, "Plate offset at the last advance (m)")
      .def_property_readonly("height", &lab::ShearPath::height, "The consolidated height the strain is over (m)");

  py::enum_<lab::CyclicShape>(m, "CyclicShape", "The cyclic paths in the horizontal plane (lab/toolkit/cyclic_path.hpp)")
      .value("SINE", lab::CyclicShape::Sine, "a sin(2 pi N) along the direction")
      .value("CIRCLE", lab::CyclicShape::Circle, "|value| = a while it turns 360 deg per cycle")
      .value("ELLIPSE", lab::CyclicShape::Ellipse, "axes a along the direction, q a across")
      .value("FIGURE8", lab::CyclicShape::Figure8, "two lobes across the direction per cycle")
      .value("SERIES", lab::CyclicShape::Series, "(x, y)(N) from a CSV file");
  py::class_<lab::CyclicPath>(m, "CyclicPath", "Where a cyclic path is at N cycles, in units of its amplitude (a series: absolute)")
      .def(py::init<lab::CyclicShape, double, double>(), py::arg("shape"), py::arg("direction_deg") = 0.0, py::arg("minor_ratio") = 0.5,
           "A drawn shape (not SERIES).\n\n"
           "Args:\n"
           "    shape: a CyclicShape.\n"
           "    direction_deg: of the path's direction, from +x towards +y (deg).\n"
           "    minor_ratio: q of the ellipse and figure-8 (-, >= 0).")
      .def_static("from_csv", &lab::CyclicPath::from_csv, py::arg("file"), py::arg("period"),
                  "A series from a CSV file: columns cycle (or time, s, over period in s) then x and y")
      .def("at", &lab::CyclicPath::at, py::arg("cycles"),
           "The target at N cycles (N >= 0), horizontal: unit amplitude for a drawn shape")
      .def("length_cycles", &lab::CyclicPath::length_cycles, "The cycles the path lasts: infinite for a drawn shape")
      .def_property_readonly("absolute", &lab::CyclicPath::absolute,
                             "True for a series: its values are CSR or strains, not multiples of an amplitude")
      .def_property_readonly("shape", &lab::CyclicPath::shape, "The CyclicShape");

  py::class_<lab::HorizontalDriveSettings>(m, "HorizontalDriveSettings", "Plates, area (m^2), height (m), servo gain and cap")
      .def(py::init([](WallId top, WallId bottom, double area, double height, double stiffness_ratio, double relaxation, double max_speed) {
             return lab::HorizontalDriveSettings{top, bottom, area, height, stiffness_ratio, relaxation, max_speed};
           }),
           py::arg("top"), py::arg("bottom"), py::arg("area"), py::arg("height"), py::arg("stiffness_ratio") = 1.0,
           py::arg("relaxation") = 1.0, py::arg("max_speed"),
           "Args:\n"
           "    top, bottom: the plates' wall ids.\n"
           "    area: over which the plate force is a stress (m^2).\n"
           "    height: H of the shear strain (m, the consolidated height).\n"
           "    stiffness_ratio: the plate contacts' kn / ks (-).\n"
           "    relaxation: in (0, 1], the fraction of the stress error removed per step (-).\n"
           "    max_speed: of the top plate under stress control (m/s).");
  py::class_<lab::HorizontalDrive, std::shared_ptr<lab::HorizontalDrive>>(
      m, "HorizontalDrive", "The plates' horizontal motion of a cyclic or monotonic stage (lab/toolkit/horizontal_drive.hpp); call it from a controller")
      .def(py::init<const lab::HorizontalDriveSettings&>(), py::arg("settings"), "A drive at rest (ValueError names a bad setting)")
      .def("hold", &lab::HorizontalDrive::hold, "Plates at rest horizontally from the next step on")
      .def("servo_stress", &lab::HorizontalDrive::servo_stress, py::arg("target"), py::arg("start_step"), py::arg("steps_per_cycle"),
           "Stress control from start_step on: target(N) gives the horizontal stress (Pa, a 3-vector) the top plate's\n"
           "servo follows at N cycles, counted as steps_per_cycle steps")
      .def("follow_strain", &lab::HorizontalDrive::follow_strain, py::arg("target"), py::arg("start_step"), py::arg("steps_per_cycle"),
           "Strain control from start_step on: target(N) gives the horizontal shear strain (-, a 3-vector) the bottom\n"
           "plate is moved to at N cycles, counted as steps_per_cycle steps")
      .def("move_bottom", &lab::HorizontalDrive::move_bottom, py::arg("velocity"),
           "The bottom plate at `velocity` (m/s, horizontal), the top plate at rest")
      .def("__call__", &lab::HorizontalDrive::operator(), py::arg("world"),
           "One control step: sets the plates' horizontal velocities and adds the step's work")
      .def("cycles_at", &lab::HorizontalDrive::cycles_at, py::arg("step"), "N since the stage began, `step` steps into the run")
      .def("target", &lab::HorizontalDrive::target, py::arg("cycles"),
           "The target at N cycles (Pa or -), NaN when neither stress nor strain is controlled")
      .def_property_readonly("work", &lab::HorizontalDrive::work, "Work tau . d gamma since the last reset_work (J/m^3)")
      .def("reset_work", &lab::HorizontalDrive::reset_work, "Sets the work to 0");
}

}  // namespace

void bind_toolkit(py::module_& m) {
  bind_cell(m);
  bind_specimen(m);
  bind_loading(m);
}

}  // namespace dem::python
