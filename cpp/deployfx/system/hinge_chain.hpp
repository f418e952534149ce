#pragma once
// A base (free-floating or fixed) carrying a serial chain of N >= 1 rigid bodies on revolute
// spring hinges (issue 5: a yoke and panels, as on solar arrays): hinge 0 is on the base, hinge k
// on body k-1, and body k turns with its frame C_k, whose origin lies on hinge k's axis:
//   R_PC_k(theta_k) = Rot(axis_k, theta_k) R_PC0_k,   p_PoCo_P = point_k (fixed in the parent P).
// Each hinge has a spring tau0 - k_theta theta, a viscous damper and optionally a lock
// (joint/hinge_lock.hpp, with its own history).
//
// Coordinates (minimal, tree-structured; docs/engine-design.md "Coordinates"):
//   q = [r_W (3), quaternion of R_WB (w, x, y, z)] [theta_0 .. theta_N-1]   (base blocks: free only)
//   v = [v_W (3, W axes), w_B (3, B axes)]         [theta'_0 .. theta'_N-1]
// Equations by virtual power over all bodies (docs/engine-design.md "System assembly"):
//   r = sum_b J_b^T f_b(q, v, vdot) - tau(q, v, t) = M(q) vdot - f(q, v, t) = 0,
// f_b the Newton-Euler inertial wrench of body b about its origin (body::RigidInertia), evaluated
// by a forward pass of the body motions and a backward pass of the wrenches (a recursive
// Newton-Euler, Featherstone, "Rigid Body Dynamics Algorithms", 2008, Sec. 5.3); the mass matrix
// sum_b J_b^T M_b J_b from the body Jacobians J_b (twists in body axes, J_b v = (V_b, w_b)).
#include <Eigen/Core>
#include <mutex>
#include <optional>
#include <vector>

#include "deployfx/body/rigid_inertia.hpp"
#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/system/base_frame.hpp"
#include "deployfx/system/hinged_system.hpp"  // BaseSpec

namespace deployfx::system {

/// Hinge k of a chain and the rigid body it carries. P is the parent's frame (B for hinge 0, else
/// C_{k-1}); C the child's.
struct ChainHingeSpec {
  Eigen::Vector3d point_P = Eigen::Vector3d::Zero();    ///< a point of the axis and C's origin, m, P axes
  Eigen::Vector3d axis_P = Eigen::Vector3d::UnitY();    ///< unit axis, P axes
  Eigen::Matrix3d R_PC0 = Eigen::Matrix3d::Identity();  ///< C's axes at theta = 0, in P
  double tau0 = 0;     ///< preload torque at theta = 0, N m
  double k_theta = 0;  ///< N m/rad: tau = tau0 - k_theta theta
  double c_theta = 0;  ///< viscous damping, N m s/rad
  std::optional<joint::HingeLockSpec> lock;  ///< the lock at the deployed angle (absent: free swing)
  body::RigidInertia body;  ///< the child body (panel, fitting, parts), in C (origin on the axis)
};

class HingeChain final : public integrate::SecondOrderSystem {
 public:
  /// Throws std::invalid_argument naming the parameter (`hinges`, `hinges[k].axis`, ...).
  HingeChain(BaseSpec base, std::vector<ChainHingeSpec> hinges);

  int num_hinges() const { return static_cast<int>(hinges_.size()); }
  bool base_free() const { return base_.free; }
  int num_positions() const override { return nq_; }
  int num_velocities() const override { return nv_; }
  Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const override {
    return retract_with_base(base_.free, q, dq);
  }
  Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                           double t) const override;
  /// c_a M (exact) + c_v dr/dv + c_q dr/dq (central differences of r, dr/dq along retract()); a
  /// dense matrix, all border (no elastic block).
  integrate::BlockMatrix iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                          const Eigen::VectorXd& a, double t, double c_a, double c_v,
                                          double c_q) const override;
  /// M(q), (nv x nv).
  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) const;

  /// A free base conserves [P_W; H_W]: total linear momentum and angular momentum about W's origin.
  int num_conserved() const override { return base_.free ? 6 : 0; }
  Eigen::VectorXd momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const override;
  /// c_v dPi/dv (exact: Pi = A(q) v) + c_q dPi/dq (central differences along retract()).
  Eigen::MatrixXd momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v,
                                    double c_q) const override;

  /// The locks' event functions, two per locked hinge in hinge order (joint::lock_events).
  Eigen::VectorXd gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const override;
  void accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const override;
  void reset_history() const override;
  /// Held for the whole of a run: the locks' histories are per run (see HingedSystem::run_mutex).
  std::mutex& run_mutex() const { return run_mutex_; }

  /// The stowed configuration: base at rest at W's origin (identity attitude), every theta = 0.
  Eigen::VectorXd initial_positions() const;

  struct Outputs {
    Eigen::VectorXd theta, theta_rate, spring_torque;  ///< per hinge: rad, rad/s, N m
    Eigen::VectorXd lock_force, lock_torque;           ///< per hinge: N (normal, both walls), N m
    Eigen::VectorXd latched;                           ///< per hinge: 1 once its lock has latched
    Eigen::Vector3d P_W, H_W;            ///< total linear (N s), angular momentum about W's origin (N m s)
    Eigen::Vector3d P_base_W, H_base_W;  ///< the base's share
    double kinetic = 0, potential = 0;   ///< J (potential: the hinge springs)
  };
  Outputs outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const;

  /// Body frames in W (for drawing): R_WC_k (3 x 3N, side by side) and C_k's origins (3 x N), m.
  std::pair<Eigen::MatrixXd, Eigen::MatrixXd> frames(const Eigen::VectorXd& q) const;

 private:
  struct Kin;
  Kin kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a) const;
  // The body Jacobians: (V_b; w_b) = J_b v in body axes; index 0 the base (free only), then the links.
  std::vector<Eigen::MatrixXd> jacobians(const Kin& k) const;
  // A(q): Pi = A v.
  Eigen::MatrixXd momentum_matrix(const Kin& k) const;

  BaseSpec base_;
  std::vector<ChainHingeSpec> hinges_;
  mutable std::vector<joint::LockHistory> lock_history_;  // one per hinge; a run's data (accept())
  mutable std::mutex run_mutex_;
  int nq_ = 0, nv_ = 0, iq_theta_ = 0, iv_theta_ = 0;
};

}  // namespace deployfx::system
