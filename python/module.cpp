// The Python module `libdem`: errors first (bad input raises ValueError with the library's message,
// an instability libdem.InstabilityError), then the engine, the lab toolkit and the lab protocols.
#include <pybind11/pybind11.h>

#include <dem/core/errors.hpp>

#include "bindings.hpp"

namespace py = pybind11;

PYBIND11_MODULE(libdem, m) {
  m.doc() =
      "libdem: discrete element method for geotechnical laboratory tests (SI units throughout: m, kg, s, N, Pa).\n\n"
      "The engine: World (balls, clumps, walls, contact laws, the clock; step() advances it), WorldSettings,\n"
      "LinearParams and RollingLinearParams per ContactKind, walls from make_disc, make_rectangle,\n"
      "make_cylinder_shell and read_stl or analytic ones, ServoWall, measurement spheres (World.measure).\n"
      "The lab toolkit: build_shear_cell, radius expansion, consolidate, shear legs, HistoryLog.\n"
      "The lab protocols: SimpleShear and CyclicShear, as the apps run them, with progress lines.\n\n"
      "DOF_X, DOF_Y, DOF_Z (and DOF_TRANSLATION, DOF_ROTATION, DOF_ALL) are the bits of a `fixed` argument:\n"
      "the degrees of freedom held. Bad input raises ValueError naming the key or argument, the value and what\n"
      "is allowed; a run that goes unstable raises InstabilityError.";
  static py::exception<dem::InstabilityError> instability(m, "InstabilityError", PyExc_RuntimeError);
  instability.attr("__doc__") =
      "A run that went unstable (NaN, runaway overlap or speed); the message names the particle, the step and the likely cause";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const dem::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const dem::InstabilityError& e) {
      instability(e.what());
    }
  });
  dem::python::bind_engine(m);
  dem::python::bind_toolkit(m);
  dem::python::bind_history(m);
  dem::python::bind_lab(m);
}
