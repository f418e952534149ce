#pragma once
// Fixed-output-step driver: advances an integrator to t_end and records every output step.
// - A step whose Newton iteration fails is retried as two half steps, recursively down to
//   dt / 2^10; if even that fails the run ends early with the reason, keeping what was computed.
// - Contact events are located in time: when a step takes one of the system's event functions
//   (SecondOrderSystem::gaps: a gap while a contact is open, its force while closed) from > 0 to
//   <= 0, the step is redone with the size found by safeguarded secant iteration (Illinois), so
//   it ends at the switch; that instant is recorded too. No impact is missed or tunnels
//   through, whatever dt. A search never steps below 1e-8 s (where the velocity update nears
//   round-off and Newton cannot converge): switches are located to that width at best, and one
//   closer than that to an output time ends the output step.
// - A contact is resolved whatever dt: while the system asks for it (step_error_bounds: a contact
//   in progress), steps are shortened until their local displacement error estimate
//   h^2 |beta - 1/6| |a_n+1 - a_n| respects the system's bounds, and grow back (at most doubling)
//   to dt after the contact; they divide the output step evenly, so the outputs stay on the
//   user's grid (Trajectory::contact_steps counts them).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "deployfx/integrate/generalized_alpha.hpp"

namespace deployfx::integrate {

/// Step-size control: tolerance <= 0 keeps the step fixed at the output step dt. Otherwise steps
/// are chosen (at most dt, at least min_step) so that the local displacement error estimate stays
/// below `tolerance` (absolute, in the coordinates' units: m and rad); rejected steps are redone.
struct StepControl {
  double tolerance = 0;     ///< m or rad; 0: fixed step
  double initial_step = 0;  ///< s; 0: dt / 10
  double min_step = 1e-9;   ///< s
};

/// What a run did; the states themselves go to the Observer at each recorded time.
struct Trajectory {
  std::vector<double> t;                // recorded times (output steps and contact onsets), s
  std::vector<int> newton_iterations;   // per recorded interval (summed over its substeps)
  long substeps = 0;                    // integrator steps taken (event searches included)
  long events = 0;                      // contact switches located
  long steps = 0;                       // accepted integrator steps (the outer ones)
  long rejected = 0;                    // steps rejected by the error control (contacts' included)
  long contact_steps = 0;               // accepted steps shortened below dt to resolve a contact
  std::string failure;                  // empty when t_end was reached
};

/// Called with the state at each recorded time, after the system's history was updated; returns
/// false to stop the run there (the trajectory so far is kept, `failure` says when).
using Observer = std::function<bool(const AlphaState&)>;
/// Called after every integrator step (event-search trials included) with the time reached;
/// returns a reason to stop the run (Ctrl-C, a stop flag), or an empty string to go on. The run
/// then ends with the states recorded so far and `failure` saying why and when.
using Poll = std::function<std::string(double)>;

/// What the driver and the integrator carry from one output instant to the next (the system's
/// history aside): with them a run resumes bit for bit.
struct DriverState {
  AlphaState state;           ///< at the output instant t0 + k dt (the predictor's history included)
  double t0 = 0;              ///< s, the run's start: output times are t0 + k dt
  long k = 0;                 ///< the output step just completed
  double h_try = 0;           ///< s, the error control's next step
  double h_contact = 0;       ///< s, the next step while a contact is resolved
  /// The last resolved contact's step bounds, kept until the steps are back at dt (run()).
  SecondOrderSystem::StepBounds contact_bounds;
  GeneralizedAlpha::Solver solver;  ///< the integrator's Newton matrix and reuse counters
};

/// Checkpoints of a run: `sink` is called at the end of each output step listed in `at` (after
/// the state was recorded and the system's history updated); taking one changes nothing in the
/// run. `resume`: start from that driver state (the system's history restored by the caller)
/// instead of `state`; its instant is recorded, not accepted again.
struct Checkpoints {
  std::vector<long> at;
  std::function<void(const DriverState&)> sink;
  const DriverState* resume = nullptr;
};

/// Output every dt = h (and at located events), with the step control `control`.
/// Throws std::invalid_argument for h <= 0, t_end < t0 or a negative tolerance.
Trajectory run(GeneralizedAlpha& integrator, AlphaState state, double t_end, double h,
               const StepControl& control, const Observer& observe = {}, const Poll& poll = {},
               const Checkpoints* checkpoints = nullptr);
/// run() with fixed steps.
Trajectory run_fixed_step(GeneralizedAlpha& integrator, AlphaState state, double t_end, double h,
                          const Observer& observe = {});

}  // namespace deployfx::integrate
