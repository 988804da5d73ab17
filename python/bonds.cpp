// Bonds through Python (docs/cementation.md): a cement's material, World.add_bond and cement() to
// make bonds, and World.bonds() to read them, copied into NumPy arrays in bond order.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <vector>

#include <dem/contact/bond_material.hpp>
#include <dem/contact/bond_store.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/toolkit/cementation.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

namespace {

template <class T>
py::array copied(const std::vector<T>& v) {
  return py::array(py::cast(v));
}

py::dict bonds_of(const World& world) {
  const BondStore& b = world.bonds();
  py::dict d;
  d["first"] = copied(b.first), d["second"] = copied(b.second);
  d["radius"] = copied(b.radius);
  d["normal_stiffness"] = copied(b.normal_stiffness), d["shear_stiffness"] = copied(b.shear_stiffness);
  d["tensile_strength"] = copied(b.tensile_strength), d["cohesion"] = copied(b.cohesion);
  d["friction_angle"] = copied(b.friction_angle);
  d["normal_force"] = copied(b.normal_force), d["shear_force"] = vec3_rows(b.shear_force);
  d["twist_moment"] = copied(b.twist_moment), d["bend_moment"] = vec3_rows(b.bend_moment);
  d["status"] = copied(b.status);
  std::vector<double> energy(b.size());
  for (std::size_t k = 0; k < b.size(); ++k) energy[k] = ParallelBondLaw::strain_energy(b.params(k), b.state(k));
  d["strain_energy"] = copied(energy);
  return d;
}

}  // namespace

void bind_bonds(py::module_& m, py::class_<World>& world) {
  py::class_<ParallelBondMaterial>(m, "BondMaterial",
                                   "A cement (docs/cementation.md): the linear parallel bond's stiffnesses per area and the mean\n"
                                   "and standard deviation of its strengths, each bond's own drawn from (seed, the two ball ids)")
      .def(py::init([](double radius_multiplier, double normal_stiffness, double shear_stiffness, double tensile_strength,
                       double cohesion, double friction_angle, double tensile_strength_std, double cohesion_std,
                       std::uint64_t seed) {
             ParallelBondMaterial p{radius_multiplier, normal_stiffness, shear_stiffness, tensile_strength,
                                    tensile_strength_std, cohesion, cohesion_std, friction_angle, seed};
             p.validate("BondMaterial");
             return p;
           }),
           py::kw_only(), py::arg("radius_multiplier") = 1.0, py::arg("normal_stiffness"), py::arg("shear_stiffness"),
           py::arg("tensile_strength"), py::arg("cohesion"), py::arg("friction_angle") = 0.0,
           py::arg("tensile_strength_std") = 0.0, py::arg("cohesion_std") = 0.0, py::arg("seed") = 1,
           "A cement, validated (ValueError naming the parameter).\n\n"
           "Args:\n"
           "    radius_multiplier: lambda, the bond's radius lambda min(R1, R2) (-, in (0, 1]).\n"
           "    normal_stiffness: kn per area (Pa/m).\n"
           "    shear_stiffness: ks per area (Pa/m).\n"
           "    tensile_strength: mean sigma_c (Pa).\n"
           "    cohesion: mean c (Pa).\n"
           "    friction_angle: phi (rad, in [0, pi/2)).\n"
           "    tensile_strength_std: standard deviation of sigma_c (Pa).\n"
           "    cohesion_std: standard deviation of c (Pa).\n"
           "    seed: the key of the strengths' draw (-).")
      .def_readonly("radius_multiplier", &ParallelBondMaterial::radius_multiplier, "lambda (-)")
      .def_readonly("normal_stiffness", &ParallelBondMaterial::normal_stiffness, "kn per area (Pa/m)")
      .def_readonly("shear_stiffness", &ParallelBondMaterial::shear_stiffness, "ks per area (Pa/m)")
      .def_readonly("tensile_strength", &ParallelBondMaterial::tensile_strength, "Mean tensile strength (Pa)")
      .def_readonly("tensile_strength_std", &ParallelBondMaterial::tensile_strength_std, "Its standard deviation (Pa)")
      .def_readonly("cohesion", &ParallelBondMaterial::cohesion, "Mean cohesion (Pa)")
      .def_readonly("cohesion_std", &ParallelBondMaterial::cohesion_std, "Its standard deviation (Pa)")
      .def_readonly("friction_angle", &ParallelBondMaterial::friction_angle, "Friction angle of the bond's shear strength (rad)")
      .def_readonly("seed", &ParallelBondMaterial::seed, "The key of the strengths' draw");

  world
      .def("add_bond",
           [](World& w, ParticleId a, ParticleId b, const ParallelBondMaterial& material) {
             const ParticleStore& p = w.particles();
             require(a >= 0 && static_cast<std::size_t>(a) < p.size(), "bond ball id a", a, "an id of this World");
             require(b >= 0 && static_cast<std::size_t>(b) < p.size(), "bond ball id b", b, "an id of this World");
             return w.add_bond(a, b, material.draw(a, b, p.radius[p.index_of(a)], p.radius[p.index_of(b)]));
           },
           py::arg("a"), py::arg("b"), py::arg("material"),
           "Bonds balls `a` and `b` (particle ids) with a linear parallel bond of `material`, unloaded now;\n"
           "returns its index in bonds(). ValueError for a pebble, the same ball twice or an unknown id.")
      .def("bonds", &bonds_of,
           "The bonds, copied, in bond order, as a dict of arrays: first, second (ball ids), radius (m),\n"
           "normal_stiffness and shear_stiffness (Pa/m), tensile_strength and cohesion (Pa), friction_angle (rad),\n"
           "normal_force (N, tension positive), shear_force (N, k x 3), twist_moment (N m), bend_moment (N m, k x 3),\n"
           "the loads on the second ball (a broken bond keeps those it broke under), status (0 intact, 1 broken\n"
           "in tension, 2 in shear) and strain_energy (J, held now; of a broken bond, released when it broke)")
      .def_property_readonly("bond_energy_released", [](const World& w) { return w.bonds().released_energy(); },
                             "The strain energy the broken bonds held when they broke, summed (J)");

  m.def("cement", &lab::cement, py::arg("world"), py::arg("material"), py::arg("gap_ratio"), py::arg("fraction") = 1.0,
        "Bonds every pair of free balls of `world` whose gap is below gap_ratio x their mean radius\n"
        "(overlapping pairs included), or the `fraction` of them chosen per pair from the material's seed;\n"
        "returns how many bonds it made (docs/cementation.md). Pairs already bonded are left as they are.\n\n"
        "Args:\n"
        "    world: the World, its balls placed.\n"
        "    material: a BondMaterial.\n"
        "    gap_ratio: the largest gap over the pair's mean radius (-), within the World's skin.\n"
        "    fraction: of those pairs bonded (-, in (0, 1]).");
}

}  // namespace dem::python
