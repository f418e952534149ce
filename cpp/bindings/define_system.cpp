#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"
#include "deployfx/integrate/trajectory.hpp"
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/system/hinged_system.hpp"
#include "run_loop.hpp"
#include "trajectory_dict.hpp"

namespace py = pybind11;
using namespace deployfx::system;
using deployfx::integrate::AlphaParameters;
using deployfx::joint::HingeLockSpec;

namespace {

// The system's methods index q, v and a directly: check sizes here so a wrong call raises.
void check_sizes(const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                 const Eigen::VectorXd* a = nullptr) {
  if (q.size() != s.num_positions() || v.size() != s.num_velocities() ||
      (a && a->size() != s.num_velocities()))
    throw std::invalid_argument("q, v, a must have sizes " + std::to_string(s.num_positions()) + ", " +
                                std::to_string(s.num_velocities()) + ", " +
                                std::to_string(s.num_velocities()));
}

}  // namespace

void define_system(py::module_& m) {
  py::class_<HingeLockSpec>(m, "HingeLockSpec")
      .def(py::init([](double theta_lock, double pin_radius, double clearance,
                       const deployfx::contact::ContactLaw& law, double mu, double v_reg) {
             HingeLockSpec l{theta_lock, pin_radius, clearance, law, deployfx::contact::CoulombFriction(mu, v_reg)};
             l.validate();
             return l;
           }),
           py::arg("theta_lock"), py::arg("pin_radius"), py::arg("clearance"), py::arg("law"),
           py::arg("mu"), py::arg("v_reg"))
      .def_readonly("theta_lock", &HingeLockSpec::theta_lock)
      .def_readonly("pin_radius", &HingeLockSpec::pin_radius)
      .def_readonly("clearance", &HingeLockSpec::clearance);

  py::class_<HingedSystem>(m, "HingedSystem",
                           "The compiled one-hinge system (base, hinge, appendage, lock): q = a free "
                           "base's position (m) and unit quaternion (w, x, y, z), the hinge angle (rad), "
                           "the elastic dofs (m, rad) or modal coordinates.")
      .def(py::init([](bool base_free, double base_mass, const Eigen::Matrix3d& base_inertia,
                       const Eigen::Vector3d& hinge_point, const Eigen::Vector3d& hinge_axis,
                       const Eigen::Matrix3d& R_BE0, double tau0, double k_theta, double c_theta,
                       std::optional<std::pair<double, double>> spin_up,
                       const deployfx::fem::ShellModel& model, std::vector<int> fixed_dofs,
                       const std::string& fidelity, const Eigen::Vector3d& base_com,
                       double fitting_mass, const Eigen::Vector3d& fitting_com,
                       const Eigen::Matrix3d& fitting_inertia,
                       std::optional<deployfx::joint::HingeLockSpec> lock, double alpha_M, double beta_K,
                       int modes, int derivative_modes) {
             BaseSpec b{base_free, {base_mass, base_com, base_inertia}};
             HingeSpec h;
             h.fitting = {fitting_mass, fitting_com, fitting_inertia};
             h.lock = lock;
             h.point_B = hinge_point;
             h.axis_B = hinge_axis;
             h.R_BE0 = R_BE0;
             h.tau0 = tau0;
             h.k_theta = k_theta;
             h.c_theta = c_theta;
             if (spin_up) h.driven = true, h.driver = {spin_up->first, spin_up->second};
             AppendageSpec a{std::make_shared<const deployfx::fem::ShellModel>(model),
                             std::move(fixed_dofs), deployfx::body::fidelity_from_name(fidelity), alpha_M, beta_K, modes,
                             derivative_modes};
             return std::make_unique<HingedSystem>(b, h, a);
           }),
           py::arg("base_free"), py::arg("base_mass"), py::arg("base_inertia"),
           py::arg("hinge_point"), py::arg("hinge_axis"), py::arg("R_BE0"), py::arg("tau0"),
           py::arg("k_theta"), py::arg("c_theta"), py::arg("spin_up"), py::arg("model"),
           py::arg("fixed_dofs"), py::arg("fidelity"), py::arg("base_com") = Eigen::Vector3d::Zero(),
           py::arg("fitting_mass") = 0.0, py::arg("fitting_com") = Eigen::Vector3d::Zero(),
           py::arg("fitting_inertia") = Eigen::Matrix3d::Zero().eval(), py::arg("lock") = py::none(),
           py::arg("alpha_M") = 0.0, py::arg("beta_K") = 0.0, py::arg("modes") = 10,
           py::arg("derivative_modes") = -1)
      .def_property_readonly("num_positions", &HingedSystem::num_positions)
      .def_property_readonly("num_velocities", &HingedSystem::num_velocities)
      .def_property_readonly("num_elastic", &HingedSystem::num_elastic)
      .def_property_readonly(
          "basis",
          [](const HingedSystem& s) -> const Eigen::MatrixXd& { return s.basis().Phi; },
          py::return_value_policy::reference_internal,
          "Reduced models: mesh dofs = basis @ eta (read-only view); empty for a full model.")
      .def_property_readonly(
          "basis_info",
          [](const HingedSystem& s) {
            py::dict d;
            d["modes"] = s.basis().modes;
            d["static_corrections"] = s.basis().static_corrections;
            d["modal_derivatives"] = s.basis().modal_derivatives;
            d["size"] = static_cast<int>(s.basis().Phi.cols());
            d["omega2"] = s.basis().omega2;
            return d;
          },
          "Reduced models: the vectors proposed of each kind, the basis size and its Ritz values "
          "((rad/s)^2).")
      .def("initial_positions", &HingedSystem::initial_positions)
      .def("retract",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& dq) {
             check_sizes(s, q, dq);
             return s.retract(q, dq);
           },
           py::arg("q"), py::arg("dq"))
      .def("outputs",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
             check_sizes(s, q, v);
             const auto o = s.outputs(q, v, t);
             py::dict d;
             d["theta"] = o.theta;
             d["linear_momentum"] = o.P_W;
             d["angular_momentum"] = o.H_W;
             d["kinetic_energy"] = o.kinetic;
             d["potential_energy"] = o.potential;
             return d;
           },
           py::arg("q"), py::arg("v"), py::arg("t"))
      .def("residual",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
              const Eigen::VectorXd& a, double t) {
             check_sizes(s, q, v, &a);
             return s.residual(q, v, a, t);
           },
           py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"))
      .def("iteration_matrix",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
              const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q) {
             check_sizes(s, q, v, &a);
             return s.iteration_matrix(q, v, a, t, c_a, c_v, c_q).dense();
           },
           py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::arg("c_a"), py::arg("c_v"),
           py::arg("c_q"))
      .def("gaps",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
             check_sizes(s, q, v);
             return s.gaps(q, v, t);
           },
           py::arg("q"), py::arg("v"), py::arg("t"),
           "The lock's event functions (stop, latch) at (q, v) under the lock's history of the last "
           "run: positive while each wall's mode holds (m for a gap, N for a force; the latch's is "
           "inf until latched); empty without a lock.")
      .def_property_readonly("num_conserved", &HingedSystem::num_conserved)
      .def("momentum",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
             check_sizes(s, q, v);
             return s.momentum(q, v);
           },
           py::arg("q"), py::arg("v"))
      .def("momentum_jacobian",
           [](const HingedSystem& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v,
              double c_q) {
             check_sizes(s, q, v);
             return s.momentum_jacobian(q, v, c_v, c_q);
           },
           py::arg("q"), py::arg("v"), py::arg("c_v"), py::arg("c_q"));

  m.def("simulate_hinged",
        [](const HingedSystem& sys, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
           double t_end, double dt, const AlphaParameters& p, bool reuse_jacobian, double tolerance,
           const py::object& progress) {
          check_sizes(sys, q0, v0);
          std::vector<HingedSystem::Outputs> out;
          long factorizations = 0;
          const RunOptions opt{t_end, dt, p, reuse_jacobian, tolerance};
          const auto tr = run_released(
              sys, q0, v0, opt, progress,
              [&](const deployfx::integrate::AlphaState& s) { out.push_back(sys.outputs(s.q, s.v, s.t)); },
              &factorizations);
          const Eigen::Index n = static_cast<Eigen::Index>(out.size());
          Eigen::MatrixXd P(n, 3), H(n, 3), Hb(n, 3), Pb(n, 3), scalars(n, 7);
          for (Eigen::Index k = 0; k < n; ++k) {
            const auto& o = out[k];
            P.row(k) = o.P_W.transpose();
            H.row(k) = o.H_W.transpose();
            Hb.row(k) = o.H_base_W.transpose();
            Pb.row(k) = o.P_base_W.transpose();
            scalars.row(k) << o.theta, o.theta_rate, o.spring_torque, o.kinetic, o.potential,
                o.lock_force, o.lock_torque;
          }
          py::dict d = trajectory_dict(tr);
          d["factorizations"] = factorizations;
          d["linear_momentum"] = P;
          d["angular_momentum"] = H;
          d["base_angular_momentum"] = Hb;
          d["base_linear_momentum"] = Pb;
          const char* names[] = {"theta", "theta_rate", "spring_torque", "kinetic_energy",
                                 "potential_energy", "lock_force", "lock_torque"};
          for (int c = 0; c < 7; ++c) d[names[c]] = Eigen::VectorXd(scalars.col(c));
          return d;
        },
        py::arg("system"), py::arg("q0"), py::arg("v0"), py::arg("t_end"), py::arg("dt"), py::arg("scheme"),
        py::arg("reuse_jacobian") = true, py::arg("tolerance") = 0.0, py::arg("progress") = py::none());
}
