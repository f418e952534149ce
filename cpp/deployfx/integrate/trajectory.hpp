#pragma once
// Fixed-output-step driver: advances an integrator to t_end and records every output step.
// - A step whose Newton iteration fails is retried as two half steps, recursively down to
//   dt / 2^10; if even that fails the run ends early with the reason, keeping what was computed.
// - Contact events are located in time: when a step takes one of the system's event functions
//   (SecondOrderSystem::gaps: a gap while a contact is open, its force while closed) from > 0 to
//   <= 0, the step is redone with the size found by safeguarded secant iteration (Illinois), so
//   it ends at the switch; that instant is recorded too. No impact is missed or tunnels
//   through, whatever dt.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"

namespace deployfx::integrate {

struct Trajectory {
  std::vector<double> t;                // recorded times (output steps and contact onsets), s
  std::vector<Eigen::VectorXd> q, v;    // per recorded time
  std::vector<int> newton_iterations;   // per recorded interval (summed over its substeps)
  long substeps = 0;                    // integrator steps taken (event searches included)
  long events = 0;                      // contact onsets located
  std::string failure;                  // empty when t_end was reached
};

/// Called with the state at each recorded time, after the system's history was updated.
using Observer = std::function<void(const AlphaState&)>;

/// Throws std::invalid_argument for h <= 0 or t_end < t0.
Trajectory run_fixed_step(const GeneralizedAlpha& integrator, AlphaState state, double t_end, double h,
                          const Observer& observe = {});

}  // namespace deployfx::integrate
