#pragma once
// What a run records at each output instant, from the state and its accelerations: per hinge its
// angle, rate, spring and lock loads and the reaction it carries, per panel its strain energy,
// and the system's energies and momenta.
#include <Eigen/Core>

#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

struct Outputs {
  // Per hinge k (size num_hinges()).
  Eigen::VectorXd theta, rate;         ///< rad, rad/s: the travel from stowed
  Eigen::VectorXd spring_torque;       ///< N m: tau0 - k_theta theta
  Eigen::VectorXd lock_force;          ///< N: the lock's normal force (>= 0), both walls
  Eigen::VectorXd lock_torque;         ///< N m: the lock's torque on theta (contact and friction)
  Eigen::VectorXd latched;             ///< 1 once the lock has latched, else 0
  Eigen::VectorXd strain_energy;       ///< J: the panel's (0 without a deforming panel)
  /// The reaction the parent exerts on hinge k's subtree through the joint (bearings and lock pin
  /// together: the lock acts as a torque about the axis), about the hinge point, in C_k's axes:
  /// force (N) and moment (N m, perpendicular to the axis; the axial torque is the spring's, the
  /// damper's and the lock's).
  Eigen::Matrix3Xd hinge_force, hinge_moment;
  Eigen::Vector3d P_W, H_W;            ///< total linear (N s) and angular momentum about W's origin (N m s)
  Eigen::Vector3d P_base_W, H_base_W;  ///< the base's share
  /// The momentum the bodies carry: sum over bodies (base included) of |P_b| (N s) and of |H_b|
  /// (about W's origin, N m s), the scale of the total's conservation error.
  double P_scale = 0, H_scale = 0;
  double kinetic = 0;                  ///< J
  double potential = 0;                ///< J: the springs' and the panels' strain energy
};

/// The outputs at (q, v) with accelerations a at time t (d's lock history as it stands).
Outputs outputs(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                const Eigen::VectorXd& a, double t);

/// Every body's frame in W at (q, t): R_WC side by side (3 x 3N) and origins (3 x N, m). On a
/// panel a hinge rides on the deformed mesh.
void body_frames(const Model& m, Data& d, const Eigen::VectorXd& q, double t, Eigen::MatrixXd& R, Eigen::MatrixXd& o);

}  // namespace deployfx::multibody
