#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "deployfx/integrate/generalized_alpha.hpp"
#include "deployfx/integrate/linear_system.hpp"
#include "deployfx/integrate/trajectory.hpp"

namespace py = pybind11;
using namespace deployfx::integrate;

namespace {

// Trajectory -> dict of numpy arrays (t: (n,), q: (n, nq), v: (n, nv)).
py::dict to_dict(const Trajectory& tr) {
  const Eigen::Index n = static_cast<Eigen::Index>(tr.t.size());
  const Eigen::Index nq = n ? tr.q[0].size() : 0, nv = n ? tr.v[0].size() : 0;
  Eigen::MatrixXd Q(n, nq), V(n, nv);
  for (Eigen::Index k = 0; k < n; ++k) {
    Q.row(k) = tr.q[k].transpose();
    V.row(k) = tr.v[k].transpose();
  }
  py::dict d;
  d["t"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(tr.t.data(), n));
  d["q"] = Q;
  d["v"] = V;
  d["newton_iterations"] = tr.newton_iterations;
  d["substeps"] = tr.substeps;
  d["failure"] = tr.failure;
  return d;
}

}  // namespace

void define_integrate(py::module_& m) {
  py::class_<AlphaParameters>(m, "AlphaParameters")
      .def_static("newmark", &AlphaParameters::newmark, py::arg("beta"), py::arg("gamma"))
      .def_static("hht", &AlphaParameters::hht, py::arg("alpha"))
      .def_static("generalized_alpha", &AlphaParameters::generalized_alpha, py::arg("rho_inf"))
      .def_readonly("alpha_m", &AlphaParameters::alpha_m)
      .def_readonly("alpha_f", &AlphaParameters::alpha_f)
      .def_readonly("beta", &AlphaParameters::beta)
      .def_readonly("gamma", &AlphaParameters::gamma);

  m.def("simulate_linear",
        [](const Eigen::MatrixXd& M, const Eigen::MatrixXd& C, const Eigen::MatrixXd& K,
           const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, double t_end, double dt,
           const AlphaParameters& p) {
          const LinearSystem sys(M, C, K);
          if (q0.size() != M.rows() || v0.size() != M.rows())
            throw std::invalid_argument("q0 and v0 must have the size of M");
          Trajectory tr;
          {
            py::gil_scoped_release release;
            const GeneralizedAlpha integrator(sys, p);
            tr = run_fixed_step(integrator, integrator.initial_state(0.0, q0, v0), t_end, dt);
          }
          return to_dict(tr);
        },
        py::arg("M"), py::arg("C"), py::arg("K"), py::arg("q0"), py::arg("v0"), py::arg("t_end"),
        py::arg("dt"), py::arg("scheme"));
}
