#pragma once
// The locks' contact events and history (joint/hinge_lock.hpp): the event functions the stepper
// locates in time (integrate/trajectory.hpp), the history updated on accepted steps only, and
// the locks' limit on a Newton step across their friction band.
#include <Eigen/Core>

#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

/// Two event functions per locked hinge (stop, latch), in hinge order; positive while each wall's
/// mode holds (joint::lock_events) under d's history.
Eigen::VectorXd lock_events(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v);
/// Updates d's lock histories after an accepted step ending at (q, v); an event function at or
/// below its `margin` (lock_events' order; empty: 0) switches.
void accept(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
            const Eigen::VectorXd& margin = Eigen::VectorXd());
/// The smallest of the locks' joint::friction_step_limit for the velocity change dv.
double friction_step_limit(const Model& m, const Data& d, const Eigen::VectorXd& v, const Eigen::VectorXd& dv);

}  // namespace deployfx::multibody
