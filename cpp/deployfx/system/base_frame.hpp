#pragma once
// The base frame B of a multibody system, shared by the systems that carry one (hinged_system,
// hinge_chain):
//   q = [r_W (3), unit quaternion of R_WB (w, x, y, z)] ...,  v = [v_W (3, W axes), w_B (3, B axes)] ...
// A fixed base has no coordinates: it rests at W's origin with R_WB = I. The attitude is updated
// by a body-frame rotation vector, R_WB exp(dpsi) (Bruls & Cardona, J. Comput. Nonlinear Dyn. 5,
// 2010); every other coordinate is additive.
#include <Eigen/Core>
#include <string>

#include "deployfx/body/rigid_inertia.hpp"

namespace deployfx::system {

constexpr int kBasePositions = 7;   ///< r_W and the quaternion
constexpr int kBaseVelocities = 6;  ///< v_W and w_B

/// B's motion at one instant. The origin's velocity and acceleration are given both in W axes
/// (the coordinates) and in B axes (V_B = R_WB^T v_W, a_B = R_WB^T a_W: the Newton-Euler inputs).
struct BaseMotion {
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d r_W = Eigen::Vector3d::Zero(), v_W = Eigen::Vector3d::Zero(), a_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d V_B = Eigen::Vector3d::Zero(), a_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero(), wd_B = Eigen::Vector3d::Zero();  ///< rad/s, rad/s^2
};

/// B's motion from the leading base blocks of q, v and a (a may be null: zero accelerations).
BaseMotion base_motion(bool free, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a);

/// q (+) dq with the base blocks leading (free base) and every other coordinate additive.
Eigen::VectorXd retract_with_base(bool free, const Eigen::VectorXd& q, const Eigen::VectorXd& dq);

/// Checks a rigid body's inertia: mass finite and >= 0 (> 0 if `definite`), com finite, inertia
/// about the com symmetric positive semidefinite (definite if `definite`). Throws
/// std::invalid_argument naming `<name>.mass`, `<name>.com` or `<name>.inertia`.
void check_rigid_inertia(const std::string& name, const body::RigidInertia& body, bool definite);

}  // namespace deployfx::system
