#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <ctime>
#include <string>
#include <vector>

#include "deployfx/integrate/anderson.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/integrate/generalized_alpha.hpp"
#include "deployfx/integrate/linear_system.hpp"
#include "deployfx/integrate/trajectory.hpp"

namespace py = pybind11;
using namespace deployfx::integrate;

void define_integrate(py::module_& m) {
  py::class_<AlphaParameters>(m, "AlphaParameters")
      .def_static("newmark", &AlphaParameters::newmark, py::arg("beta"), py::arg("gamma"))
      .def_static("hht", &AlphaParameters::hht, py::arg("alpha"))
      .def_static("generalized_alpha", &AlphaParameters::generalized_alpha, py::arg("rho_inf"))
      .def_readonly("alpha_m", &AlphaParameters::alpha_m)
      .def_readonly("alpha_f", &AlphaParameters::alpha_f)
      .def_readonly("beta", &AlphaParameters::beta)
      .def_readonly("gamma", &AlphaParameters::gamma);

  m.def("bordered_solve",
        [](const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
           const Eigen::SparseMatrix<double>& E, const Eigen::VectorXd& r, bool exact) {
          const Eigen::Index nb = A.rows(), ne = E.rows();
          if (A.cols() != nb || B.rows() != nb || B.cols() != ne || C.rows() != ne || C.cols() != nb ||
              E.cols() != ne || r.size() != nb + ne)
            throw std::invalid_argument("bordered_solve: S = [A B; C E] must be square with A (nb x nb), "
                                        "E (ne x ne), and r of size nb + ne");
          BlockMatrix S{A, B, C, E};
          S.E.makeCompressed();
          BorderedSolver solver;
          if (!solver.factorize(S)) throw std::invalid_argument("bordered_solve: S is singular");
          return py::make_tuple(solver.solve(r, exact), std::string(solver.method()));
        },
        py::arg("A"), py::arg("B"), py::arg("C"), py::arg("E"), py::arg("r"), py::arg("exact") = true,
        "Newton's bordered solve (integrate/bordered_solver), for the tests: x = S^-1 r and how E "
        "was factorized (BorderedSolver::method).");

  m.def("anderson_fixed_point",
        [](const Eigen::MatrixXd& G, const Eigen::VectorXd& c, const Eigen::VectorXd& x0, int depth, int iterations) {
          const Eigen::Index n = G.rows();
          if (G.cols() != n || c.size() != n || x0.size() != n)
            throw std::invalid_argument("anderson_fixed_point: G must be square (n x n), c and x0 of size n");
          if (depth < 0) throw std::invalid_argument("anderson_fixed_point: depth must be >= 0");
          if (iterations < 0 || iterations > 10000)
            throw std::invalid_argument("anderson_fixed_point: iterations must be in [0, 10000]");
          AndersonMixing mixing(depth);
          Eigen::MatrixXd X(n, iterations + 1);
          Eigen::VectorXd x = x0;
          X.col(0) = x;
          for (int k = 0; k < iterations; ++k) {
            const Eigen::VectorXd f = G * x + c - x;
            mixing.update(x, f);
            X.col(k + 1) = x;
          }
          return X;
        },
        py::arg("G"), py::arg("c"), py::arg("x0"), py::arg("depth"), py::arg("iterations"),
        "Anderson acceleration (integrate/anderson) of the fixed-point iteration x <- G x + c, for the "
        "tests: the iterates x_0 .. x_iterations as columns.");

  m.def("bordered_solve_cost",
        [](const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
           const Eigen::SparseMatrix<double>& E, const Eigen::VectorXd& r, double seconds) {
          const Eigen::Index nb = A.rows(), ne = E.rows();
          if (A.cols() != nb || B.rows() != nb || B.cols() != ne || C.rows() != ne || C.cols() != nb ||
              E.cols() != ne || r.size() != nb + ne)
            throw std::invalid_argument("bordered_solve_cost: S = [A B; C E] must be square with A (nb x nb), "
                                        "E (ne x ne), and r of size nb + ne");
          if (!(seconds > 0 && seconds <= 60))
            throw std::invalid_argument("bordered_solve_cost: seconds must be in (0, 60]");
          BlockMatrix S{A, B, C, E};
          S.E.makeCompressed();
          std::string method;
          double factorize = 0, solve = 0, solve_exact = 0;
          {
            py::gil_scoped_release release;
            BorderedSolver solver;
            if (!solver.factorize(S)) throw std::invalid_argument("bordered_solve_cost: S is singular");
            // Each the median CPU time of this thread (one core) over batches of about 1/40 of
            // `seconds`: the pattern's analysis (the first factorization, above) excluded.
            auto median_cpu = [seconds](auto&& f) {
              auto now = [] {
                timespec ts;
                clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
                return ts.tv_sec + 1e-9 * ts.tv_nsec;
              };
              double t0 = now();
              f();
              const double once = std::max(now() - t0, 1e-7);
              const long batch = std::max(1L, static_cast<long>(seconds / 40 / once));
              std::vector<double> times;
              const double start = now();
              while (times.size() < 5 || now() - start < seconds) {
                t0 = now();
                for (long i = 0; i < batch; ++i) f();
                times.push_back((now() - t0) / batch);
              }
              std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
              return times[times.size() / 2];
            };
            Eigen::VectorXd x;
            factorize = median_cpu([&] { solver.factorize(S); });
            solve = median_cpu([&] { x = solver.solve(r, false); });
            solve_exact = median_cpu([&] { x = solver.solve(r, true); });
            method = solver.method();
          }
          py::dict d;
          d["method"] = method;
          d["factorize"] = factorize;
          d["solve"] = solve;
          d["solve_exact"] = solve_exact;
          return d;
        },
        py::arg("A"), py::arg("B"), py::arg("C"), py::arg("E"), py::arg("r"), py::arg("seconds") = 0.3,
        "The engine's bordered solver's cost on S = [A B; C E], for bench/targets.py: a dict of "
        "``method`` (how E was factorized) and the median CPU seconds of one thread for one "
        "``factorize`` (its pattern analysed once before), one ``solve`` (unrefined: a kept "
        "matrix's Newton step) and one ``solve_exact`` (refined against E's skew part: a fresh "
        "matrix's), each timed over about ``seconds``.");

  m.def("simulate_linear",
        [](const Eigen::MatrixXd& M, const Eigen::MatrixXd& C, const Eigen::MatrixXd& K,
           const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, double t_end, double dt,
           const AlphaParameters& p) {
          LinearSystem sys(M, C, K);
          if (q0.size() != M.rows() || v0.size() != M.rows())
            throw std::invalid_argument("q0 and v0 must have the size of M");
          Trajectory tr;
          std::vector<double> Q, V;
          {
            py::gil_scoped_release release;
            GeneralizedAlpha integrator(sys, p);
            auto record = [&](const AlphaState& s) {
              Q.insert(Q.end(), s.q.data(), s.q.data() + s.q.size());
              V.insert(V.end(), s.v.data(), s.v.data() + s.v.size());
              return true;
            };
            tr = run_fixed_step(integrator, integrator.initial_state(0.0, q0, v0), t_end, dt, record);
          }
          const py::ssize_t n = static_cast<py::ssize_t>(tr.t.size()), m = M.rows();
          py::dict d;
          d["t"] = py::array_t<double>(n, tr.t.data());
          d["q"] = py::array_t<double>({n, m}, Q.data());
          d["v"] = py::array_t<double>({n, m}, V.data());
          d["newton_iterations"] = tr.newton_iterations;
          d["substeps"] = tr.substeps;
          d["failure"] = tr.failure;
          return d;
        },
        py::arg("M"), py::arg("C"), py::arg("K"), py::arg("q0"), py::arg("v0"), py::arg("t_end"),
        py::arg("dt"), py::arg("scheme"));
}
