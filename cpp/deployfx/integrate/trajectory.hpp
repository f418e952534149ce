#pragma once
// Fixed-output-step driver: advances an integrator to t_end and records every output step. A step
// whose Newton iteration fails is retried as two half steps, recursively down to dt / 2^10 (fast
// transients such as the preloaded hinge's first instants); if even that fails the run ends early
// with the reason, keeping everything computed so far.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"

namespace deployfx::integrate {

struct Trajectory {
  std::vector<double> t;                // (steps + 1), s
  std::vector<Eigen::VectorXd> q, v;    // per recorded time
  std::vector<int> newton_iterations;   // per output step (summed over its substeps)
  long substeps = 0;                    // integrator steps taken, >= number of output steps
  std::string failure;                  // empty when t_end was reached
};

/// Throws std::invalid_argument for h <= 0 or t_end < t0.
Trajectory run_fixed_step(const GeneralizedAlpha& integrator, AlphaState state, double t_end, double h);

}  // namespace deployfx::integrate
