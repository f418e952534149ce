// Glue for deployfx/multibody's spec structs, the immutable description a Model is compiled from
// (keyword-constructible): a rigid body's inertia, a prescribed hinge angle, a lock, a panel and a
// hinge with the body it carries; and a lock's history, which a run's Data holds.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/multibody/model.hpp"

namespace py = pybind11;
using namespace deployfx::multibody;
using deployfx::joint::HingeLockSpec;
using deployfx::joint::LockHistory;

void define_specs(py::module_& m) {
  py::class_<deployfx::body::RigidInertia>(m, "RigidInertia",
                                           "A rigid body in a frame F: mass (kg), centre of mass (m, F) and inertia "
                                           "about it (kg m^2, F axes).")
      .def(py::init([](double mass, const Eigen::Vector3d& com, const Eigen::Matrix3d& inertia) {
             return deployfx::body::RigidInertia{mass, com, inertia};
           }),
           py::kw_only(), py::arg("mass") = 0.0, py::arg("com") = Eigen::Vector3d::Zero().eval(),
           py::arg("inertia") = Eigen::Matrix3d::Zero().eval())
      .def_readonly("mass", &deployfx::body::RigidInertia::mass)
      .def_readonly("com", &deployfx::body::RigidInertia::com)
      .def_readonly("inertia", &deployfx::body::RigidInertia::inertia_com);

  py::class_<SpinUpDriver>(m, "SpinUpDriver", "theta(t) of Kane, Ryan & Banerjee (1987): omega_s (rad/s), t_s (s).")
      .def(py::init([](double omega_s, double t_s) { return SpinUpDriver{omega_s, t_s}; }), py::kw_only(),
           py::arg("omega_s"), py::arg("t_s"))
      .def("evaluate",
           [](const SpinUpDriver& d, double t) {
             double th, r, a;
             d.evaluate(t, &th, &r, &a);
             return py::make_tuple(th, r, a);
           },
           py::arg("t"));

  py::class_<HingeLockSpec>(m, "HingeLockSpec")
      .def(py::init([](double theta_lock, double pin_radius, double clearance, const deployfx::contact::ContactLaw& law,
                       double mu, double v_reg) {
             HingeLockSpec l{theta_lock, pin_radius, clearance, law, deployfx::contact::CoulombFriction(mu, v_reg)};
             l.validate();
             return l;
           }),
           py::kw_only(), py::arg("theta_lock"), py::arg("pin_radius"), py::arg("clearance"), py::arg("law"),
           py::arg("mu") = 0.0, py::arg("v_reg") = 1e-4)
      .def_readonly("theta_lock", &HingeLockSpec::theta_lock)
      .def_readonly("pin_radius", &HingeLockSpec::pin_radius)
      .def_readonly("clearance", &HingeLockSpec::clearance);

  py::class_<LockHistory>(m, "LockHistory", "What a lock remembers between steps (joint/hinge_lock.hpp).")
      .def(py::init<>())
      .def_readwrite("latched", &LockHistory::latched)
      .def_readwrite("stop_contact", &LockHistory::stop_contact)
      .def_readwrite("latch_contact", &LockHistory::latch_contact)
      .def_readwrite("stop_inside", &LockHistory::stop_inside)
      .def_readwrite("latch_inside", &LockHistory::latch_inside)
      .def_readwrite("stop_v0", &LockHistory::stop_v0)
      .def_readwrite("latch_v0", &LockHistory::latch_v0);

  py::class_<AppendageSpec>(m, "PanelSpec", "A panel in its body frame: a ShellModel (nodes in C, m), its clamped dofs, "
                                            "fidelity, Rayleigh damping alpha_M (1/s), beta_K (s), and for the reduced "
                                            "fidelities modes, derivative_modes and derivative_partners (-1: automatic).")
      .def(py::init([](const deployfx::fem::ShellModel& shell, std::vector<int> fixed_dofs, const std::string& fidelity,
                       double alpha_M, double beta_K, int modes, int derivative_modes, int derivative_partners) {
             return AppendageSpec{std::make_shared<const deployfx::fem::ShellModel>(shell), std::move(fixed_dofs),
                                  deployfx::body::fidelity_from_name(fidelity, "panel.fidelity"), alpha_M, beta_K, modes,
                                  derivative_modes, derivative_partners};
           }),
           py::kw_only(), py::arg("shell"), py::arg("fixed_dofs"), py::arg("fidelity"), py::arg("alpha_M") = 0.0,
           py::arg("beta_K") = 0.0, py::arg("modes") = 10, py::arg("derivative_modes") = -1,
           py::arg("derivative_partners") = -1);

  py::class_<HingeSpec>(m, "HingeSpec",
                        "Hinge k and the body it carries: parent (-1 the base, else an earlier hinge's index), a point "
                        "of the axis (m) and the unit axis in the parent's frame, R_PC0 (the body frame's axes at "
                        "theta = 0), spring tau0 - k_theta theta (N m, N m/rad), damper c_theta (N m s/rad), a "
                        "prescribed angle (driver), a lock, the body's rigid parts and a panel.")
      .def(py::init([](int parent, const Eigen::Vector3d& point, const Eigen::Vector3d& axis, const Eigen::Matrix3d& R_PC0,
                       double tau0, double k_theta, double c_theta, std::optional<SpinUpDriver> driver,
                       std::optional<deployfx::joint::LockSpec> lock, const deployfx::body::RigidInertia& body,
                       std::optional<AppendageSpec> panel) {
             HingeSpec h;
             h.parent = parent;
             h.point = point;
             h.axis = axis;
             h.R_PC0 = R_PC0;
             h.tau0 = tau0;
             h.k_theta = k_theta;
             h.c_theta = c_theta;
             h.driver = driver;
             h.lock = lock;
             h.body = body;
             h.panel = std::move(panel);
             return h;
           }),
           py::kw_only(), py::arg("parent") = -1, py::arg("point") = Eigen::Vector3d::Zero().eval(),
           py::arg("axis") = Eigen::Vector3d::UnitY().eval(), py::arg("R_PC0") = Eigen::Matrix3d::Identity().eval(),
           py::arg("tau0") = 0.0, py::arg("k_theta") = 0.0, py::arg("c_theta") = 0.0, py::arg("driver") = py::none(),
           py::arg("lock") = py::none(), py::arg("body") = deployfx::body::RigidInertia{},
           py::arg("panel") = py::none());
}
