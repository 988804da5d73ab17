// The engine from Python: World and its settings, balls one by one or from NumPy arrays, contact
// laws per contact kind, facet walls, clumps and ring stacks, servo walls, measurement spheres,
// Python controllers and callbacks, checkpoints, and read-only NumPy views of the state.
//
// The GIL is released while the World steps and taken back only to call Python (a controller, a
// callback, a run_until test). A view shares the World's storage: it is valid until the next
// step or change (storage is re-sorted at neighbour-list rebuilds; `ids` gives each row's ball).
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <fstream>
#include <memory>

#include <dem/boundary/clump_ring.hpp>
#include <dem/control/servo_wall.hpp>
#include <dem/core/law_registry.hpp>
#include <dem/contact/linear_law.hpp>
#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>
#include <dem/geometry/mesh.hpp>
#include <dem/geometry/stl.hpp>
#include <dem/io/atomic_file.hpp>
#include <dem/io/world_state.hpp>
#include <dem/measure/measurement_sphere.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "a std::vector<Vec3> is an N x 3 array of doubles");

py::array read_only(py::array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// An N x 3 view of a vector of Vec3 owned by `owner` (the World's Python object, kept alive).
py::array vec3_view(const std::vector<Vec3>& v, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return read_only(py::array(py::dtype::of<double>(), {n, py::ssize_t{3}},
                             {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                             v.empty() ? nullptr : v.front().data(), owner));
}

template <class T>
py::array vector_view(const std::vector<T>& v, py::handle owner) {
  return read_only(py::array(py::dtype::of<T>(), {static_cast<py::ssize_t>(v.size())}, {static_cast<py::ssize_t>(sizeof(T))},
                             v.empty() ? nullptr : v.data(), owner));
}

// N x 3 from Python, checked.
std::vector<Vec3> rows_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, const std::string& name) {
  require(a.ndim() == 2 && a.shape(1) == 3, name + " shape", a.ndim() == 2 ? std::to_string(a.shape(0)) + " x " + std::to_string(a.shape(1)) : std::to_string(a.ndim()) + " dimensions",
          "N x 3");
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<std::size_t>(i)] = Vec3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

// A Python callable shared by copies of the std::function that holds it; called with the GIL.
struct PythonCall {
  std::shared_ptr<py::object> fn;
  explicit PythonCall(py::function f) : fn(std::make_shared<py::object>(std::move(f))) {}
  py::object operator()(World& w) const {
    py::gil_scoped_acquire gil;
    return (*fn)(py::cast(&w, py::return_value_policy::reference));
  }
};

// A wall by id: stays valid when walls are added (the vector may move).
struct WallRef {
  World* world;
  WallId id;
  Wall& wall() const { return world->wall(id); }
};

template <class Params>
void set_model(World& w, ContactKind kind, const Params& params, const std::string& name) {
  if constexpr (std::is_same_v<Params, RollingLinearLaw::Params>)
    w.set_contact_model(kind, make_contact_model<RollingLinearLaw>(params, name));
  else
    w.set_contact_model(kind, make_contact_model<LinearLaw>(params, name));
}

py::dict measurement(const SphereMeasurement& m) {
  py::dict d;
  d["stress"] = Mat3(m.stress);
  d["stress_contacts"] = Mat3(m.stress_contacts);
  d["porosity"] = m.porosity;
  d["coordination_number"] = m.coordination_number;
  d["mechanical_coordination_number"] = m.mechanical_coordination_number;
  d["balls"] = m.balls;
  d["contacts"] = m.contacts;
  d["fabric"] = Mat3(m.fabric);
  d["strain_rate"] = Mat3(m.strain_rate);
  d["principal_stresses"] = Vec3(m.principal.sigma_1, m.principal.sigma_2, m.principal.sigma_3);
  Mat3 directions;
  directions << m.principal.direction_1, m.principal.direction_2, m.principal.direction_3;
  d["principal_directions"] = directions;  // columns: the directions of sigma_1, sigma_2, sigma_3
  return d;
}

}  // namespace

void bind_engine(py::module_& m) {
  // World first, so that the signatures of the parts that take one (ServoWall.__call__) name it.
  py::class_<World> world_class(m, "World", "A simulation: balls, clumps, facet walls, contact laws and the clock");
  py::enum_<ContactKind>(m, "ContactKind", "The kinds of contact, each with its own contact law (World.set_contact_model)")
      .value("BALL_BALL", ContactKind::BallBall, "two balls")
      .value("BALL_FACET", ContactKind::BallFacet, "a ball on a wall: facet walls and analytic planes and cylinders")
      .value("BALL_PEBBLE", ContactKind::BallPebble, "a ball on a pebble of a clump (the rings)");
  py::enum_<World::ContactRecords>(m, "ContactRecords",
                                   "Which steps record the pair contacts' forces (World::ContactRecords)")
      .value("WHEN_READ", World::ContactRecords::WhenRead,
             "the last step of each step() call and the steps a callback follows (the default)")
      .value("EVERY_STEP", World::ContactRecords::EveryStep, "every step, for a controller that reads contacts");
  m.attr("DOF_X") = int(dof_x), m.attr("DOF_Y") = int(dof_y), m.attr("DOF_Z") = int(dof_z);
  m.attr("DOF_TRANSLATION") = int(dof_translation), m.attr("DOF_ROTATION") = int(dof_rotation), m.attr("DOF_ALL") = int(dof_all);

  py::class_<WorldSettings>(m, "WorldSettings", "Engine settings (SI units); 0 means automatic where noted")
      .def(py::init<>(), "The defaults: automatic time step, local damping 0.7, no gravity")
      .def_readwrite("time_step", &WorldSettings::time_step, "Time step (s); 0: time_step_safety x the critical estimate")
      .def_readwrite("time_step_safety", &WorldSettings::time_step_safety,
                     "Automatic time step over the critical estimate min sqrt(m/k) (-, default 0.8)")
      .def_readwrite("local_damping", &WorldSettings::local_damping,
                     "PFC local damping alpha (-, default 0.7; 0 for dynamic problems)")
      .def_readwrite("gravity", &WorldSettings::gravity, "Gravitational acceleration (m/s^2, a 3-vector)")
      .def_readwrite("skin", &WorldSettings::skin, "Verlet skin (m); 0: half the smallest ball radius")
      .def_readwrite("sort_every", &WorldSettings::sort_every,
                     "Re-sort the particles in cell order every this many neighbour-list rebuilds (0: never)")
      .def_readwrite("threads", &WorldSettings::threads,
                     "Threads of the team; 0: auto, the cores this process may run on (OMP_NUM_THREADS where set). "
                     "Results do not depend on it")
      .def_readwrite("adapt_threads", &WorldSettings::adapt_threads,
                     "A step runs on fewer threads while that is faster, as on a busy machine (default True; speed only)")
      .def_readwrite("max_overlap_ratio", &WorldSettings::max_overlap_ratio,
                     "Overlap over the smaller radius that stops a step with InstabilityError (-, default 1)")
      .def_readwrite("max_step_travel_ratio", &WorldSettings::max_step_travel_ratio,
                     "Distance moved in one step over the radius that stops a step with InstabilityError (-, default 0.25)")
      .def_readwrite("pebble_pebble_contacts", &WorldSettings::pebble_pebble_contacts,
                     "Contacts between pebbles of different clumps, with the ball-pebble law (default False)");

  py::class_<DampingFrame>(m, "DampingFrame",
                           "Velocity field local damping measures velocities against: velocity + (z - height) velocity_gradient "
                           "(docs/model.md 3.1); the default is the fixed frame")
      .def(py::init<>(), "The fixed frame (at rest everywhere)")
      .def_readwrite("velocity", &DampingFrame::velocity, "Velocity of the field at z = height (m/s)")
      .def_readwrite("height", &DampingFrame::height, "Height of the reference layer (m)")
      .def_readwrite("velocity_gradient", &DampingFrame::velocity_gradient, "dv/dz (1/s)")
      .def("velocity_at", &DampingFrame::velocity_at, py::arg("x"),
           "The field's velocity (m/s) at the point x (m)")
      .def("spin", &DampingFrame::spin, "Half the field's vorticity (rad/s): the spin balls are damped against");

  bind_contact_laws(m);
  py::class_<geometry::TriangleMesh>(m, "TriangleMesh", "Triangles of a facet wall, sharing vertices (m)")
      .def_property_readonly("vertices", [](const geometry::TriangleMesh& mesh) {
        py::array_t<double> a({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
          for (int k = 0; k < 3; ++k) a.mutable_at(static_cast<py::ssize_t>(i), k) = mesh.vertices[i][k];
        return a;
      }, "Vertex positions (m), N x 3, a copy")
      .def_property_readonly("triangles", [](const geometry::TriangleMesh& mesh) { return mesh.triangles; },
                             "Each triangle's three vertex indices; its normal follows the right-hand rule")
      .def("area", &geometry::TriangleMesh::area, "Sum of the triangle areas (m^2)");
  m.def("make_disc", &geometry::make_disc, py::arg("centre"), py::arg("radius"), py::arg("normal"), py::arg("segments") = 24,
        "A flat disc of triangles fanned around its centre (a plate).\n\n"
        "Args:\n"
        "    centre: the disc's centre (m).\n"
        "    radius: of the rim's vertices (m); the polygon is a little smaller than the circle.\n"
        "    normal: every triangle's normal (any length but 0).\n"
        "    segments: triangles (3 to 1e6).");
  m.def("make_rectangle", &geometry::make_rectangle, py::arg("centre"), py::arg("half_u"), py::arg("half_v"),
        "A rectangle centre +- half_u +- half_v as two triangles, normals along half_u x half_v.\n\n"
        "Args:\n"
        "    centre: the rectangle's centre (m).\n"
        "    half_u, half_v: perpendicular half side vectors (m).");
  m.def("make_cylinder_shell", &geometry::make_cylinder_shell, py::arg("base_centre"), py::arg("radius"), py::arg("height"),
        py::arg("segments") = 48, py::arg("normals_inward") = true,
        "An open cylindrical shell about +z from base_centre up to base_centre + height.\n\n"
        "Args:\n"
        "    base_centre: the centre of its bottom rim (m).\n"
        "    radius: of the polygon's vertices (m).\n"
        "    height: (m).\n"
        "    segments: sides of the polygon (3 to 1e6).\n"
        "    normals_inward: normals towards the axis (balls inside), else away from it.");
  m.def("read_stl", &geometry::read_stl_ascii, py::arg("file"), py::arg("scale") = 1.0,
        "A mesh from an ASCII STL file.\n\n"
        "Args:\n"
        "    file: the STL file.\n"
        "    scale: multiplies the file's coordinates to give m (1e-3 for a file in mm).\n\n"
        "Raises:\n"
        "    ValueError: a missing or bad file, naming the line.");

  py::class_<WallRef>(m, "Wall", "A wall of a World (facets, or an analytic plane or cylinder), by id")
      .def_property_readonly("id", [](const WallRef& r) { return r.id; }, "The wall's id in its World")
      .def_property_readonly("name", [](const WallRef& r) { return r.wall().name; }, "The name it was added with")
      .def_property("velocity", [](const WallRef& r) { return r.wall().velocity; },
                    [](const WallRef& r, const Vec3& v) { r.wall().velocity = v; }, "Rigid translation velocity (m/s), applied every step")
      .def_property_readonly("displacement", [](const WallRef& r) { return r.wall().displacement; },
                             "Total translation since the wall was added (m)")
      .def_property_readonly("force", [](const WallRef& r) { return r.wall().force; },
                             "Total force of the balls on the wall in the last step (N)")
      .def_property_readonly("normal_stress", [](const WallRef& r) { return r.wall().normal_stress(); },
                             "Normal stress on the wall (Pa, compression positive): force along the outward normal over area")
      .def_property_readonly("contact_count", [](const WallRef& r) { return r.wall().contact_count; },
                             "Balls touching the wall in the last step")
      .def_property_readonly("area", [](const WallRef& r) { return r.wall().area; },
                             "Loaded area for stresses and servo gains (m^2)");

  py::class_<ServoSettings>(m, "ServoSettings", "Settings of a servo wall (docs/model.md 5); stresses compression positive")
      .def(py::init([](double target_stress, double max_speed, double relaxation, double settle_tolerance, int settle_steps) {
             ServoSettings s;
             s.target_stress = target_stress, s.max_speed = max_speed, s.relaxation = relaxation;
             s.settle_tolerance = settle_tolerance, s.settle_steps = settle_steps;
             return s;
           }),
           py::arg("target_stress"), py::arg("max_speed"), py::arg("relaxation") = 0.5, py::arg("settle_tolerance") = 0.01,
           py::arg("settle_steps") = 100,
           "Args:\n"
           "    target_stress: normal stress to hold (Pa, >= 0).\n"
           "    max_speed: cap on the wall's normal speed (m/s, > 0).\n"
           "    relaxation: alpha_s in (0, 1], the fraction of the stress error removed per step (-).\n"
           "    settle_tolerance: |stress - target| <= this x target counts as on target (-).\n"
           "    settle_steps: consecutive steps on target for settled (>= 1).");
  py::class_<ServoWall, std::shared_ptr<ServoWall>>(m, "ServoWall", "Holds a target normal stress on a wall (docs/model.md 5)")
      .def(py::init<WallId, ServoSettings>(), py::arg("wall"), py::arg("settings"),
           "A servo a protocol's controller runs itself (world.add_servo_wall registers one as a controller).\n\n"
           "Args:\n"
           "    wall: the wall's id.\n"
           "    settings: a ServoSettings (ValueError names a bad one).")
      .def("__call__", &ServoWall::operator(), py::arg("world"), "One control step: sets the wall's normal velocity (m/s)")
      .def("set_target", &ServoWall::set_target, py::arg("stress"),
           "A constant target normal stress (Pa, >= 0); the settled count restarts")
      .def("set_max_speed", &ServoWall::set_max_speed, py::arg("max_speed"), "Changes the speed cap (m/s, > 0)")
      .def("hold_position", &ServoWall::hold_position, py::arg("hold"),
           "True: the wall's normal speed is held at 0 (constant volume); False: stress control")
      .def_property_readonly("target", &ServoWall::target, "Target stress of the last step (Pa)")
      .def_property_readonly("achieved_stress", &ServoWall::achieved_stress, "Normal stress the wall carried in the last step (Pa)")
      .def_property_readonly("settled", &ServoWall::settled, "True once the stress has been on target for settle_steps steps")
      .def_property_readonly("gain", &ServoWall::gain, "Gain in use (m/(s Pa)); 0 before the wall first touched a ball");

  py::class_<RingStackSpec>(m, "RingStackSpec", "An NGI stack of pebble rings around a cylindrical specimen, axis +z (docs/model.md 4)")
      .def(py::init<>(), "An empty spec: set at least inner_radius, height, ring_height and pebble_radius")
      .def_readwrite("base_centre", &RingStackSpec::base_centre, "Centre of the specimen's bottom face (m)")
      .def_readwrite("inner_radius", &RingStackSpec::inner_radius, "Specimen radius (m): the pebbles' inner surfaces touch it")
      .def_readwrite("height", &RingStackSpec::height, "Specimen height the stack covers (m)")
      .def_readwrite("ring_count", &RingStackSpec::ring_count, "Rings in the stack; 0: the fewest that cover height")
      .def_readwrite("ring_height", &RingStackSpec::ring_height, "Height of one ring (m), >= 2 pebble_radius")
      .def_readwrite("pebble_radius", &RingStackSpec::pebble_radius, "Pebble radius (m)")
      .def_readwrite("gap", &RingStackSpec::gap, "Vertical gap between neighbouring rings (m)")
      .def_readwrite("ring_density", &RingStackSpec::ring_density,
                     "Density of the solid ring the pebbles stand for (kg/m^3, default 2700)")
      .def_readwrite("max_opening", &RingStackSpec::max_opening,
                     "If > 0, every opening of the stack must be smaller (m): give the smallest ball diameter")
      .def_readwrite("fixed", &RingStackSpec::fixed, "DOF bits held of every ring (default DOF_Z | DOF_ROTATION)");

  world_class.def(py::init<WorldSettings>(), py::arg("settings") = WorldSettings{}, "An empty World with these settings")
      .def("add_ball",
           [](World& w, const Vec3& position, double radius, double density, const Vec3& velocity, int group, int fixed) {
             BallSpec b;
             b.position = position, b.radius = radius, b.density = density, b.velocity = velocity, b.group = group;
             b.fixed = static_cast<std::uint8_t>(fixed);
             return w.add_ball(b);
           },
           py::arg("position"), py::arg("radius"), py::arg("density"), py::arg("velocity") = Vec3::Zero().eval(),
           py::arg("group") = 0, py::arg("fixed") = 0,
           "Adds a ball; returns its id.\n\n"
           "Args:\n"
           "    position: centre (m).\n"
           "    radius: (m).\n"
           "    density: (kg/m^3).\n"
           "    velocity: (m/s).\n"
           "    group: a user tag (material, layer...).\n"
           "    fixed: DOF bits held (DOF_X | ...).")
      .def("add_balls",
           [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& positions,
              const py::array_t<double, py::array::c_style | py::array::forcecast>& radii, double density) {
             const std::vector<Vec3> x = rows_of(positions, "positions");
             require(radii.ndim() == 1 && radii.shape(0) == static_cast<py::ssize_t>(x.size()), "radii length", radii.size(),
                     std::to_string(x.size()) + " (one per position)");
             py::array_t<ParticleId> ids(static_cast<py::ssize_t>(x.size()));
             for (std::size_t i = 0; i < x.size(); ++i) {
               BallSpec b;
               b.position = x[i], b.radius = radii.at(static_cast<py::ssize_t>(i)), b.density = density;
               ids.mutable_at(static_cast<py::ssize_t>(i)) = w.add_ball(b);
             }
             return ids;
           },
           py::arg("positions"), py::arg("radii"), py::arg("density"),
           "Adds N balls at rest; returns their ids.\n\n"
           "Args:\n"
           "    positions: centres (m), N x 3.\n"
           "    radii: (m), N.\n"
           "    density: of every ball (kg/m^3).")
      .def("add_wall",
           [](World& w, const std::string& name, const geometry::TriangleMesh& mesh, const Vec3& outward_normal, double area) {
             return WallRef{&w, w.add_wall(make_facet_wall(name, mesh, outward_normal, area))};
           },
           py::arg("name"), py::arg("mesh"), py::arg("outward_normal"), py::arg("area") = 0.0, py::keep_alive<0, 1>(),
           "Adds a facet wall (the ball-facet law); returns it.\n\n"
           "Args:\n"
           "    name: for outputs and messages.\n"
           "    mesh: its triangles (m).\n"
           "    outward_normal: the direction in which the specimen pushes the wall (stresses are compressive along it).\n"
           "    area: loaded area for stresses and servos (m^2); 0: the mesh's area.")
      .def("add_plane_wall",
           [](World& w, const std::string& name, const Vec3& point, const Vec3& outward_normal, double area) {
             return WallRef{&w, w.add_wall(make_plane_wall(name, point, outward_normal, area))};
           },
           py::arg("name"), py::arg("point"), py::arg("outward_normal"), py::arg("area"), py::keep_alive<0, 1>(),
           "Adds an analytic infinite plane (the ball-facet law); returns it.\n\n"
           "Args:\n"
           "    name: for outputs and messages.\n"
           "    point: a point of the plane (m).\n"
           "    outward_normal: the direction in which the specimen pushes it.\n"
           "    area: loaded area for stresses and servos (m^2, > 0).")
      .def("add_cylinder_wall",
           [](World& w, const std::string& name, const Vec3& axis_point, const Vec3& axis, double radius, double area) {
             return WallRef{&w, w.add_wall(make_cylinder_wall(name, axis_point, axis, radius, area))};
           },
           py::arg("name"), py::arg("axis_point"), py::arg("axis"), py::arg("radius"), py::arg("area"),
           py::keep_alive<0, 1>(),
           "Adds an analytic infinite cylinder (the ball-facet law), for balls inside or outside; returns it.\n\n"
           "Args:\n"
           "    name: for outputs and messages.\n"
           "    axis_point: a point of the axis (m).\n"
           "    axis: the axis direction (also the wall's outward normal).\n"
           "    radius: (m).\n"
           "    area: loaded area for stresses (m^2, > 0; 2 pi R H for a specimen of height H).")
      .def("wall", [](World& w, WallId id) {
             require(id >= 0 && static_cast<std::size_t>(id) < w.walls().size(), "wall id", id, "0 <= id < " + std::to_string(w.walls().size()));
             return WallRef{&w, id};
           }, py::arg("id"), py::keep_alive<0, 1>(), "The wall of this id (ValueError for an id not in use)")
      .def_property_readonly("wall_count", [](const World& w) { return w.walls().size(); }, "Walls in the World")
      .def("add_clump",
           [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& positions, const std::vector<double>& radii,
              double density, int fixed) {
             const std::vector<Vec3> x = rows_of(positions, "pebble positions");
             require(radii.size() == x.size(), "pebble radii length", radii.size(), std::to_string(x.size()) + " (one per pebble)");
             ClumpSpec c;
             for (std::size_t i = 0; i < x.size(); ++i) c.pebbles.push_back({x[i], radii[i]});
             c.with_pebble_mass(density);
             c.fixed = static_cast<std::uint8_t>(fixed);
             return w.add_clump(c);
           },
           py::arg("positions"), py::arg("radii"), py::arg("density"), py::arg("fixed") = 0,
           "Adds a rigid clump of pebbles, its mass from the pebbles as solid spheres; returns its id.\n\n"
           "Args:\n"
           "    positions: pebble centres (m), N x 3.\n"
           "    radii: pebble radii (m), N.\n"
           "    density: (kg/m^3).\n"
           "    fixed: DOF bits held (DOF_X | ...).")
      .def("add_ring_stack",
           [](World& w, const RingStackSpec& spec) {
             std::vector<ClumpId> ids;
             for (const ClumpSpec& ring : make_ring_stack(spec)) ids.push_back(w.add_clump(ring));
             return ids;
           },
           py::arg("spec"), "Adds the rings of an NGI stack as clumps; returns their ids")
      // The derived law first: pybind11 takes the first overload that accepts the argument, and a
      // RollingLinearParams is also a LinearParams.
      .def("set_contact_model", &set_model<RollingLinearLaw::Params>, py::arg("kind"), py::arg("params"), py::arg("name") = "contact",
           "Sets the rolling-resistance linear law of a contact kind.\n\n"
           "Args:\n"
           "    kind: a ContactKind.\n"
           "    params: its parameters (ValueError names a bad one).\n"
           "    name: for messages and outputs.")
      .def("set_contact_model", &set_model<LinearParams>, py::arg("kind"), py::arg("params"), py::arg("name") = "contact",
           "Sets the linear law of a contact kind.\n\n"
           "Args:\n"
           "    kind: a ContactKind.\n"
           "    params: its parameters (ValueError names a bad one).\n"
           "    name: for messages and outputs.")
      .def("set_contact_law",
           [](World& w, ContactKind kind, const std::string& law, const py::dict& parameters, const std::string& name) {
             // The registry's row, its parameters at their defaults, then the given ones (each one named).
             const LawEntry& entry = contact_law(law, "law");
             LawValues values(entry.parameters);
             for (const auto& [key, value] : parameters) {
               const std::string k = key.cast<std::string>();
               if (!values.has(k)) {
                 std::string known;
                 for (const LawParameter& p : entry.parameters) known += (known.empty() ? "" : ", ") + p.name;
                 throw InputError(name + "." + k + ": not a parameter of contact law " + law + " (its parameters: " + known + ")");
               }
               const auto parameter = std::find_if(entry.parameters.begin(), entry.parameters.end(),
                                                   [&k](const LawParameter& p) { return p.name == k; });
               if (!parameter->choices.empty() && py::isinstance<py::str>(value))
                 values.set(k, parameter->choice_index(value.cast<std::string>(), name + "." + k));
               else
                 values.set(k, value.cast<double>());
             }
             w.set_contact_model(kind, entry.bind(values, name));
           },
           py::arg("kind"), py::arg("law"), py::arg("parameters") = py::dict(), py::arg("name") = "contact",
           "Sets a contact kind's law by its keyword, as the apps' `<type>.law` key does (contact_laws() lists them).\n\n"
           "Args:\n"
           "    kind: a ContactKind.\n"
           "    law: the keyword, e.g. 'rrlinear' or 'linear'.\n"
           "    parameters: {name: value} in SI units (e.g. {'effective_modulus': 1e8, 'friction': 0.5}); a named\n"
           "        choice by its name (e.g. {'damping_model': 'tsuji'}); the others keep the registry's defaults.\n"
           "    name: for messages.\n\n"
           "Raises:\n"
           "    ValueError: an unknown law or parameter, or a value the law cannot use, named.")
      .def("contact_law", [](const World& w, ContactKind kind) {
             const ContactModel* model = w.contact_model(kind);
             return model ? std::string(model->law_name()) : std::string();
           }, py::arg("kind"), "The name of the law set on a contact kind ('' if none)")
      .def("add_servo_wall", [](World& w, WallId id, const ServoSettings& s) { return add_servo_wall(w, id, s); },
           py::arg("wall"), py::arg("settings"),
           "Adds a servo on a wall as a controller of this World; returns it.\n\n"
           "Args:\n"
           "    wall: the wall's id.\n"
           "    settings: a ServoSettings.")
      .def("step", [](World& w, std::int64_t n) {
             py::gil_scoped_release release;
             w.step(n);
           }, py::arg("n") = 1,
           "Advances the simulation by n time steps (of time_step s each): contact forces, controllers,\n"
           "integration, callbacks. The GIL is released meanwhile; a Python controller or callback takes it back.\n\n"
           "Args:\n"
           "    n: steps to take.\n\n"
           "Raises:\n"
           "    InstabilityError: a run that went unstable, naming the particle, the step and the likely cause.")
      .def("run_until",
           [](World& w, py::function done, std::int64_t check_every, std::int64_t max_steps) {
             const PythonCall call(std::move(done));
             py::gil_scoped_release release;
             return w.run_until([&](const World& world) { return call(const_cast<World&>(world)).cast<bool>(); },
                                check_every, max_steps);
           },
           py::arg("done"), py::arg("check_every"), py::arg("max_steps"),
           "Steps until done(world) is true; returns False if max_steps came first.\n\n"
           "Args:\n"
           "    done: called with the World every check_every steps.\n"
           "    check_every: steps between two calls.\n"
           "    max_steps: steps after which it gives up.")
      .def("add_controller", [](World& w, py::function f) {
             const PythonCall call(std::move(f));
             w.add_controller([call](World& world) { call(world); });
           }, py::arg("controller"), "controller(world) runs every step after the forces, before integration")
      .def_property("contact_records", &World::contact_records, &World::set_contact_records,
                    "WHEN_READ (the last step of each step() call and before callbacks) or EVERY_STEP (for a "
                    "controller that reads contacts)")
      .def("add_callback", [](World& w, std::int64_t every, py::function f) {
             const PythonCall call(std::move(f));
             w.add_callback(every, [call](World& world) { call(world); });
           }, py::arg("every"), py::arg("callback"), "callback(world) runs after every `every` steps")
      .def_property_readonly("time", &World::time, "Simulated time (s)")
      .def_property_readonly("step_count", &World::step_count, "Steps taken")
      .def_property("time_step", &World::time_step, &World::set_time_step,
                    "Time step in use (s; 0 until the first step if automatic); setting one (> 0) turns the estimate off")
      .def("critical_time_step", &World::critical_time_step, "Critical time step estimate min over bodies of sqrt(m/K) (s)")
      .def("update_time_step", &World::update_time_step,
           "Re-estimates the automatic time step now (after generation or a stiffness change)")
      .def_property_readonly("threads", &World::threads, "The thread team (a step may run on fewer while the machine is busy)")
      .def("steps_on_threads", [](const World& w, int size) { return w.thread_team().steps_on(size); }, py::arg("size"),
           "Steps run so far on `size` threads (the team runs on fewer while that is faster)")
      .def("kinetic_energy", &World::kinetic_energy, "Translational and rotational kinetic energy of balls and clumps (J)")
      .def("unbalanced_force_ratio", &World::unbalanced_force_ratio,
           "Mean unbalanced force on free balls over the mean contact normal force (-, PFC's ratio)")
      .def("contact_count", &World::contact_count, py::arg("kind"), "Touching contacts of a ContactKind in the last step")
      .def("set_gravity", &World::set_gravity, py::arg("gravity"), "Sets the gravitational acceleration (m/s^2, a 3-vector)")
      .def("set_local_damping", &World::set_local_damping, py::arg("alpha"), "Sets the PFC local damping coefficient alpha (-, in [0, 1))")
      .def("set_damping_frame", &World::set_damping_frame, py::arg("frame"),
           "Sets the DampingFrame local damping measures velocities against; a protocol sets it every step; not saved")
      .def_property_readonly("damping_frame", [](const World& w) { return w.damping_frame(); },
                             "The DampingFrame of the last step, a copy: change it with set_damping_frame")
      // Views of the state in storage order (row i is ball ids[i]); valid until the next step.
      .def_property_readonly("size", [](const World& w) { return w.particles().size(); }, "Particles (balls and pebbles)")
      .def_property_readonly("positions", [](py::object self) { return vec3_view(self.cast<World&>().particles().x, self); },
                             "Centres (m), N x 3, storage order: a read-only view, valid until the next step")
      .def_property_readonly("velocities", [](py::object self) { return vec3_view(self.cast<World&>().particles().v, self); },
                             "Velocities (m/s), N x 3, storage order: a read-only view, valid until the next step")
      .def_property_readonly("spins", [](py::object self) { return vec3_view(self.cast<World&>().particles().w, self); },
                             "Angular velocities (rad/s), N x 3, storage order: a read-only view, valid until the next step")
      .def_property_readonly("forces", [](py::object self) { return vec3_view(self.cast<World&>().particles().f, self); },
                             "Forces of the last step (N), N x 3, storage order: a read-only view, valid until the next step")
      .def_property_readonly("torques", [](py::object self) { return vec3_view(self.cast<World&>().particles().t, self); },
                             "Torques of the last step (N m), N x 3, storage order: a read-only view, valid until the next step")
      .def_property_readonly("radii", [](py::object self) { return vector_view(self.cast<World&>().particles().radius, self); },
                             "Radii (m), storage order: a read-only view, valid until the next step")
      .def_property_readonly("masses", [](py::object self) { return vector_view(self.cast<World&>().particles().mass, self); },
                             "Masses (kg), storage order: a read-only view, valid until the next step")
      .def_property_readonly("ids", [](py::object self) { return vector_view(self.cast<World&>().particles().id, self); },
                             "Each storage row's particle id (storage is re-sorted at neighbour-list rebuilds)")
      .def_property_readonly("clump_of", [](py::object self) { return vector_view(self.cast<World&>().particles().clump, self); },
                             "-1 for a free ball, else the clump of the pebble, storage order")
      .def("index_of", [](const World& w, ParticleId id) { return w.particles().index_of(id); }, py::arg("id"),
           "The storage row of the particle `id` now")
      .def("set_velocities", [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& v) {
             const std::vector<Vec3> rows = rows_of(v, "velocities");
             require(rows.size() == w.particles().size(), "velocities rows", rows.size(), std::to_string(w.particles().size()));
             w.particles().v = rows;
           }, py::arg("velocities"), "Sets every particle's velocity (m/s), N x 3, storage order")
      .def("set_positions", [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& x) {
             const std::vector<Vec3> rows = rows_of(x, "positions");
             require(rows.size() == w.particles().size(), "positions rows", rows.size(), std::to_string(w.particles().size()));
             w.particles().x = rows;
             w.invalidate_contacts();
           }, py::arg("positions"), "Sets every particle's centre (m), N x 3, storage order (the contact lists are rebuilt)")
      .def("set_fixed", [](World& w, ParticleId id, int fixed) { w.particles().fixed[w.particles().index_of(id)] = static_cast<std::uint8_t>(fixed); },
           py::arg("id"), py::arg("fixed"), "Sets the DOF bits held (DOF_X | ...) of ball `id`")
      .def("contacts",
           [](const World& w) {
             std::vector<std::uint8_t> kind;
             std::vector<std::int64_t> first, second;
             std::vector<Vec3> normal, point, force;
             std::vector<double> normal_force;
             w.for_each_contact([&](const ContactView& c) {
               kind.push_back(static_cast<std::uint8_t>(c.kind));
               first.push_back(static_cast<std::int64_t>(c.first));
               second.push_back(c.second);
               normal.push_back(c.normal), point.push_back(c.point), force.push_back(c.force);
               normal_force.push_back(c.normal_force);
             });
             auto owned = [](auto&& v) { return py::array(py::cast(std::move(v))); };
             py::dict d;
             d["kind"] = owned(kind), d["first"] = owned(first), d["second"] = owned(second);
             d["normal"] = vec3_rows(normal), d["point"] = vec3_rows(point), d["force"] = vec3_rows(force);
             d["normal_force"] = owned(normal_force);
             return d;
           },
           "Touching contacts of the last step, copied: kind (ContactKind value), first (ball's storage index), second "
           "(ball or pebble storage index, or wall id), normal (first -> second), point (m), force (N, on second), "
           "normal_force (N, elastic, compression positive)")
      .def("measure", [](const World& w, const Vec3& centre, double radius) {
             MeasurementSphere s{centre, radius};
             s.validate();
             return measurement(dem::measure::measure(w, s));
           }, py::arg("centre"), py::arg("radius"),
           "A measurement sphere (docs/model.md 6) over the last step, as a dict: stress and stress_contacts (Pa,\n"
           "3 x 3, tension positive), porosity (-), coordination_number and mechanical_coordination_number (-), balls,\n"
           "contacts, fabric (-), strain_rate (1/s), principal_stresses (Pa) and principal_directions (columns).\n\n"
           "Args:\n"
           "    centre: the sphere's centre (m).\n"
           "    radius: (m).\n\n"
           "Raises:\n"
           "    ValueError: a sphere that holds no ball centre.")
      .def("save_state", [](const World& w, const std::filesystem::path& file) {
             io::write_atomically_binary(file, [&](std::ostream& out) { io::write_world_state(out, w); });
           }, py::arg("file"),
           "Writes the complete dynamic state to `file`, atomically; contact models and controllers are code, not state")
      .def("load_state", [](World& w, const std::filesystem::path& file) {
             std::ifstream in(file, std::ios::binary);
             require(static_cast<bool>(in), "state file", file.string(), "a readable file written by save_state");
             io::read_world_state(in, w);
           }, py::arg("file"),
           "Replaces the state with the one save_state wrote to `file` (set the same contact models first)");
  bind_periodic(m, world_class);
  bind_bonds(m, world_class);
}

}  // namespace dem::python
