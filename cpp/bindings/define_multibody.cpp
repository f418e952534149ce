// Glue for deployfx/multibody: the compiled Model, a run's Data, the engine's stages for tests and
// tools, and simulate (run_loop.hpp); the spec structs it is compiled from are define_specs.cpp's.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/multibody/events.hpp"
#include "deployfx/multibody/model.hpp"
#include "deployfx/multibody/momentum.hpp"
#include "deployfx/multibody/newton_matrix.hpp"
#include "deployfx/multibody/outputs.hpp"
#include "deployfx/multibody/residual.hpp"
#include "deployfx/multibody/tree_system.hpp"
#include "run_loop.hpp"

namespace py = pybind11;
using namespace deployfx::multibody;
using deployfx::joint::LockHistory;

namespace {

using ModelPtr = std::shared_ptr<Model>;  // used as const: the model is immutable

// A run's Data together with the model it was made for (a Data is meaningless without it).
struct PyData {
  ModelPtr model;
  Data data;
  explicit PyData(ModelPtr m) : model(std::move(m)), data(*model) {}
};

// The Data to evaluate with: the caller's (checked against the model), or a fresh one.
struct DataArg {
  std::optional<Data> own;
  Data* data;
  DataArg(const Model& m, PyData* given) {
    if (given) {
      if (given->model.get() != &m) throw std::invalid_argument("data was made for another model: use model.make_data()");
      data = &given->data;
    } else {
      own.emplace(m);
      data = &*own;
    }
  }
};

void check_hinge(const Model& m, int k) {
  if (k < 0 || k >= m.num_hinges())
    throw std::invalid_argument("hinge = " + std::to_string(k) + " is out of range: must be in [0, " +
                                std::to_string(m.num_hinges() - 1) + "]");
}

// Hinge k's deforming panel, for q_el with `count` elastic coordinates (`got` names q_el's shape).
const deployfx::body::FlexibleBody& elastic_panel(const Model& m, int k, Eigen::Index count, const std::string& got) {
  check_hinge(m, k);
  const auto& panel = m.body(k).panel;
  if (!panel) throw std::invalid_argument("hinge = " + std::to_string(k) + " carries no deforming panel");
  const int n = m.body(k).n_el;
  if (count != n)
    throw std::invalid_argument("q_el must hold hinge " + std::to_string(k) + "'s " + std::to_string(n) +
                                " elastic coordinates, got " + got);
  return *panel;
}

py::dict outputs_dict(const Outputs& o) {
  py::dict d;
  d["theta"] = o.theta;
  d["theta_rate"] = o.rate;
  d["spring_torque"] = o.spring_torque;
  d["lock_force"] = o.lock_force;
  d["lock_torque"] = o.lock_torque;
  d["latched"] = o.latched;
  d["strain_energy"] = o.strain_energy;
  d["hinge_force"] = Eigen::MatrixXd(o.hinge_force.transpose());
  d["hinge_moment"] = Eigen::MatrixXd(o.hinge_moment.transpose());
  d["linear_momentum"] = o.P_W;
  d["angular_momentum"] = o.H_W;
  d["base_linear_momentum"] = o.P_base_W;
  d["base_angular_momentum"] = o.H_base_W;
  d["kinetic_energy"] = o.kinetic;
  d["potential_energy"] = o.potential;
  return d;
}

}  // namespace

void define_multibody(py::module_& m) {
  py::class_<Model, ModelPtr>(m, "Model",
                              "The compiled scene (immutable, shared by runs): q = a free base's position (m) and unit "
                              "quaternion (w, x, y, z), the undriven hinges' angles (rad), then each panel's elastic "
                              "coordinates in hinge order.")
      .def(py::init([](bool base_free, const deployfx::body::RigidInertia& base, std::vector<HingeSpec> hinges) {
             TreeSpec spec{BaseSpec{base_free, base}, std::move(hinges)};
             py::gil_scoped_release release;  // compiling panels (bases, modal coefficients) can take a while
             return std::make_shared<Model>(std::move(spec));
           }),
           py::kw_only(), py::arg("base_free"), py::arg("base"), py::arg("hinges"))
      .def_property_readonly("num_positions", &Model::num_positions)
      .def_property_readonly("num_velocities", &Model::num_velocities)
      .def_property_readonly("num_hinges", &Model::num_hinges)
      .def_property_readonly("num_conserved", &Model::num_conserved)
      .def_property_readonly("border", &Model::border, "Base and hinge coordinates (the Newton matrix's border).")
      .def_property_readonly("base_free", &Model::base_free)
      .def(
          "layout",
          [](const Model& s, int k) {
            check_hinge(s, k);
            const Body& b = s.body(k);
            py::dict d;
            d["parent"] = b.parent;
            d["iq_theta"] = b.iq_theta;
            d["iv_theta"] = b.iv_theta;
            d["num_elastic"] = b.n_el;
            d["iq_elastic"] = b.iq_el;
            d["iv_elastic"] = b.iv_el;
            d["attachment_node"] = b.attachment ? b.attachment->node : -1;
            return d;
          },
          py::arg("hinge"),
          "Hinge k's coordinates: its parent, where its angle sits in q and v (-1: driven), its panel's elastic "
          "coordinates (count, first index in q and v), and the parent panel's node it rides on (-1: none).")
      .def(
          "displacement_map",
          [](const Model& s, int k) {
            check_hinge(s, k);
            const auto& panel = s.body(k).panel;
            if (!panel) return Eigen::MatrixXd(0, 0);
            std::vector<int> all(static_cast<std::size_t>(panel->spec().model->num_dofs()));
            for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
            return panel->mesh_rows(all);
          },
          py::arg("hinge"),
          "Hinge k's panel: mesh displacements per panel coordinate (panel_coordinates), (6 nodes x count): the Ritz "
          "basis of a reduced panel, a selection of the free dofs for a full one; empty without a deforming panel.")
      .def(
          "panel_coordinates",
          [](const Model& s, int k, const Eigen::MatrixXd& Q) {
            const auto& panel =
                elastic_panel(s, k, Q.cols(), std::to_string(Q.rows()) + " x " + std::to_string(Q.cols()));
            Eigen::MatrixXd out(Q.rows(), panel.num_coordinates());
            for (Eigen::Index i = 0; i < Q.rows(); ++i) out.row(i) = panel.coordinates(Q.row(i).transpose()).transpose();
            return out;
          },
          py::arg("hinge"), py::arg("q_el"),
          "Hinge k's panel coordinates (the columns of displacement_map) at each row of its elastic coordinates "
          "q_el (n x num_elastic): eta = g(q) for 'reduced-manifold' (the in-plane Ritz coordinates slaved to the "
          "bending ones), q_el itself otherwise.")
      .def(
          "panel_tangent",
          [](const Model& s, int k, const Eigen::VectorXd& q) {
            return elastic_panel(s, k, q.size(), std::to_string(q.size()) + " entries").coordinates_jacobian(q);
          },
          py::arg("hinge"), py::arg("q_el"),
          "d panel_coordinates / d q_el at q_el, (count x num_elastic): a velocity or shape s of the elastic "
          "coordinates moves the mesh by displacement_map @ panel_tangent @ s.")
      .def(
          "basis_info",
          [](const Model& s, int k) -> py::object {
            check_hinge(s, k);
            const auto& panel = s.body(k).panel;
            if (!panel || !panel->reduced()) return py::none();
            py::dict d;
            d["modes"] = panel->basis().modes;
            d["static_corrections"] = panel->basis().static_corrections;
            d["modal_derivatives"] = panel->basis().modal_derivatives;
            d["size"] = static_cast<int>(panel->basis().Phi.cols());
            d["omega2"] = panel->basis().omega2;
            return std::move(d);
          },
          py::arg("hinge"),
          "A reduced panel's basis: the vectors proposed of each kind, its size and Ritz values ((rad/s)^2); None "
          "otherwise.")
      .def("initial_positions", &Model::initial_positions)
      .def("retract",
           [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& dq) {
             s.check_state(q, Eigen::VectorXd::Zero(s.num_velocities()), &dq);
             return s.retract(q, dq);
           },
           py::arg("q"), py::arg("dq"))
      .def("make_data", [](const ModelPtr& s) { return std::make_unique<PyData>(s); },
           "A run's data for this model (lock histories, memos, staged kinematics).")
      .def(
          "residual",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             PyData* data) {
            s.check_state(q, v, &a);
            DataArg d(s, data);
            return residual(s, *d.data, q, v, a, t);
          },
          py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::kw_only(), py::arg("data") = nullptr)
      .def(
          "slaved_rows",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             PyData* data) {
            s.check_state(q, v, &a);
            DataArg d(s, data);
            Eigen::VectorXd rows;
            const bool formed = slaved_rows(s, *d.data, q, v, a, t, rows);
            const std::vector<int> slaved = TreeSystem(s, *d.data).slaved_velocities();
            return py::make_tuple(slaved, formed ? py::cast(rows) : py::none());
          },
          py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::kw_only(), py::arg("data") = nullptr,
          "(indices, rows): the velocity indices of the panels' in-plane coordinates (the rows Newton's "
          "membrane sweeps relax) and the residual's rows there as formed alone (multibody::slaved_rows), "
          "None where they are not (a reduced Green-strain panel; a hinge riding on any panel with in-plane "
          "coordinates).")
      .def(
          "newton_matrix",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             double c_a, double c_v, double c_q, PyData* data) {
            s.check_state(q, v, &a);
            DataArg d(s, data);
            py::gil_scoped_release release;
            return newton_matrix(s, *d.data, q, v, a, t, c_a, c_v, c_q).dense();
          },
          py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::arg("c_a"), py::arg("c_v"), py::arg("c_q"),
          py::kw_only(), py::arg("data") = nullptr,
          "c_a dr/da + c_v dr/dv + c_q dr/dq (dr/dq along retract()), assembled dense.")
      .def(
          "refreshed_newton_matrix",
          [](const Model& s, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, const Eigen::VectorXd& a0,
             double t0, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             double c_a, double c_v, double c_q, PyData* data) {
            s.check_state(q0, v0, &a0);
            s.check_state(q, v, &a);
            DataArg d(s, data);
            py::gil_scoped_release release;
            deployfx::integrate::BlockMatrix S = newton_matrix(s, *d.data, q0, v0, a0, t0, c_a, c_v, c_q);
            const bool refreshed = refresh_panel_blocks(s, *d.data, q, v, a, t, c_a, c_v, c_q, S);
            return std::make_pair(S.dense(), refreshed);
          },
          py::arg("q0"), py::arg("v0"), py::arg("a0"), py::arg("t0"), py::arg("q"), py::arg("v"), py::arg("a"),
          py::arg("t"), py::arg("c_a"), py::arg("c_v"), py::arg("c_q"), py::kw_only(), py::arg("data") = nullptr,
          "(S, refreshed): the Newton matrix at (q0, v0, a0, t0) with its panels' own elastic blocks formed anew "
          "at (q, v, a, t) (what a full-Newton step of a reduced Green-strain panel refreshes; "
          "NewtonOptions::elastic_refreshes), assembled dense; refreshed False (S as built) where the model "
          "cannot (no flexible panel, a hinge on a panel, a manifold panel).")
      .def(
          "newton_matrix_and_momentum_jacobian",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             double c_a, double c_v, double c_q, PyData* data) {
            s.check_state(q, v, &a);
            if (!(c_v > 0)) throw std::invalid_argument("c_v must be > 0");
            DataArg d(s, data);
            Eigen::MatrixXd J;
            Eigen::MatrixXd S = newton_matrix(s, *d.data, q, v, a, t, c_a, c_v, c_q, &J).dense();
            return py::make_tuple(S, J);
          },
          py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::arg("c_a"), py::arg("c_v"), py::arg("c_q"),
          py::kw_only(), py::arg("data") = nullptr,
          "(the Newton matrix, (1/c_v)(c_v dPi/dv + c_q dPi/dq)) from one set of derivative passes: what the "
          "integrator's momentum rows use.")
      .def(
          "momentum",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t, PyData* data) {
            s.check_state(q, v);
            DataArg d(s, data);
            return momentum(s, *d.data, q, v, t);
          },
          py::arg("q"), py::arg("v"), py::kw_only(), py::arg("t") = 0.0, py::arg("data") = nullptr)
      .def(
          "momentum_jacobian",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v, double c_q, PyData* data) {
            s.check_state(q, v);
            DataArg d(s, data);
            return momentum_jacobian(s, *d.data, q, v, c_v, c_q);
          },
          py::arg("q"), py::arg("v"), py::arg("c_v"), py::arg("c_q"), py::kw_only(), py::arg("data") = nullptr)
      .def(
          "base_velocity_jacobian",
          [](const Model& s, const Eigen::VectorXd& q, PyData* data) {
            const Eigen::VectorXd v = Eigen::VectorXd::Zero(s.num_velocities());
            s.check_state(q, v);
            if (!s.base_free()) throw std::invalid_argument("base_velocity_jacobian: the base is fixed");
            DataArg d(s, data);
            return Eigen::MatrixXd(base_velocity_jacobian(s, *d.data, q, v, 0.0));
          },
          py::arg("q"), py::kw_only(), py::arg("data") = nullptr,
          "dPi/d(v_W, w_B), (6 x 6), from the composite inertia (the momentum polish's matrix).")
      .def(
          "lock_events",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, PyData* data) {
            s.check_state(q, v);
            DataArg d(s, data);
            return lock_events(s, *d.data, q, v);
          },
          py::arg("q"), py::arg("v"), py::kw_only(), py::arg("data") = nullptr,
          "The locks' event functions (stop, latch per locked hinge) under data's history: positive while each "
          "wall's mode holds (m for a gap, N for a force; the latch's is inf until latched).")
      .def(
          "outputs",
          [](const Model& s, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
             PyData* data) {
            s.check_state(q, v, &a);
            DataArg d(s, data);
            return outputs_dict(outputs(s, *d.data, q, v, a, t));
          },
          py::arg("q"), py::arg("v"), py::arg("a"), py::arg("t"), py::kw_only(), py::arg("data") = nullptr)
      .def(
          "frames",
          [](const Model& s, const Eigen::MatrixXd& Q, const Eigen::VectorXd& t) {
            if (Q.cols() != s.num_positions() || t.size() != Q.rows())
              throw std::invalid_argument("q must be (n, " + std::to_string(s.num_positions()) +
                                          ") and t (n,), got q " + std::to_string(Q.rows()) + " x " +
                                          std::to_string(Q.cols()) + " and t " + std::to_string(t.size()));
            const int N = s.num_hinges();
            const Eigen::Index n = Q.rows();
            py::array_t<double> R({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(N), py::ssize_t{3}, py::ssize_t{3}});
            py::array_t<double> o({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(N), py::ssize_t{3}});
            auto Rm = R.mutable_unchecked<4>();
            auto om = o.mutable_unchecked<3>();
            Data d(s);
            Eigen::MatrixXd Rk, ok;
            for (Eigen::Index i = 0; i < n; ++i) {
              const Eigen::VectorXd q = Q.row(i).transpose();
              s.check_state(q, Eigen::VectorXd::Zero(s.num_velocities()));
              body_frames(s, d, q, t(i), Rk, ok);
              for (int k = 0; k < N; ++k)
                for (int r = 0; r < 3; ++r) {
                  om(i, k, r) = ok(r, k);
                  for (int c = 0; c < 3; ++c) Rm(i, k, r, c) = Rk(r, 3 * k + c);
                }
            }
            return py::make_tuple(R, o);
          },
          py::arg("q"), py::arg("t"),
          "Every body's frame in W at each recorded configuration: R_WC (n, hinges, 3, 3) and origins (n, hinges, 3), "
          "m; a hinge on a panel rides on its deformed mesh.");

  py::class_<PyData>(m, "Data", "A run's data on one model: lock histories, memos and the staged kinematics.")
      .def(py::init([](const ModelPtr& model) { return std::make_unique<PyData>(model); }), py::arg("model"))
      .def(
          "lock",
          [](const PyData& d, int k) {
            check_hinge(*d.model, k);
            return d.data.locks[static_cast<std::size_t>(k)];
          },
          py::arg("hinge"), "Hinge k's lock history (a copy): a LockHistory or a PinGrooveHistory.")
      .def(
          "set_lock",
          [](PyData& d, int k, const deployfx::joint::LockState& h) {
            check_hinge(*d.model, k);
            if (h.index() != d.data.locks[static_cast<std::size_t>(k)].index())
              throw std::invalid_argument("history: hinge " + std::to_string(k) + "'s lock takes a " +
                                          (h.index() ? "LockHistory" : "PinGrooveHistory"));
            d.data.locks[static_cast<std::size_t>(k)] = h;
          },
          py::arg("hinge"), py::arg("history"))
      .def(
          "reset_history",
          [](PyData& d, std::optional<Eigen::VectorXd> q) {
            const Eigen::VectorXd q0 = q ? *q : d.model->initial_positions();
            d.model->check_state(q0, Eigen::VectorXd::Zero(d.model->num_velocities()));
            d.data.reset_history(*d.model, q0);
          },
          py::arg("q") = py::none(), "A new run's history from configuration q (default: the initial one).");

  py::class_<Checkpoint>(m, "Checkpoint",
                         "Everything a run carries from one output instant to the next (multibody/simulate.hpp): "
                         "the integrator's state and history, the step control, the lock histories and impact records.")
      .def_property_readonly("t", [](const Checkpoint& c) { return c.driver.state.t; }, "The instant, s.")
      .def_property_readonly("t0", [](const Checkpoint& c) { return c.driver.t0; }, "The run's start, s.")
      .def_property_readonly("step", [](const Checkpoint& c) { return c.driver.k; },
                             "The output step it ends (t = t0 + step dt).")
      .def_property_readonly("q", [](const Checkpoint& c) { return c.driver.state.q; })
      .def_property_readonly("v", [](const Checkpoint& c) { return c.driver.state.v; })
      .def_property_readonly("impacts", [](const Checkpoint& c) { return impact_table(c.impacts); },
                             "The impact records so far (the last may be open).")
      .def("check", [](const Checkpoint& c, const ModelPtr& model) { check_checkpoint(*model, c); }, py::arg("model"),
           "ValueError unless it fits the model (state sizes, lock kinds).")
      .def("to_bytes", [](const Checkpoint& c) { return py::bytes(c.to_bytes()); })
      .def_static(
          "from_bytes", [](const py::bytes& b) { return Checkpoint::from_bytes(std::string(b)); }, py::arg("data"))
      .def(py::pickle([](const Checkpoint& c) { return py::bytes(c.to_bytes()); },
                      [](const py::bytes& b) { return Checkpoint::from_bytes(std::string(b)); }));

  m.attr("NEWTON_TOLERANCE_DEFAULT") = deployfx::integrate::NewtonOptions{}.tolerance;
  m.attr("CONTRACTION_DENSE_DEFAULT") = deployfx::integrate::NewtonOptions{}.contraction_dense;
  m.attr("NEWTON_TOLERANCE_RANGE") = py::make_tuple(deployfx::multibody::kMinNewtonTolerance,
                                                    deployfx::multibody::kMaxNewtonTolerance);
  m.def(
      "simulate",
      [](const ModelPtr& model, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, double t_end, double dt,
         const deployfx::integrate::AlphaParameters& scheme, bool reuse_jacobian, double tolerance,
         double newton_tolerance, const py::object& progress, const py::object& should_stop, PyData* data,
         const std::vector<long>& checkpoint_steps, const Checkpoint* resume, double contraction_dense) {
        DataArg d(*model, data);
        RunOptions opt;
        opt.t_end = t_end;
        opt.dt = dt;
        opt.scheme = scheme;
        opt.reuse_jacobian = reuse_jacobian;
        opt.tolerance = tolerance;
        opt.newton_tolerance = newton_tolerance;
        opt.contraction_dense = contraction_dense;
        for (long k : checkpoint_steps)
          if (k < 1) throw std::invalid_argument("checkpoint_steps: output steps must be >= 1, got " + std::to_string(k));
        return run_released(*model, *d.data, q0, v0, opt, progress, should_stop, checkpoint_steps, resume);
      },
      py::arg("model"), py::arg("q0"), py::arg("v0"), py::kw_only(), py::arg("t_end"), py::arg("dt"),
      py::arg("scheme"), py::arg("reuse_jacobian") = true, py::arg("tolerance") = 0.0,
      py::arg("newton_tolerance") = deployfx::integrate::NewtonOptions{}.tolerance, py::arg("progress") = py::none(),
      py::arg("should_stop") = py::none(), py::arg("data") = nullptr,
      py::arg("checkpoint_steps") = std::vector<long>{}, py::arg("resume") = nullptr, py::arg("contraction_dense") = 0.0,
      "Runs the model from (q0, v0) to t_end (s), output every dt (s), the GIL released; newton_tolerance: Newton's "
      "convergence test on the accelerations' relative error estimate, in [1e-14, 1e-4]. Every 0.2 s of wall time "
      "Ctrl-C is checked (main thread), progress(t, t_end) called and should_stop() asked (any thread); either "
      "stops the run, keeping what was computed. Returns a dict of numpy arrays: t (n,), q (n, nq), v (n, nv), "
      "per hinge (n, hinges): theta (rad), theta_rate (rad/s), spring_torque (N m), lock_force (N), lock_torque "
      "(N m), latched (0/1), strain_energy (J); hinge_force, hinge_moment (n, hinges, 3: N, N m, about the hinge "
      "point in the body's axes); linear_momentum, angular_momentum, base_linear_momentum, base_angular_momentum "
      "(n, 3: N s, N m s about W's origin, W axes); kinetic_energy, potential_energy (n,) J; and the run's counts "
      "(newton_iterations, substeps, steps, rejected, events, factorizations) and failure ('' when complete). "
      "checkpoint_steps: output steps k (t = k dt) at whose end a Checkpoint is taken (the list 'checkpoints'); "
      "resume: a Checkpoint to start from instead of (q0, v0), bit-identical to the run that took it. "
      "contraction_dense: modified Newton's contraction test for the rigid and reduced models' dense iteration "
      "matrix, in (0, 1) (0: the default, CONTRACTION_DENSE_DEFAULT; bench/newton_reuse.py).");
}
