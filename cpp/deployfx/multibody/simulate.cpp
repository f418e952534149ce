#include "deployfx/multibody/simulate.hpp"

#include <sstream>
#include <stdexcept>

#include "deployfx/multibody/tree_system.hpp"

namespace deployfx::multibody {

RunResult simulate(const Model& m, Data& d, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                   const RunOptions& options, const integrate::Observer& record, const integrate::Poll& poll,
                   const CheckpointOptions* checkpoints) {
  if (!(options.newton_tolerance >= kMinNewtonTolerance && options.newton_tolerance <= kMaxNewtonTolerance)) {
    std::ostringstream e;
    e << "newton_tolerance = " << options.newton_tolerance << " is out of range: must be in ["
      << kMinNewtonTolerance << ", " << kMaxNewtonTolerance << "]";
    throw std::invalid_argument(e.str());
  }
  if (!(options.contraction_dense >= 0 && options.contraction_dense < 1)) {
    std::ostringstream e;
    e << "contraction_dense = " << options.contraction_dense
      << " is out of range: must be in (0, 1), or 0 for the default";
    throw std::invalid_argument(e.str());
  }
  const Checkpoint* resume = checkpoints ? checkpoints->resume : nullptr;
  if (resume) {
    check_checkpoint(m, *resume);
    d.locks = resume->locks;
    d.impacts = resume->impacts;
    d.accepted_q = resume->accepted_q;
  } else {
    m.check_state(q0, v0);
    d.reset_history(m, q0);
  }
  TreeSystem system(m, d);
  integrate::NewtonOptions newton;
  newton.reuse_jacobian = options.reuse_jacobian;
  newton.tolerance = options.newton_tolerance;
  if (options.contraction_dense > 0) newton.contraction_dense = options.contraction_dense;
  integrate::GeneralizedAlpha integrator(system, options.scheme, newton);
  integrate::StepControl control;
  control.tolerance = options.tolerance;
  integrate::Checkpoints points;
  if (checkpoints) {
    points.at = checkpoints->at;
    points.resume = resume ? &resume->driver : nullptr;
    if (checkpoints->sink)
      points.sink = [&](const integrate::DriverState& s) {
        checkpoints->sink(Checkpoint{s, d.locks, d.impacts, d.accepted_q});
      };
  }
  RunResult out;
  integrate::AlphaState start;
  if (resume) {
    start = resume->driver.state;
  } else {
    // No consistent start: the model, not the run, is at fault (a fuzz case: a free base of
    // 1e-100 kg m^2 under a hinge whose fitting alone has inertia), so a ValueError that says what
    // to look for rather than a failed run.
    try {
      start = integrator.initial_state(0.0, q0, v0);
    } catch (const integrate::StepFailure& e) {
      throw std::invalid_argument(std::string(e.what()) +
                                  " to working precision: a motion the hinges allow carries no inertia against the "
                                  "rest (a massless body, or a base or hinge fitting whose inertia is negligible)");
    }
  }
  out.trajectory = integrate::run(integrator, std::move(start), options.t_end, options.dt, control, record, poll,
                                  checkpoints ? &points : nullptr);
  out.factorizations = integrator.factorizations();
  return out;
}

}  // namespace deployfx::multibody
