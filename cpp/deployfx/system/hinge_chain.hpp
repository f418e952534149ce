#pragma once
// A base (free-floating or fixed) carrying a serial chain of N >= 1 bodies on revolute spring
// hinges (issue 5: a yoke and panels, as on solar arrays): hinge 0 is on the base, hinge k on body
// k-1, and body k turns with its frame C_k, whose origin lies on hinge k's axis. Body k is rigid,
// or a flexible panel described in C_k as its floating frame E_k (root edge clamped to it, as in
// HingedSystem; fidelities linear, nonlinear, reduced-linear, reduced-nonlinear:
// body/flexible_body.hpp) together with the rigid parts turning with C_k (fitting, parts).
// A hinge on a rigid parent P is fixed in P:
//   R_PC_k(theta_k) = Rot(axis_k, theta_k) R_PC0_k,   p_PoCo_P = point_k;
// a hinge on a flexible parent rides on the parent's deforming mesh, bolted to the node nearest
// point_k and rigid from there to point_k (system/chain_attachment.hpp, docs/research/flexible-chain.md):
//   R_PC_k = R_att Rot(axis_k, theta_k) R_PC0_k,   p_PoCo_P = X + u + R_att (point_k - X),
// with the node's undeformed position X, elastic translation u and rotation R_att = exp(psi~).
// Each hinge has a spring tau0 - k_theta theta, a viscous damper and optionally a lock
// (joint/hinge_lock.hpp, with its own history).
//
// Coordinates (minimal, tree-structured; docs/engine-design.md "Coordinates"), in this order, each
// block present only when the scene needs it:
//   q = [r_W (3), quaternion of R_WB (w, x, y, z)] [theta_0 .. theta_N-1] [d_0] [d_1] .. [d_N-1]
//   v = [v_W (3, W axes), w_B (3, B axes)]         [theta'_0 .. theta'_N-1] [d'_0] .. [d'_N-1]
// with d_k body k's elastic coordinates (its free mesh dofs, m and rad, or its Ritz coordinates
// for a reduced body; absent for a rigid body) in hinge order: a chain of one hinge has
// HingedSystem's coordinates.
// Equations by virtual power over all bodies (docs/engine-design.md "System assembly"):
//   r = sum_b J_b^T f_b(q, v, vdot) - tau(q, v, t) + (f_int + Rayleigh damping on each d_k) = 0,
// f_b the inertial forces of body b about its origin: Newton-Euler for the rigid parts
// (body::RigidInertia) and the floating-frame forces (F, M, Q) of a flexible panel
// (body::FloatingFrameInertia, docs/engine-design.md "Body-level equations"), evaluated by a
// forward pass of the body motions and a backward pass of the wrenches (a recursive Newton-Euler,
// Featherstone, "Rigid Body Dynamics Algorithms", 2008, Sec. 5.3, with the elastic coordinates of
// Shabana, "Dynamics of Multibody Systems", 4th ed., 2013, Ch. 5); the mass matrix
// sum_b J_b^T M_b J_b from the body Jacobians J_b (twists in body axes and elastic rates).
#include <Eigen/Core>
#include <mutex>
#include <optional>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/body/rigid_inertia.hpp"
#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/joint/hinge_lock.hpp"
#include "deployfx/system/base_frame.hpp"
#include "deployfx/system/chain_attachment.hpp"
#include "deployfx/system/hinged_system.hpp"  // BaseSpec

namespace deployfx::system {

/// Hinge k of a chain and the body it carries. P is the parent's frame (B for hinge 0, else
/// C_{k-1}); C the child's.
struct ChainHingeSpec {
  Eigen::Vector3d point_P = Eigen::Vector3d::Zero();    ///< a point of the axis and C's origin, m, P axes
  Eigen::Vector3d axis_P = Eigen::Vector3d::UnitY();    ///< unit axis, P axes
  Eigen::Matrix3d R_PC0 = Eigen::Matrix3d::Identity();  ///< C's axes at theta = 0, in P
  double tau0 = 0;     ///< preload torque at theta = 0, N m
  double k_theta = 0;  ///< N m/rad: tau = tau0 - k_theta theta
  double c_theta = 0;  ///< viscous damping, N m s/rad
  std::optional<joint::HingeLockSpec> lock;  ///< the lock at the deployed angle (absent: free swing)
  body::RigidInertia body;  ///< the child's rigid parts (fitting, parts, rigid panel), in C (origin on the axis)
  /// A panel in C (nodes in C, m), flexible or rigid (then merged into `body`), or none.
  std::optional<body::AppendageSpec> appendage;
};

class HingeChain final : public integrate::SecondOrderSystem {
 public:
  /// Throws std::invalid_argument naming the parameter (`hinges`, `hinges[k].axis`,
  /// `hinges[k].appendage.modes`, ...).
  HingeChain(BaseSpec base, std::vector<ChainHingeSpec> hinges);

  int num_hinges() const { return static_cast<int>(hinges_.size()); }
  /// Body k's elastic coordinates: how many, and where its block starts in q (and in v: the
  /// same offset minus 1 for a free base's quaternion); 0 and -1 for a rigid body.
  int num_elastic(int k) const { return links_.at(k).n_d; }
  int elastic_position(int k) const { return links_.at(k).iq_d; }
  /// Body k's compiled panel (null for a rigid body).
  const body::FlexibleBody* flexible_body(int k) const {
    return links_.at(k).flex ? &*links_.at(k).flex : nullptr;
  }
  /// Hinge k's attachment to its flexible parent (null on the base or a rigid parent).
  const ChainAttachment* attachment(int k) const {
    return links_.at(k).attach ? &*links_.at(k).attach : nullptr;
  }
  bool base_free() const { return base_.free; }
  int num_positions() const override { return nq_; }
  int num_velocities() const override { return nv_; }
  Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const override {
    return retract_with_base(base_.free, q, dq);
  }
  Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                           double t) const override;
  /// c_a M (exact) + c_v dr/dv + c_q dr/dq: the inertial and hinge forces' by central
  /// differences (dr/dq along retract()), each panel's elastic force's analytic
  /// (FlexibleBody::elastic_tangent); a dense matrix, all border (no sparse elastic block).
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

  /// The smallest of the locks' limits (joint::friction_step_limit) on the hinge rates' changes
  /// (HingedSystem applies the same to its one lock).
  double newton_step_limit(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& dv) const override;

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
    Eigen::VectorXd strain_energy;                     ///< per hinge: its panel's, J (0 if rigid)
    Eigen::Vector3d P_W, H_W;            ///< total linear (N s), angular momentum about W's origin (N m s)
    Eigen::Vector3d P_base_W, H_base_W;  ///< the base's share
    double kinetic = 0, potential = 0;   ///< J (potential: the hinge springs and the strain energy)
  };
  Outputs outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const;

  /// Body frames in W (for drawing): R_WC_k (3 x 3N, side by side) and C_k's origins (3 x N), m;
  /// on a flexible parent they ride on its deformed mesh.
  std::pair<Eigen::MatrixXd, Eigen::MatrixXd> frames(const Eigen::VectorXd& q) const;

 private:
  struct Kin;
  Kin kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a) const;
  // r without the panels' internal forces and Rayleigh damping (which depend on their own d, d').
  Eigen::VectorXd inertial_residual(const Kin& k) const;
  // The body Jacobians: (V_b; w_b) = J_b v in body axes; index 0 the base (zero for a fixed base),
  // then the links.
  std::vector<Eigen::MatrixXd> jacobians(const Kin& k) const;
  // Link c's generalized inertia about C's origin on (V, w, d'): M_c (6 + n_d square; the
  // floating-frame mass matrix of a flexible panel, from the integrals of its kinetic energy), and
  // its Jacobian (J_b stacked on the selection of d'_c).
  Eigen::MatrixXd link_inertia(const Kin& k, int c) const;
  Eigen::MatrixXd link_jacobian(const Eigen::MatrixXd& J, int c) const;
  // A(q): Pi = A v.
  Eigen::MatrixXd momentum_matrix(const Kin& k) const;

  // The compiled body of each hinge (immutable).
  struct Link {
    body::RigidInertia rigid;                // everything rigid in C
    std::optional<body::FlexibleBody> flex;  // a flexible panel in C
    std::optional<ChainAttachment> attach;   // the hinge on a flexible parent
    int n_d = 0, iq_d = -1, iv_d = -1;       // its elastic block (absent: 0, -1)
  };

  BaseSpec base_;
  std::vector<ChainHingeSpec> hinges_;
  std::vector<Link> links_;
  mutable std::vector<joint::LockHistory> lock_history_;  // one per hinge; a run's data (accept())
  mutable std::mutex run_mutex_;
  int nq_ = 0, nv_ = 0, iq_theta_ = 0, iv_theta_ = 0;
};

}  // namespace deployfx::system
