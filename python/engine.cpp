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

#include <fstream>
#include <memory>

#include <dem/boundary/clump_ring.hpp>
#include <dem/control/servo_wall.hpp>
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
  py::enum_<ContactKind>(m, "ContactKind")
      .value("BALL_BALL", ContactKind::BallBall)
      .value("BALL_FACET", ContactKind::BallFacet)
      .value("BALL_PEBBLE", ContactKind::BallPebble);
  py::enum_<World::ContactRecords>(m, "ContactRecords",
                                   "Which steps record the pair contacts' forces (World::ContactRecords)")
      .value("WHEN_READ", World::ContactRecords::WhenRead)
      .value("EVERY_STEP", World::ContactRecords::EveryStep);
  m.attr("DOF_X") = int(dof_x), m.attr("DOF_Y") = int(dof_y), m.attr("DOF_Z") = int(dof_z);
  m.attr("DOF_TRANSLATION") = int(dof_translation), m.attr("DOF_ROTATION") = int(dof_rotation), m.attr("DOF_ALL") = int(dof_all);

  py::class_<WorldSettings>(m, "WorldSettings", "Engine settings (SI units); 0 means automatic where noted")
      .def(py::init<>())
      .def_readwrite("time_step", &WorldSettings::time_step, "s; 0: from stiffnesses and masses")
      .def_readwrite("time_step_safety", &WorldSettings::time_step_safety)
      .def_readwrite("local_damping", &WorldSettings::local_damping)
      .def_readwrite("gravity", &WorldSettings::gravity, "m/s^2")
      .def_readwrite("skin", &WorldSettings::skin, "m; 0: half the smallest radius")
      .def_readwrite("sort_every", &WorldSettings::sort_every)
      .def_readwrite("threads", &WorldSettings::threads, "0: OMP_NUM_THREADS")
      .def_readwrite("max_overlap_ratio", &WorldSettings::max_overlap_ratio)
      .def_readwrite("max_step_travel_ratio", &WorldSettings::max_step_travel_ratio)
      .def_readwrite("pebble_pebble_contacts", &WorldSettings::pebble_pebble_contacts);

  py::class_<DampingFrame>(m, "DampingFrame",
                           "Velocity field local damping measures velocities against: velocity + (z - height) velocity_gradient "
                           "(docs/model.md 3.1); the default is the fixed frame")
      .def(py::init<>())
      .def_readwrite("velocity", &DampingFrame::velocity, "m/s, at z = height")
      .def_readwrite("height", &DampingFrame::height, "m")
      .def_readwrite("velocity_gradient", &DampingFrame::velocity_gradient, "1/s, dv/dz")
      .def("velocity_at", &DampingFrame::velocity_at, py::arg("x"))
      .def("spin", &DampingFrame::spin, "rad/s, half the vorticity");

  py::class_<LinearParams>(m, "LinearParams", "Linear spring-dashpot-slider law (docs/model.md 3)")
      .def(py::init<>())
      .def_static("deformable", &LinearParams::deformable, py::arg("effective_modulus"), py::arg("stiffness_ratio"), py::arg("friction"))
      .def_static("constant", &LinearParams::constant, py::arg("normal_stiffness"), py::arg("shear_stiffness"), py::arg("friction"))
      .def_readwrite("effective_modulus", &LinearParams::effective_modulus)
      .def_readwrite("stiffness_ratio", &LinearParams::stiffness_ratio)
      .def_readwrite("normal_stiffness", &LinearParams::normal_stiffness)
      .def_readwrite("shear_stiffness", &LinearParams::shear_stiffness)
      .def_readwrite("friction", &LinearParams::friction)
      .def_readwrite("normal_damping_ratio", &LinearParams::normal_damping_ratio)
      .def_readwrite("shear_damping_ratio", &LinearParams::shear_damping_ratio)
      .def_readwrite("normal_damping_rate", &LinearParams::normal_damping_rate)
      .def_readwrite("shear_damping_rate", &LinearParams::shear_damping_rate);
  py::class_<RollingLinearLaw::Params, LinearParams>(m, "RollingLinearParams", "Linear law with rolling resistance (docs/model.md 3.3)")
      .def(py::init<>())
      .def_static("deformable", &RollingLinearLaw::Params::deformable, py::arg("effective_modulus"), py::arg("stiffness_ratio"),
                  py::arg("friction"), py::arg("rolling_friction"))
      .def_static("constant", &RollingLinearLaw::Params::constant, py::arg("normal_stiffness"), py::arg("shear_stiffness"),
                  py::arg("friction"), py::arg("rolling_friction"))
      .def_readwrite("rolling_friction", &RollingLinearLaw::Params::rolling_friction);

  py::class_<geometry::TriangleMesh>(m, "TriangleMesh", "Triangles of a facet wall (m)")
      .def_property_readonly("vertices", [](const geometry::TriangleMesh& mesh) {
        py::array_t<double> a({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
          for (int k = 0; k < 3; ++k) a.mutable_at(static_cast<py::ssize_t>(i), k) = mesh.vertices[i][k];
        return a;
      })
      .def_property_readonly("triangles", [](const geometry::TriangleMesh& mesh) { return mesh.triangles; })
      .def("area", &geometry::TriangleMesh::area);
  m.def("make_disc", &geometry::make_disc, py::arg("centre"), py::arg("radius"), py::arg("normal"), py::arg("segments") = 24);
  m.def("make_rectangle", &geometry::make_rectangle, py::arg("centre"), py::arg("half_u"), py::arg("half_v"));
  m.def("make_cylinder_shell", &geometry::make_cylinder_shell, py::arg("base_centre"), py::arg("radius"), py::arg("height"),
        py::arg("segments") = 48, py::arg("normals_inward") = true);
  m.def("read_stl", &geometry::read_stl_ascii, py::arg("file"), py::arg("scale") = 1.0, "An ASCII STL file; scale converts its units to m");

  py::class_<WallRef>(m, "Wall", "A wall of a World (facets, or an analytic plane or cylinder), by id")
      .def_property_readonly("id", [](const WallRef& r) { return r.id; })
      .def_property_readonly("name", [](const WallRef& r) { return r.wall().name; })
      .def_property("velocity", [](const WallRef& r) { return r.wall().velocity; },
                    [](const WallRef& r, const Vec3& v) { r.wall().velocity = v; }, "m/s, rigid translation")
      .def_property_readonly("displacement", [](const WallRef& r) { return r.wall().displacement; }, "m since added")
      .def_property_readonly("force", [](const WallRef& r) { return r.wall().force; }, "N, of the balls on the wall, last step")
      .def_property_readonly("normal_stress", [](const WallRef& r) { return r.wall().normal_stress(); }, "Pa, compression positive")
      .def_property_readonly("contact_count", [](const WallRef& r) { return r.wall().contact_count; })
      .def_property_readonly("area", [](const WallRef& r) { return r.wall().area; });

  py::class_<ServoSettings>(m, "ServoSettings")
      .def(py::init([](double target_stress, double max_speed, double relaxation, double settle_tolerance, int settle_steps) {
             ServoSettings s;
             s.target_stress = target_stress, s.max_speed = max_speed, s.relaxation = relaxation;
             s.settle_tolerance = settle_tolerance, s.settle_steps = settle_steps;
             return s;
           }),
           py::arg("target_stress"), py::arg("max_speed"), py::arg("relaxation") = 0.5, py::arg("settle_tolerance") = 0.01,
           py::arg("settle_steps") = 100);
  py::class_<ServoWall, std::shared_ptr<ServoWall>>(m, "ServoWall", "Holds a target normal stress on a wall (docs/model.md 5)")
      .def(py::init<WallId, ServoSettings>(), py::arg("wall"), py::arg("settings"),
           "A servo a protocol's controller runs itself (world.add_servo_wall registers one as a controller)")
      .def("__call__", &ServoWall::operator(), py::arg("world"), "One control step: sets the wall's normal velocity")
      .def("set_target", &ServoWall::set_target, py::arg("stress"))
      .def("set_max_speed", &ServoWall::set_max_speed, py::arg("max_speed"))
      .def("hold_position", &ServoWall::hold_position, py::arg("hold"))
      .def_property_readonly("target", &ServoWall::target)
      .def_property_readonly("achieved_stress", &ServoWall::achieved_stress)
      .def_property_readonly("settled", &ServoWall::settled)
      .def_property_readonly("gain", &ServoWall::gain);

  py::class_<RingStackSpec>(m, "RingStackSpec", "An NGI stack of pebble rings (docs/model.md 4)")
      .def(py::init<>())
      .def_readwrite("base_centre", &RingStackSpec::base_centre)
      .def_readwrite("inner_radius", &RingStackSpec::inner_radius)
      .def_readwrite("height", &RingStackSpec::height)
      .def_readwrite("ring_count", &RingStackSpec::ring_count)
      .def_readwrite("ring_height", &RingStackSpec::ring_height)
      .def_readwrite("pebble_radius", &RingStackSpec::pebble_radius)
      .def_readwrite("gap", &RingStackSpec::gap)
      .def_readwrite("ring_density", &RingStackSpec::ring_density)
      .def_readwrite("max_opening", &RingStackSpec::max_opening)
      .def_readwrite("fixed", &RingStackSpec::fixed);

  py::class_<World>(m, "World", "A simulation: balls, clumps, facet walls, contact laws and the clock")
      .def(py::init<WorldSettings>(), py::arg("settings") = WorldSettings{})
      .def("add_ball",
           [](World& w, const Vec3& position, double radius, double density, const Vec3& velocity, int group, int fixed) {
             BallSpec b;
             b.position = position, b.radius = radius, b.density = density, b.velocity = velocity, b.group = group;
             b.fixed = static_cast<std::uint8_t>(fixed);
             return w.add_ball(b);
           },
           py::arg("position"), py::arg("radius"), py::arg("density"), py::arg("velocity") = Vec3::Zero().eval(),
           py::arg("group") = 0, py::arg("fixed") = 0, "Adds a ball (m, m, kg/m^3, m/s); returns its id")
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
           py::arg("positions"), py::arg("radii"), py::arg("density"), "Adds N balls from N x 3 positions and N radii; returns their ids")
      .def("add_wall",
           [](World& w, const std::string& name, const geometry::TriangleMesh& mesh, const Vec3& outward_normal, double area) {
             return WallRef{&w, w.add_wall(make_facet_wall(name, mesh, outward_normal, area))};
           },
           py::arg("name"), py::arg("mesh"), py::arg("outward_normal"), py::arg("area") = 0.0, py::keep_alive<0, 1>())
      .def("add_plane_wall",
           [](World& w, const std::string& name, const Vec3& point, const Vec3& outward_normal, double area) {
             return WallRef{&w, w.add_wall(make_plane_wall(name, point, outward_normal, area))};
           },
           py::arg("name"), py::arg("point"), py::arg("outward_normal"), py::arg("area"), py::keep_alive<0, 1>(),
           "Adds an analytic infinite plane (the ball-facet law; area in m^2 for stresses and servos)")
      .def("add_cylinder_wall",
           [](World& w, const std::string& name, const Vec3& axis_point, const Vec3& axis, double radius, double area) {
             return WallRef{&w, w.add_wall(make_cylinder_wall(name, axis_point, axis, radius, area))};
           },
           py::arg("name"), py::arg("axis_point"), py::arg("axis"), py::arg("radius"), py::arg("area"),
           py::keep_alive<0, 1>(), "Adds an analytic infinite cylinder (the ball-facet law), for balls inside or outside")
      .def("wall", [](World& w, WallId id) {
             require(id >= 0 && static_cast<std::size_t>(id) < w.walls().size(), "wall id", id, "0 <= id < " + std::to_string(w.walls().size()));
             return WallRef{&w, id};
           }, py::keep_alive<0, 1>())
      .def_property_readonly("wall_count", [](const World& w) { return w.walls().size(); })
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
           "A rigid clump of pebbles (m), its mass from the pebbles as solid spheres; returns its id")
      .def("add_ring_stack",
           [](World& w, const RingStackSpec& spec) {
             std::vector<ClumpId> ids;
             for (const ClumpSpec& ring : make_ring_stack(spec)) ids.push_back(w.add_clump(ring));
             return ids;
           },
           py::arg("spec"), "The rings of an NGI stack as clumps; returns their ids")
      // The derived law first: pybind11 takes the first overload that accepts the argument, and a
      // RollingLinearParams is also a LinearParams.
      .def("set_contact_model", &set_model<RollingLinearLaw::Params>, py::arg("kind"), py::arg("params"), py::arg("name") = "contact")
      .def("set_contact_model", &set_model<LinearParams>, py::arg("kind"), py::arg("params"), py::arg("name") = "contact")
      .def("contact_law", [](const World& w, ContactKind kind) {
             const ContactModel* model = w.contact_model(kind);
             return model ? std::string(model->law_name()) : std::string();
           }, py::arg("kind"), "The name of the law set on a contact kind ('' if none)")
      .def("add_servo_wall", [](World& w, WallId id, const ServoSettings& s) { return add_servo_wall(w, id, s); },
           py::arg("wall"), py::arg("settings"))
      .def("step", [](World& w, std::int64_t n) {
             py::gil_scoped_release release;
             w.step(n);
           }, py::arg("n") = 1, "Advances n steps (the GIL is released meanwhile)")
      .def("run_until",
           [](World& w, py::function done, std::int64_t check_every, std::int64_t max_steps) {
             const PythonCall call(std::move(done));
             py::gil_scoped_release release;
             return w.run_until([&](const World& world) { return call(const_cast<World&>(world)).cast<bool>(); },
                                check_every, max_steps);
           },
           py::arg("done"), py::arg("check_every"), py::arg("max_steps"), "Steps until done(world) is true; False if max_steps came first")
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
           }, py::arg("every"), py::arg("callback"))
      .def_property_readonly("time", &World::time, "s")
      .def_property_readonly("step_count", &World::step_count)
      .def_property("time_step", &World::time_step, &World::set_time_step, "s")
      .def("critical_time_step", &World::critical_time_step)
      .def("update_time_step", &World::update_time_step)
      .def_property_readonly("threads", &World::threads)
      .def("kinetic_energy", &World::kinetic_energy, "J")
      .def("unbalanced_force_ratio", &World::unbalanced_force_ratio)
      .def("contact_count", &World::contact_count, py::arg("kind"))
      .def("set_gravity", &World::set_gravity)
      .def("set_local_damping", &World::set_local_damping)
      .def("set_damping_frame", &World::set_damping_frame, py::arg("frame"), "set every step by the protocol that uses it; not saved")
      .def_property_readonly("damping_frame", [](const World& w) { return w.damping_frame(); },
                             "a copy: change it with set_damping_frame")
      // Views of the state in storage order (row i is ball ids[i]); valid until the next step.
      .def_property_readonly("size", [](const World& w) { return w.particles().size(); })
      .def_property_readonly("positions", [](py::object self) { return vec3_view(self.cast<World&>().particles().x, self); }, "m, N x 3")
      .def_property_readonly("velocities", [](py::object self) { return vec3_view(self.cast<World&>().particles().v, self); }, "m/s")
      .def_property_readonly("spins", [](py::object self) { return vec3_view(self.cast<World&>().particles().w, self); }, "rad/s")
      .def_property_readonly("forces", [](py::object self) { return vec3_view(self.cast<World&>().particles().f, self); }, "N")
      .def_property_readonly("torques", [](py::object self) { return vec3_view(self.cast<World&>().particles().t, self); }, "N m")
      .def_property_readonly("radii", [](py::object self) { return vector_view(self.cast<World&>().particles().radius, self); }, "m")
      .def_property_readonly("masses", [](py::object self) { return vector_view(self.cast<World&>().particles().mass, self); }, "kg")
      .def_property_readonly("ids", [](py::object self) { return vector_view(self.cast<World&>().particles().id, self); })
      .def_property_readonly("clump_of", [](py::object self) { return vector_view(self.cast<World&>().particles().clump, self); },
                             "-1 for a free ball, else the clump of the pebble")
      .def("index_of", [](const World& w, ParticleId id) { return w.particles().index_of(id); }, py::arg("id"))
      .def("set_velocities", [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& v) {
             const std::vector<Vec3> rows = rows_of(v, "velocities");
             require(rows.size() == w.particles().size(), "velocities rows", rows.size(), std::to_string(w.particles().size()));
             w.particles().v = rows;
           }, "N x 3, m/s, storage order")
      .def("set_positions", [](World& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& x) {
             const std::vector<Vec3> rows = rows_of(x, "positions");
             require(rows.size() == w.particles().size(), "positions rows", rows.size(), std::to_string(w.particles().size()));
             w.particles().x = rows;
             w.invalidate_contacts();
           }, "N x 3, m, storage order (the contact lists are rebuilt)")
      .def("set_fixed", [](World& w, ParticleId id, int fixed) { w.particles().fixed[w.particles().index_of(id)] = static_cast<std::uint8_t>(fixed); },
           py::arg("id"), py::arg("fixed"), "Dof bits (DOF_X | ...) held of ball `id`")
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
             auto rows = [](const std::vector<Vec3>& v) {
               py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
               auto r = a.mutable_unchecked<2>();
               for (std::size_t i = 0; i < v.size(); ++i)
                 for (int k = 0; k < 3; ++k) r(static_cast<py::ssize_t>(i), k) = v[i][k];
               return a;
             };
             py::dict d;
             d["kind"] = owned(kind), d["first"] = owned(first), d["second"] = owned(second);
             d["normal"] = rows(normal), d["point"] = rows(point), d["force"] = rows(force);
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
           }, py::arg("centre"), py::arg("radius"), "A measurement sphere (docs/model.md 6): stresses in Pa, tension positive")
      .def("save_state", [](const World& w, const std::filesystem::path& file) {
             io::write_atomically_binary(file, [&](std::ostream& out) { io::write_world_state(out, w); });
           }, py::arg("file"), "The complete dynamic state, written atomically; models and controllers are code, not state")
      .def("load_state", [](World& w, const std::filesystem::path& file) {
             std::ifstream in(file, std::ios::binary);
             require(static_cast<bool>(in), "state file", file.string(), "a readable file written by save_state");
             io::read_world_state(in, w);
           }, py::arg("file"));
}

}  // namespace dem::python
