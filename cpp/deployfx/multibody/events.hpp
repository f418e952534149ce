#pragma once
// The locks' contact events and history (joint/lock.hpp): the event functions the stepper
// locates in time (integrate/trajectory.hpp), the history updated on accepted steps only, and
// the locks' limit on a Newton step across their friction band.
#include <Eigen/Core>

#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

/// The locks' event functions (joint::events: two per stop-and-latch lock, one per facet of a
/// groove and its latch pin's drop), in hinge order; positive while each contact's mode holds
/// under d's history.
Eigen::VectorXd lock_events(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v);
/// Updates d's lock histories after an accepted step ending at (q, v, t); an event function at or
/// below its `margin` (lock_events' order; empty: 0) switches. A wall that closes gets its
/// time scale from the pin's effective mass there, or where the law's dashpot stops the pin
/// alone, from the hinge's with the panels held rigid (hinge_inverse_inertia); every wall's
/// contact is followed into d.impacts (joint/impact_record.hpp). Returns true when a latch pin
/// dropped to another support.
bool accept(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t,
            const Eigen::VectorXd& margin = Eigen::VectorXd());
/// The inverse of hinge k's effective inertia (1/(kg m^2)) against an impulse about its axis:
/// `free`, e^T M(q)^-1 e with every other coordinate free (the mass matrix, dr/da; on a deforming
/// panel that is the fitting's and the root's, far below the panel's), and `rigid`, the same with
/// every panel's deformation rates held at zero (the mass matrix's border block).
struct HingeInverseInertia {
  double free = 0, rigid = 0;
};
HingeInverseInertia hinge_inverse_inertia(const Model& m, Data& d, const Eigen::VectorXd& q, double t, int k);
/// integrate::SecondOrderSystem::step_bounds at the last accepted state: on each hinge angle whose
/// lock has a contact being resolved, joint::resolution's error (rad); empty with none.
integrate::SecondOrderSystem::StepBounds step_bounds(const Model& m, const Data& d);
/// The smallest of the locks' joint::friction_step_limit for the velocity change dv at (q, v).
double friction_step_limit(const Model& m, const Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& dv);

}  // namespace deployfx::multibody
