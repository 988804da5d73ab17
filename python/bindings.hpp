// The parts of the Python module, each binding one floor of the library.
#pragma once

#include <pybind11/pybind11.h>

namespace dem {
class World;
}

namespace dem::python {

void bind_contact_laws(pybind11::module_& m);  // the linear laws' parameters, the registry of laws by keyword (from bind_engine)
void bind_engine(pybind11::module_& m);   // World, particles, laws, walls, clumps, rings, servo, measurement
void bind_periodic(pybind11::module_& m, pybind11::class_<World>& world);  // the periodic cell, its stress and servo (from bind_engine)
void bind_bonds(pybind11::module_& m, pybind11::class_<World>& world);    // bond materials, World.add_bond and bonds(), cement() (from bind_engine)
void bind_toolkit(pybind11::module_& m);  // the lab toolkit's parts: cell, radius expansion, consolidation, shear legs
void bind_history(pybind11::module_& m);  // the history log and the parts that add its columns
void bind_lab(pybind11::module_& m);      // the simple-shear and cyclic-shear protocols

}  // namespace dem::python
