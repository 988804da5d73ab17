// The contact laws from Python: the linear family's parameters as classes (World.set_contact_model),
// and the registry of laws by keyword (core/law_registry.hpp: contact_laws(), and
// World.set_contact_law in engine.cpp).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <dem/core/law_registry.hpp>
#include <dem/contact/linear_law.hpp>

#include "bindings.hpp"

namespace py = pybind11;

namespace dem::python {

void bind_contact_laws(py::module_& m) {
  py::class_<LinearParams>(m, "LinearParams",
                           "Linear spring-dashpot-slider law (docs/model.md 3): stiffness from an effective modulus (deformability\n"
                           "method) or constant per contact type, Coulomb friction, optional dashpots")
      .def(py::init<>(), "Every parameter 0: set the stiffness and friction before use")
      .def_static("deformable", &LinearParams::deformable, py::arg("effective_modulus"), py::arg("stiffness_ratio"), py::arg("friction"),
                  "Parameters by the deformability method (the study's Table 1 form): kn = pi rbar^2 E* / L, ks = kn / kappa*.\n\n"
                  "Args:\n"
                  "    effective_modulus: E* (Pa).\n"
                  "    stiffness_ratio: kappa* = kn / ks (-).\n"
                  "    friction: Coulomb coefficient mu (-).")
      .def_static("constant", &LinearParams::constant, py::arg("normal_stiffness"), py::arg("shear_stiffness"), py::arg("friction"),
                  "Parameters with the same kn and ks for every contact of the type.\n\n"
                  "Args:\n"
                  "    normal_stiffness: kn (N/m).\n"
                  "    shear_stiffness: ks (N/m).\n"
                  "    friction: Coulomb coefficient mu (-).")
      .def_readwrite("effective_modulus", &LinearParams::effective_modulus, "E* (Pa); 0: the constant stiffnesses are used")
      .def_readwrite("stiffness_ratio", &LinearParams::stiffness_ratio, "kappa* = kn / ks of the deformability method (-)")
      .def_readwrite("normal_stiffness", &LinearParams::normal_stiffness, "Constant kn (N/m), when effective_modulus is 0")
      .def_readwrite("shear_stiffness", &LinearParams::shear_stiffness, "Constant ks (N/m), when effective_modulus is 0")
      .def_readwrite("friction", &LinearParams::friction, "Coulomb coefficient mu (-)")
      .def_readwrite("normal_damping_ratio", &LinearParams::normal_damping_ratio,
                     "beta_n (-): normal dashpot c_n = 2 beta_n sqrt(m_eff kn)")
      .def_readwrite("shear_damping_ratio", &LinearParams::shear_damping_ratio, "beta_s (-): shear dashpot c_s = 2 beta_s sqrt(m_eff ks)")
      .def_readwrite("normal_damping_rate", &LinearParams::normal_damping_rate,
                     "gamma_n (1/s): normal dashpot c_n = gamma_n m_eff (LAMMPS mass_velocity)")
      .def_readwrite("shear_damping_rate", &LinearParams::shear_damping_rate, "gamma_s (1/s): shear dashpot c_s = gamma_s m_eff");
  py::class_<RollingLinearLaw::Params, LinearParams>(m, "RollingLinearParams", "Linear law with rolling resistance (docs/model.md 3.3)")
      .def(py::init<>(), "Every parameter 0: set the stiffness and friction before use")
      .def_static("deformable", &RollingLinearLaw::Params::deformable, py::arg("effective_modulus"), py::arg("stiffness_ratio"),
                  py::arg("friction"), py::arg("rolling_friction"),
                  "Parameters by the deformability method, with rolling resistance.\n\n"
                  "Args:\n"
                  "    effective_modulus: E* (Pa).\n"
                  "    stiffness_ratio: kappa* = kn / ks (-).\n"
                  "    friction: Coulomb coefficient mu (-).\n"
                  "    rolling_friction: rolling resistance coefficient mu_r (-).")
      .def_static("constant", &RollingLinearLaw::Params::constant, py::arg("normal_stiffness"), py::arg("shear_stiffness"),
                  py::arg("friction"), py::arg("rolling_friction"),
                  "Constant kn and ks, with rolling resistance.\n\n"
                  "Args:\n"
                  "    normal_stiffness: kn (N/m).\n"
                  "    shear_stiffness: ks (N/m).\n"
                  "    friction: Coulomb coefficient mu (-).\n"
                  "    rolling_friction: rolling resistance coefficient mu_r (-).")
      .def_readwrite("rolling_friction", &RollingLinearLaw::Params::rolling_friction, "Rolling resistance coefficient mu_r (-)");

  m.def("contact_laws", [] {
    py::list laws;
    for (const LawEntry& law : contact_laws()) {
      py::dict row, parameters;
      row["keyword"] = law.keyword;
      row["summary"] = law.summary;
      for (const LawParameter& p : law.parameters) {
        py::dict d;
        d["unit"] = p.unit;
        d["default"] = p.default_value;
        d["help"] = p.help;
        if (!p.choices.empty()) d["choices"] = p.choices;  // the value is the index of one
        parameters[py::str(p.name)] = d;
      }
      row["parameters"] = parameters;
      laws.append(row);
    }
    return laws;
  }, "The contact laws by keyword (core/law_registry.hpp): a list of {'keyword', 'summary', 'parameters':\n"
     "{name: {'unit', 'default', 'help'[, 'choices']}}}, the first the default of every contact type.");
}

}  // namespace dem::python
