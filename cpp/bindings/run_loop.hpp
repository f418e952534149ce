#pragma once
// A simulation run for the simulate_* bindings: generalized-alpha with the stepper of
// integrate/trajectory.hpp, the GIL released, the system's run lock held, and every 0.2 s of wall
// time the GIL taken to answer Ctrl-C and call progress(t, t_end); either one stops the run,
// keeping what was computed (the trajectory's `failure` says why and when). `record(state)` is
// called at each recorded instant (without the GIL). Used by simulate_hinged and simulate_chain.
#include <pybind11/pybind11.h>

#include <chrono>
#include <mutex>
#include <string>

#include "deployfx/integrate/generalized_alpha.hpp"
#include "deployfx/integrate/trajectory.hpp"

struct RunOptions {
  double t_end = 0, dt = 0;
  deployfx::integrate::AlphaParameters scheme;
  bool reuse_jacobian = true;
  double tolerance = 0;  ///< 0: fixed steps
};

/// Returns the trajectory; *factorizations gets the iteration matrix's factorization count.
template <class System, class Record>
deployfx::integrate::Trajectory run_released(const System& sys, const Eigen::VectorXd& q0,
                                             const Eigen::VectorXd& v0, const RunOptions& opt,
                                             const pybind11::object& progress, Record&& record,
                                             long* factorizations) {
  namespace py = pybind11;
  auto last = std::chrono::steady_clock::now();
  std::string stopped;
  auto observe = [&](const deployfx::integrate::AlphaState& s) {
    record(s);
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(200)) return true;
    last = now;
    py::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      stopped = "interrupted (Ctrl-C)";
      return false;
    }
    if (!progress.is_none()) {
      try {
        progress(s.t, opt.t_end);
      } catch (py::error_already_set& e) {
        stopped = std::string("the progress callback raised: ") + e.what();
        return false;
      }
    }
    return true;
  };
  deployfx::integrate::Trajectory tr;
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> one_run_at_a_time(sys.run_mutex());
    deployfx::integrate::NewtonOptions newton;
    newton.reuse_jacobian = opt.reuse_jacobian;
    const deployfx::integrate::GeneralizedAlpha integrator(sys, opt.scheme, newton);
    sys.reset_history();
    deployfx::integrate::StepControl control;
    control.tolerance = opt.tolerance;
    tr = deployfx::integrate::run(integrator, integrator.initial_state(0.0, q0, v0), opt.t_end, opt.dt,
                                  control, observe);
    *factorizations = integrator.factorizations();
  }
  if (!stopped.empty()) tr.failure = stopped + " at t = " + std::to_string(tr.t.back()) + " s";
  return tr;
}
