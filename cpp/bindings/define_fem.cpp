#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/fem/modal.hpp"
#include "deployfx/fem/modal_internal_force.hpp"
#include "deployfx/fem/plate.hpp"
#include "deployfx/fem/shell_model.hpp"

namespace py = pybind11;
using namespace deployfx::fem;
using deployfx::material::Laminate;

namespace {
// A modal force with the memo one run would keep (ModalInternalForce::Memo).
struct ModalForce {
  ModalInternalForce force;
  ModalInternalForce::Memo memo;
};
}  // namespace

void define_fem(py::module_& m) {
  py::class_<ModalResult>(m, "ModalResult")
      .def_readonly("eigenvalues", &ModalResult::eigenvalues)
      .def_readonly("modes", &ModalResult::modes);

  py::class_<ShellModel>(m, "ShellModel")
      .def(py::init<NodeMatrix, QuadMatrix, const Laminate&, const Eigen::Vector3d&>(),
           py::arg("nodes"), py::arg("quads"), py::arg("laminate"), py::arg("ref_axis"))
      .def_property_readonly("num_nodes", &ShellModel::num_nodes)
      .def_property_readonly("num_dofs", &ShellModel::num_dofs)
      .def_property_readonly("nodes", &ShellModel::nodes)
      .def_property_readonly("quads", &ShellModel::quads)
      .def("stiffness", &ShellModel::stiffness)
      .def("mass", &ShellModel::mass)
      .def("total_mass", &ShellModel::total_mass)
      .def("pressure_load", &ShellModel::pressure_load, py::arg("pressure"))
      .def("geometric_stiffness", &ShellModel::geometric_stiffness, py::arg("N"))
      .def("geometric_stiffness_from", &ShellModel::geometric_stiffness_from, py::arg("u"))
      .def("strain_energy", &ShellModel::strain_energy, py::arg("u"))
      .def("modes",
           [](const ShellModel& s, int n, const std::vector<int>& fixed) {
             return constrained_modes(s.stiffness(), s.mass(), n, fixed);
           },
           py::arg("n"), py::arg("fixed"), py::call_guard<py::gil_scoped_release>())
      .def("static_solve",
           [](const ShellModel& s, const Eigen::VectorXd& f, const std::vector<int>& fixed) {
             return static_solve(s.stiffness(), f, fixed);
           },
           py::arg("f"), py::arg("fixed"), py::call_guard<py::gil_scoped_release>())
      .def("internal_force", [](const ShellModel& s, const Eigen::VectorXd& u) {
        Eigen::VectorXd f;
        SparseMatrix K;
        {
          py::gil_scoped_release release;
          s.internal_force(u, &f, &K);
        }
        return py::make_tuple(f, K);
      }, py::arg("u"))
      .def_property_readonly("batched_force", &ShellModel::batched_force)
      .def("tangent",
           [](const ShellModel& s, const Eigen::VectorXd& u) {
             SparseMatrix K;
             s.internal_force(u, nullptr, &K);
             return K;
           },
           py::arg("u"), py::call_guard<py::gil_scoped_release>(),
           "The tangent alone (the engine's Newton matrix's; on a mesh in world axes four elements at a "
           "time, fem/shell_batch.hpp).")
      .def("force",
           [](const ShellModel& s, const Eigen::VectorXd& u, bool in_plane_rows) {
             Eigen::VectorXd f;
             if (in_plane_rows) s.in_plane_force(u, &f);
             else s.internal_force(u, &f, nullptr);
             return f;
           },
           py::arg("u"), py::arg("in_plane_rows") = false, py::call_guard<py::gil_scoped_release>(),
           "The internal force alone (the engine's residual's; on a mesh in world axes four elements at a "
           "time, fem/shell_batch.hpp), or with in_plane_rows its in-plane rows (u, v, theta_z).")
      .def("energy",
           [](const ShellModel& s, const Eigen::VectorXd& u) {
             double U = 0;
             s.internal_force(u, nullptr, nullptr, &U);
             return U;
           },
           py::arg("u"), py::call_guard<py::gil_scoped_release>(),
           "The strain energy alone (J) from the force's strains, as the engine reports it (on a mesh in "
           "world axes four elements at a time, fem/shell_batch.hpp).");

  py::class_<ModalForce>(m, "ModalInternalForce",
                         "The shell model's internal force in a Ritz basis d = Phi eta, as an exact polynomial, "
                         "with the memo of its last evaluation that one run keeps.")
      .def(py::init([](const ShellModel& model, const Eigen::MatrixXd& Phi, bool green_strain) {
             py::gil_scoped_release release;
             return std::unique_ptr<ModalForce>(new ModalForce{ModalInternalForce(model, Phi, green_strain), {}});
           }),
           py::arg("model"), py::arg("basis"), py::arg("green_strain"))
      .def_property_readonly("linear_stiffness", [](const ModalForce& f) { return f.force.linear_stiffness(); })
      .def_property_readonly("quartic_blocks", [](const ModalForce& f) { return f.force.quartic_blocks(); },
                             "The sizes of the quartic coefficients' diagonal blocks: one block, or two when "
                             "every basis vector is exactly bending or exactly in-plane (fem/parity.hpp).")
      .def("internal_force",
           [](ModalForce& f, const Eigen::VectorXd& eta) {
             Eigen::VectorXd out;
             Eigen::MatrixXd T;
             f.force.evaluate(eta, &out, &T, &f.memo);
             return py::make_tuple(out, T);
           },
           py::arg("eta"))
      .def("strain_energy", [](const ModalForce& f, const Eigen::VectorXd& eta) { return f.force.strain_energy(eta, &f.memo); },
           py::arg("eta"));

  py::class_<RectangularPlate>(m, "RectangularPlate")
      .def(py::init<double, double, const Laminate&, int, int>(), py::arg("length"),
           py::arg("width"), py::arg("laminate"), py::arg("nx"), py::arg("ny"))
      .def_property_readonly("model", &RectangularPlate::model, py::return_value_policy::reference_internal)
      .def("fixed_dofs", &RectangularPlate::fixed_dofs, py::arg("boundary"))
      .def("static_deflection", &RectangularPlate::static_deflection, py::arg("pressure"),
           py::arg("boundary"), py::call_guard<py::gil_scoped_release>())
      .def("modes", &RectangularPlate::modes, py::arg("n"), py::arg("boundary"),
           py::call_guard<py::gil_scoped_release>());
}
