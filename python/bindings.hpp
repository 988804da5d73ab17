// The parts of the Python module, each binding one floor of the library.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

#include <dem/base/math.hpp>

namespace dem {
class World;
}

namespace dem::python {

/// `v` copied into a new N x 3 array (m, N, ... as the vectors hold).
inline pybind11::array_t<double> vec3_rows(const std::vector<Vec3>& v) {
  pybind11::array_t<double> a({static_cast<pybind11::ssize_t>(v.size()), pybind11::ssize_t{3}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) r(static_cast<pybind11::ssize_t>(i), k) = v[i][k];
  return a;
}

void bind_contact_laws(pybind11::module_& m);  // the linear laws' parameters, the registry of laws by keyword (from bind_engine)
void bind_engine(pybind11::module_& m);   // World, particles, laws, walls, clumps, rings, servo, measurement
void bind_periodic(pybind11::module_& m, pybind11::class_<World>& world);  // the periodic cell, its stress and servo (from bind_engine)
void bind_bonds(pybind11::module_& m, pybind11::class_<World>& world);    // bond materials, World.add_bond and bonds(), cement() (from bind_engine)
void bind_toolkit(pybind11::module_& m);  // the lab toolkit's parts: cell, radius expansion, consolidation, shear legs
void bind_history(pybind11::module_& m);  // the history log and the parts that add its columns
void bind_lab(pybind11::module_& m);      // the simple-shear and cyclic-shear protocols

}  // namespace dem::python
