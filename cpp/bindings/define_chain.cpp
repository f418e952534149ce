// Glue for system::HingeChain (a base and a serial chain of rigid or flexible bodies on spring hinges).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/system/hinge_chain.hpp"
#include "run_loop.hpp"
#include "trajectory_dict.hpp"

namespace py = pybind11;
using deployfx::system::BaseSpec;
using deployfx::system::ChainHingeSpec;
using deployfx::system::HingeChain;

namespace {

void check_hinge_index(const HingeChain& s, int k) {
  if (k < 0 || k >= s.num_hinges())
    throw std::invalid_argument("hinge = " + std::to_string(k) + " is out of range: must be in [0, " +
                                std::to_string(s.num_hinges() - 1) + "]");
}

// The system's methods index q, v and a directly: check sizes here so a wrong call raises.
void check_sizes(const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                 const Eigen::VectorXd* a = nullptr) {
  if (q.size() != s.num_positions() || v.size() != s.num_velocities() || (a && a->size() != s.num_velocities()))
    throw std::invalid_argument("q, v, a must have sizes " + std::to_string(s.num_positions()) + ", " +
                                std::to_string(s.num_velocities()) + ", " + std::to_string(s.num_velocities()) +
                                "; got " + std::to_string(q.size()) + ", " + std::to_string(v.size()) +
                                (a ? ", " + std::to_string(a->size()) : std::string()));
}

// Per-hinge outputs at every recorded instant as (n, N) arrays.
Eigen::MatrixXd stack(const std::vector<HingeChain::Outputs>& out, int hinges,
                      Eigen::VectorXd HingeChain::Outputs::*field) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(out.size()), hinges);
  for (std::size_t k = 0; k < out.size(); ++k) X.row(static_cast<Eigen::Index>(k)) = (out[k].*field).transpose();
  return X;
}

Eigen::MatrixXd stack3(const std::vector<HingeChain::Outputs>& out, Eigen::Vector3d HingeChain::Outputs::*field) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(out.size()), 3);
  for (std::size_t k = 0; k < out.size(); ++k) X.row(static_cast<Eigen::Index>(k)) = (out[k].*field).transpose();
  return X;
}

}  // namespace

void define_chain(py::module_& m) {
  py::class_<ChainHingeSpec>(m, "ChainHingeSpec")
      .def(py::init([](const Eigen::Vector3d& point, const Eigen::Vector3d& axis, const Eigen::Matrix3d& R_PC0,
                       double tau0, double k_theta, double c_theta, double mass, const Eigen::Vector3d& com,
                       const Eigen::Matrix3d& inertia, std::optional<deployfx::joint::HingeLockSpec> lock,
                       std::optional<deployfx::fem::ShellModel> shell, std::vector<int> fixed_dofs,
                       const std::string& fidelity, double alpha_M, double beta_K, int modes,
                       int derivative_modes) {
             ChainHingeSpec h;
             h.point_P = point;
             h.axis_P = axis;
             h.R_PC0 = R_PC0;
             h.tau0 = tau0;
             h.k_theta = k_theta;
             h.c_theta = c_theta;
             h.body = {mass, com, inertia};
             h.lock = lock;
             if (shell)
               h.appendage = deployfx::body::AppendageSpec{
                   std::make_shared<const deployfx::fem::ShellModel>(std::move(*shell)), std::move(fixed_dofs),
                   deployfx::body::fidelity_from_name(fidelity, "appendage.fidelity"), alpha_M, beta_K, modes,
                   derivative_modes};
             return h;
           }),
           py::arg("point"), py::arg("axis"), py::arg("R_PC0"), py::arg("tau0"), py::arg("k_theta"),
           py::arg("c_theta"), py::arg("mass"), py::arg("com"), py::arg("inertia"), py::arg("lock") = py::none(),
           py::arg("shell") = py::none(), py::arg("fixed_dofs") = std::vector<int>(),
           py::arg("fidelity") = "rigid", py::arg("alpha_M") = 0.0, py::arg("beta_K") = 0.0, py::arg("modes") = 10,
           py::arg("derivative_modes") = -1,
           "Hinge k and its child body: point (m) and unit axis in the parent's frame, the child's axes at "
           "theta = 0, spring tau0 - k_theta theta (N m, N m/rad), damper c_theta (N m s/rad), the child "
           "body's rigid mass (kg), centre of mass (m) and inertia about it (kg m^2) in the child frame, a lock; "
           "optionally a panel: its ShellModel (nodes in the child frame, m), clamped dofs, fidelity, Rayleigh "
           "damping alpha_M (1/s) and beta_K (s), and for the reduced fidelities modes and derivative_modes "
           "(-1: automatic).")
      .def_readonly("point", &ChainHingeSpec::point_P)
      .def_readonly("axis", &ChainHingeSpec::axis_P)
      .def_readonly("R_PC0", &ChainHingeSpec::R_PC0);

  py::class_<HingeChain>(m, "HingeChain",
                         "The compiled chain of bodies on spring hinges: q = a free base's position (m) and unit "
                         "quaternion (w, x, y, z), the hinge angles (rad), then each flexible panel's elastic "
                         "coordinates in hinge order.")
      .def(py::init([](bool base_free, double base_mass, const Eigen::Matrix3d& base_inertia,
                       const Eigen::Vector3d& base_com, std::vector<ChainHingeSpec> hinges) {
             BaseSpec b{base_free, {base_mass, base_com, base_inertia}};
             return std::make_unique<HingeChain>(b, std::move(hinges));
           }),
           py::arg("base_free"), py::arg("base_mass"), py::arg("base_inertia"),
           py::arg("base_com") = Eigen::Vector3d::Zero().eval(), py::arg("hinges"))
      .def_property_readonly("num_positions", &HingeChain::num_positions)
      .def_property_readonly("num_velocities", &HingeChain::num_velocities)
      .def_property_readonly("num_hinges", &HingeChain::num_hinges)
      .def_property_readonly("num_conserved", &HingeChain::num_conserved)
      .def(
          "num_elastic",
          [](const HingeChain& s, int k) {
            check_hinge_index(s, k);
            return s.num_elastic(k);
          },
          py::arg("hinge"), "Body k's elastic coordinates (0 for a rigid body).")
      .def(
          "elastic_position",
          [](const HingeChain& s, int k) {
            check_hinge_index(s, k);
            return s.elastic_position(k);
          },
          py::arg("hinge"), "Where body k's elastic coordinates start in q (-1 for a rigid body).")
      .def(
          "displacement_map",
          [](const HingeChain& s, int k) {
            check_hinge_index(s, k);
            const auto* f = s.flexible_body(k);
            if (!f) return Eigen::MatrixXd(0, 0);
            std::vector<int> all(f->spec().model->num_dofs());
            for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
            return f->mesh_rows(all);
          },
          py::arg("hinge"),
          "Body k's mesh displacements per elastic coordinate, (6 nodes x num_elastic(k)): the Ritz basis of a "
          "reduced panel, a selection of the free dofs for a full one; empty for a rigid body.")
      .def(
          "basis_info",
          [](const HingeChain& s, int k) -> py::object {
            check_hinge_index(s, k);
            const auto* f = s.flexible_body(k);
            if (!f || !f->reduced()) return py::none();
            py::dict d;
            d["modes"] = f->basis().modes;
            d["static_corrections"] = f->basis().static_corrections;
            d["modal_derivatives"] = f->basis().modal_derivatives;
            d["size"] = static_cast<int>(f->basis().Phi.cols());
            d["omega2"] = f->basis().omega2;
            return std::move(d);
          },
          py::arg("hinge"), "A reduced panel's basis: the vectors proposed of each kind, its size and Ritz values "
          "((rad/s)^2); None otherwise.")
      .def(
          "attachment_node",
          [](const HingeChain& s, int k) {
            check_hinge_index(s, k);
            const auto* a = s.attachment(k);
            return a ? a->node : -1;
          },
          py::arg("hinge"), "The node of hinge k's flexible parent the hinge is attached to (-1: a rigid parent).")
      .def("initial_positions", &HingeChain::initial_positions)
      .def("retract",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& dq) {
             check_sizes(s, q, dq);
             return s.retract(q, dq);
           },
           py::arg("q"), py::arg("dq"))
      .def("residual",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
              double t) {
             check_sizes(s, q, v, &a);
             return s.residual(q, v, a, t);
           },
           py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"))
      .def("iteration_matrix",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
              double t, double c_a, double c_v, double c_q) {
             check_sizes(s, q, v, &a);
             return s.iteration_matrix(q, v, a, t, c_a, c_v, c_q).dense();
           },
           py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::arg("c_a"), py::arg("c_v"), py::arg("c_q"))
      .def("mass_matrix",
           [](const HingeChain& s, const Eigen::VectorXd& q) {
             check_sizes(s, q, Eigen::VectorXd::Zero(s.num_velocities()));
             return s.mass_matrix(q);
           },
           py::arg("q"))
      .def("momentum",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
             check_sizes(s, q, v);
             return s.momentum(q, v);
           },
           py::arg("q"), py::arg("v"))
      .def("momentum_jacobian",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v, double c_q) {
             check_sizes(s, q, v);
             return s.momentum_jacobian(q, v, c_v, c_q);
           },
           py::arg("q"), py::arg("v"), py::arg("c_v"), py::arg("c_q"))
      .def("frames",
           [](const HingeChain& s, const Eigen::VectorXd& q) {
             check_sizes(s, q, Eigen::VectorXd::Zero(s.num_velocities()));
             return s.frames(q);
           },
           py::arg("q"), "(R_WC (3 x 3N, side by side), origins (3 x N), m) of the bodies' frames.")
      .def("outputs",
           [](const HingeChain& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
             check_sizes(s, q, v);
             const auto o = s.outputs(q, v, t);
             py::dict d;
             d["theta"] = o.theta;
             d["theta_rate"] = o.theta_rate;
             d["spring_torque"] = o.spring_torque;
             d["lock_force"] = o.lock_force;
             d["lock_torque"] = o.lock_torque;
             d["latched"] = o.latched;
             d["strain_energy"] = o.strain_energy;
             d["linear_momentum"] = o.P_W;
             d["angular_momentum"] = o.H_W;
             d["base_linear_momentum"] = o.P_base_W;
             d["base_angular_momentum"] = o.H_base_W;
             d["kinetic_energy"] = o.kinetic;
             d["potential_energy"] = o.potential;
             return d;
           },
           py::arg("q"), py::arg("v"), py::arg("t"));

  m.def("simulate_chain",
        [](const HingeChain& sys, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, double t_end, double dt,
           const deployfx::integrate::AlphaParameters& scheme, bool reuse_jacobian, double tolerance,
           const py::object& progress) {
          check_sizes(sys, q0, v0);
          std::vector<HingeChain::Outputs> out;
          long factorizations = 0;
          const auto tr = run_released(
              sys, q0, v0, RunOptions{t_end, dt, scheme, reuse_jacobian, tolerance}, progress,
              [&](const deployfx::integrate::AlphaState& s) { out.push_back(sys.outputs(s.q, s.v, s.t)); },
              &factorizations);
          using O = HingeChain::Outputs;
          const int N = sys.num_hinges();
          py::dict d = trajectory_dict(tr);
          d["factorizations"] = factorizations;
          d["theta"] = stack(out, N, &O::theta);
          d["theta_rate"] = stack(out, N, &O::theta_rate);
          d["spring_torque"] = stack(out, N, &O::spring_torque);
          d["lock_force"] = stack(out, N, &O::lock_force);
          d["lock_torque"] = stack(out, N, &O::lock_torque);
          d["latched"] = stack(out, N, &O::latched);
          d["strain_energy"] = stack(out, N, &O::strain_energy);
          d["linear_momentum"] = stack3(out, &O::P_W);
          d["angular_momentum"] = stack3(out, &O::H_W);
          d["base_linear_momentum"] = stack3(out, &O::P_base_W);
          d["base_angular_momentum"] = stack3(out, &O::H_base_W);
          Eigen::VectorXd T(static_cast<Eigen::Index>(out.size())), V(T.size());
          for (Eigen::Index k = 0; k < T.size(); ++k) T(k) = out[k].kinetic, V(k) = out[k].potential;
          d["kinetic_energy"] = T;
          d["potential_energy"] = V;
          return d;
        },
        py::arg("system"), py::arg("q0"), py::arg("v0"), py::arg("t_end"), py::arg("dt"), py::arg("scheme"),
        py::arg("reuse_jacobian") = true, py::arg("tolerance") = 0.0, py::arg("progress") = py::none(),
        "Runs the chain from (q0, v0) to t_end (s), output every dt (s), with the GIL released (Ctrl-C and "
        "progress(t, t_end) every 0.2 s). Returns the trajectory dict (t, q, v, ...) with per-hinge series "
        "as (n, N) arrays (theta rad, theta_rate rad/s, spring_torque N m, lock_force N, lock_torque N m, "
        "latched 0/1, strain_energy J), momenta (n, 3) in W (N s, N m s about W's origin), energies (n,) J.");
}
