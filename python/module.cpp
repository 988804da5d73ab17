// The Python module `libdem`: errors first (bad input raises ValueError with the library's message,
// an instability libdem.InstabilityError), then the engine, the lab toolkit and the lab protocols.
#include <pybind11/pybind11.h>

#include <dem/core/errors.hpp>

#include "bindings.hpp"

namespace py = pybind11;

PYBIND11_MODULE(libdem, m) {
  m.doc() = "libdem: discrete element method for geotechnical laboratory tests (SI units throughout)";
  static py::exception<dem::InstabilityError> instability(m, "InstabilityError", PyExc_RuntimeError);
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
