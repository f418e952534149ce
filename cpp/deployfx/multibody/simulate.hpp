#pragma once
// A run: generalized-alpha (integrate/generalized_alpha.hpp) with the stepper of
// integrate/trajectory.hpp on one model and one run's Data, from (q0, v0) at t = 0. The only run
// loop of the engine; the bindings add the GIL, Ctrl-C and the progress bar around it.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"
#include "deployfx/integrate/trajectory.hpp"
#include "deployfx/multibody/checkpoint.hpp"
#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

struct RunOptions {
  double t_end = 0;   ///< s
  double dt = 0;      ///< output step (and the fixed step), s
  integrate::AlphaParameters scheme = integrate::AlphaParameters::generalized_alpha(0.8);
  bool reuse_jacobian = true;
  double tolerance = 0;  ///< m or rad; 0: fixed steps
  /// Newton's convergence test (integrate::NewtonOptions::tolerance): the estimated error of the
  /// accelerations relative to max(|vdot_n|, 1), in [kMinNewtonTolerance, kMaxNewtonTolerance].
  double newton_tolerance = integrate::NewtonOptions{}.tolerance;
  /// Modified Newton's contraction test for a dense iteration matrix (the rigid and reduced
  /// models: integrate::NewtonOptions::contraction_dense), in (0, 1); 0: NewtonOptions' default.
  /// For bench/newton_reuse.py.
  double contraction_dense = 0;
};

/// The range of RunOptions::newton_tolerance: below 1e-14 the test asks for less than the
/// solve's round-off; above 1e-4 a step's error is no longer small against dt's.
inline constexpr double kMinNewtonTolerance = 1e-14, kMaxNewtonTolerance = 1e-4;

struct RunResult {
  integrate::Trajectory trajectory;
  long factorizations = 0;  ///< of the Newton matrix
};

/// Checkpoints of a run (integrate::Checkpoints): at the end of output steps `at`, into `sink`;
/// `resume`: start from that checkpoint instead of (q0, v0) (its history replaces d's).
struct CheckpointOptions {
  std::vector<long> at;
  std::function<void(Checkpoint)> sink;
  const Checkpoint* resume = nullptr;
};

/// Runs from (q0, v0) with d's lock histories reset; `record(state)` at each recorded time
/// (after the history was updated), `poll(t)` after every step (see integrate::run). Throws
/// std::invalid_argument for bad options or a state of the wrong size; a run that fails ends
/// early with `trajectory.failure` saying when and why.
RunResult simulate(const Model& m, Data& d, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                   const RunOptions& options, const integrate::Observer& record = {},
                   const integrate::Poll& poll = {}, const CheckpointOptions* checkpoints = nullptr);

}  // namespace deployfx::multibody
