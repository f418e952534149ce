#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "deployfx/material/laminate.hpp"
#include "deployfx/material/orthotropic.hpp"

namespace py = pybind11;
using deployfx::material::Laminate;
using deployfx::material::Orthotropic;
using deployfx::material::Ply;

void define_material(py::module_& m) {
  py::class_<Orthotropic>(m, "Orthotropic")
      .def(py::init<double, double, double, double, double, double, double>(), py::arg("E1"),
           py::arg("E2"), py::arg("G12"), py::arg("G13"), py::arg("G23"), py::arg("nu12"),
           py::arg("rho"))
      .def_static("isotropic", &Orthotropic::isotropic, py::arg("E"), py::arg("nu"), py::arg("rho"))
      .def_property_readonly("E1", &Orthotropic::E1)
      .def_property_readonly("E2", &Orthotropic::E2)
      .def_property_readonly("G12", &Orthotropic::G12)
      .def_property_readonly("G13", &Orthotropic::G13)
      .def_property_readonly("G23", &Orthotropic::G23)
      .def_property_readonly("nu12", &Orthotropic::nu12)
      .def_property_readonly("rho", &Orthotropic::rho)
      .def("Q", &Orthotropic::Q)
      .def("Q_bar", &Orthotropic::Q_bar, py::arg("theta"))
      .def("Qs_bar", &Orthotropic::Qs_bar, py::arg("theta"));

  py::class_<Ply>(m, "Ply")
      .def(py::init<Orthotropic, double, double>(), py::arg("material"), py::arg("thickness"),
           py::arg("angle_deg"))
      .def_readonly("material", &Ply::material)
      .def_readonly("thickness", &Ply::thickness)
      .def_readonly("angle_deg", &Ply::angle_deg);

  py::class_<Laminate>(m, "Laminate")
      .def(py::init<std::vector<Ply>>(), py::arg("plies"))
      .def_property_readonly("thickness", &Laminate::thickness)
      .def_property_readonly("A", &Laminate::A)
      .def_property_readonly("B", &Laminate::B)
      .def_property_readonly("D", &Laminate::D)
      .def_property_readonly("As", &Laminate::As)
      .def_property_readonly("I0", &Laminate::I0)
      .def_property_readonly("I1", &Laminate::I1)
      .def_property_readonly("I2", &Laminate::I2)
      .def_property_readonly("z", &Laminate::z)
      .def_readonly_static("shear_correction", &Laminate::kShearCorrection);
}
