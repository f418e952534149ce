#include "deployfx/multibody/simulate.hpp"

#include "deployfx/multibody/tree_system.hpp"

namespace deployfx::multibody {

RunResult simulate(const Model& m, Data& d, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                   const RunOptions& options, const integrate::Observer& record, const integrate::Poll& poll) {
  m.check_state(q0, v0);
  d.reset_history(m, q0);
  TreeSystem system(m, d);
  integrate::NewtonOptions newton;
  newton.reuse_jacobian = options.reuse_jacobian;
  integrate::GeneralizedAlpha integrator(system, options.scheme, newton);
  integrate::StepControl control;
  control.tolerance = options.tolerance;
  RunResult out;
  out.trajectory = integrate::run(integrator, integrator.initial_state(0.0, q0, v0), options.t_end, options.dt,
                                  control, record, poll);
  out.factorizations = integrator.factorizations();
  return out;
}

}  // namespace deployfx::multibody
