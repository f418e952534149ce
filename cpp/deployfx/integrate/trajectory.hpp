#pragma once
// Fixed-step driver: steps an integrator to t_end and records every step. A failing step ends the
// run early with the reason, keeping everything computed so far.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"

namespace deployfx::integrate {

struct Trajectory {
  std::vector<double> t;                // (steps + 1), s
  std::vector<Eigen::VectorXd> q, v;    // per recorded time
  std::vector<int> newton_iterations;   // per step
  std::string failure;                  // empty when t_end was reached
};

/// Throws std::invalid_argument for h <= 0 or t_end < t0.
Trajectory run_fixed_step(const GeneralizedAlpha& integrator, AlphaState state, double t_end, double h);

}  // namespace deployfx::integrate
