#pragma once
// The applied and inertial loads of the tree at the state staged in Data (forward_kinematics):
// each hinge's torque (spring, damper, lock) and each body's inertial wrench.
#include <Eigen/Core>
#include <vector>

#include "deployfx/joint/lock.hpp"
#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

/// Hinge k's applied torque tau = tau0 - k_theta theta - c_theta theta' + the lock's
/// (joint/lock.hpp) at (theta, theta'), with its derivatives.
struct HingeTorque {
  double tau = 0;      ///< N m
  double d_theta = 0;  ///< d tau / d theta, N m/rad
  double d_rate = 0;   ///< d tau / d theta', N m s/rad
  joint::LockLoad lock;
};
HingeTorque hinge_torque(const Model& m, const Data& d, int k);

/// The base's Newton-Euler forces at its staged motion (B axes, about B's origin): (F, M).
Vector6<double> base_inertial_wrench(const Model& m, const Data& d);

/// Body k's inertial wrench at its staged motion (force; moment about C's origin; C axes): its
/// rigid parts' Newton-Euler forces plus, for a panel, the floating-frame forces
/// (docs/engine-design.md, "Body-level equations"); `Q` (if not null) gets the panel's
/// generalized inertial force on its inertia's dofs, with the panel's mass-proportional damping
/// alpha_M L_c d' (the residual's; FlexibleBody::add_elastic_force leaves it out).
Vector6<double> inertial_wrench(const Model& m, Data& d, int k, Eigen::VectorXd* Q);

}  // namespace deployfx::multibody
