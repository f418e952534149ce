#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "deployfx/body/floating_frame_inertia.hpp"

namespace py = pybind11;
using deployfx::body::FloatingFrameInertia;

void define_body(py::module_& m) {
  py::class_<FloatingFrameInertia::InertialForces>(m, "InertialForces")
      .def_readonly("F", &FloatingFrameInertia::InertialForces::F)
      .def_readonly("M", &FloatingFrameInertia::InertialForces::M)
      .def_readonly("Q", &FloatingFrameInertia::InertialForces::Q);

  py::class_<FloatingFrameInertia>(m, "FloatingFrameInertia",
                                   "Inertia shape integrals of a mesh in its floating frame (You et al. 2016, "
                                   "Eq. 9 and 28; SI units) and the inertial forces they give.")
      .def(py::init<const deployfx::fem::ShellModel&>(), py::arg("model"))
      .def_property_readonly("mass", &FloatingFrameInertia::mass)
      .def_property_readonly("S0", &FloatingFrameInertia::S0)
      .def_property_readonly("E0", &FloatingFrameInertia::E0)
      .def_property_readonly("J0", &FloatingFrameInertia::J0)
      .def_property_readonly("S1", &FloatingFrameInertia::S1)
      .def_property_readonly("C", &FloatingFrameInertia::C)
      .def_property_readonly("M", &FloatingFrameInertia::M)
      .def("Mij", &FloatingFrameInertia::Mij, py::arg("i"), py::arg("j"))
      .def("products",
           [](const FloatingFrameInertia& f, const Eigen::VectorXd& z) {
             const FloatingFrameInertia::Products P = f.products(z);
             std::vector<Eigen::VectorXd> out;
             for (int k = 0; k < 9; ++k) out.push_back(P[k]);
             return out;
           },
           py::arg("z"),
           "The nine M_ij z, index 3 i + j, that the d-dependent integrals are built from.")
      .def("products_pair",
           [](const FloatingFrameInertia& f, const Eigen::VectorXd& z1, const Eigen::VectorXd& z2) {
             FloatingFrameInertia::Products P1, P2;
             f.products(z1, z2, nullptr, P1, P2);  // one pass for both (a residual's d and dd')
             std::vector<Eigen::VectorXd> out1, out2;
             for (int k = 0; k < 9; ++k) out1.push_back(P1[k]), out2.push_back(P2[k]);
             return py::make_tuple(out1, out2);
           },
           py::arg("z1"), py::arg("z2"), "products(z1) and products(z2), formed in one pass.")
      .def("first_moment", &FloatingFrameInertia::first_moment, py::arg("d"))
      .def("inertia_tensor", [](const FloatingFrameInertia& f, const Eigen::VectorXd& d) { return f.inertia_tensor(d); },
           py::arg("d"))
      .def("rotation_coupling",
           [](const FloatingFrameInertia& f, const Eigen::VectorXd& d) { return f.rotation_coupling(d); }, py::arg("d"))
      .def("kinetic_energy",
           [](const FloatingFrameInertia& f, const Eigen::Vector3d& V, const Eigen::Vector3d& w, const Eigen::VectorXd& d,
              const Eigen::VectorXd& dd) { return f.kinetic_energy(V, w, d, dd); },
           py::arg("V"), py::arg("w"), py::arg("d"), py::arg("dd"))
      .def("inertia_tensor_rate",
           [](const FloatingFrameInertia& f, const Eigen::VectorXd& d, const Eigen::VectorXd& dd) {
             return f.inertia_tensor_rate(d, dd);
           },
           py::arg("d"), py::arg("dd"))
      .def("centrifugal_load", &FloatingFrameInertia::centrifugal_load, py::arg("w"))
      .def("centrifugal_stiffness", &FloatingFrameInertia::centrifugal_stiffness, py::arg("w"))
      .def("gyroscopic", &FloatingFrameInertia::gyroscopic, py::arg("w"))
      .def("inertial_forces",
           [](const FloatingFrameInertia& f, const Eigen::Vector3d& a, const Eigen::Vector3d& al, const Eigen::Vector3d& w,
              const Eigen::VectorXd& d, const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd, double damping) {
             return f.inertial_forces(a, al, w, d, dd, ddd, nullptr, damping);
           },
           py::arg("a"), py::arg("al"), py::arg("w"), py::arg("d"), py::arg("dd"), py::arg("ddd"),
           py::arg("damping") = 0.0)
      .def("inertial_force_rows",
           [](const FloatingFrameInertia& f, const std::vector<int>& dofs, const Eigen::Vector3d& a,
              const Eigen::Vector3d& al, const Eigen::Vector3d& w, const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
              const Eigen::VectorXd& ddd, double damping) {
             return f.inertial_force_rows(f.select_rows(dofs), a, al, w, d, dd, ddd, damping);
           },
           py::arg("dofs"), py::arg("a"), py::arg("al"), py::arg("w"), py::arg("d"), py::arg("dd"), py::arg("ddd"),
           py::arg("damping") = 0.0,
           "Q's entries at `dofs` alone, as inertial_forces forms them (the membrane sweeps' rows: by the "
           "node graph for in-plane dofs of a mesh in the x-y plane, else by restricted sparse rows).");
}
