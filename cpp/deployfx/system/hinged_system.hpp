#pragma once
// A spacecraft body (free-floating or fixed), one revolute spring hinge and one appendage in the
// hinge-rotating floating frame E: rigid, or flexible with linear or nonlinear (You et al. 2016
// Eq. 14) strain. Equations by virtual power over body-level inertial forces (docs/engine-design.md):
//   r = sum_b J_b^T f_b(q, v, vdot) - tau(q, v, t) = 0.
//
// Coordinates, in this order, each block present only when the scene needs it:
//   q = [r_W (3), quaternion of R_WB (w, x, y, z)] [theta] [d (free elastic dofs)]
//   v = [v_W (3), w_B (3)]                          [theta'] [d']
// B's origin is the base's reference point (its centroid, say; the centre of mass may be offset,
// e.g. by a yoke fixed to the base). theta is the hinge travel from the stowed position (rad); a
// driven hinge has no coordinate: theta(t) is prescribed. The border of the Newton matrix is the
// rigid block [base, theta]; the elastic block is sparse. The Newton matrix and the momentum
// Jacobian are analytic (hinged_system_jacobians.cpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/body/rigid_inertia.hpp"
#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/joint/hinge_lock.hpp"

namespace deployfx::system {

/// The appendage's model and description (body/flexible_body.hpp), under their historical names.
using body::AppendageSpec;
using body::Fidelity;

struct BaseSpec {
  bool free = true;
  body::RigidInertia inertia;  ///< in B (everything rigidly fixed to the base: body, yoke)
};

/// Prescribed hinge travel of Kane, Ryan & Banerjee (1987): rate
/// Omega(t) = (Omega_s/T_s)[t - (T_s/2 pi) sin(2 pi t/T_s)] for t <= T_s, then Omega_s.
struct SpinUpDriver {
  double omega_s = 0;  ///< rad/s
  double t_s = 1;      ///< s
  void evaluate(double t, double* theta, double* rate, double* accel) const;
};

struct HingeSpec {
  Eigen::Vector3d point_B = Eigen::Vector3d::Zero();  ///< a point of the axis and E's origin, m
  Eigen::Vector3d axis_B = Eigen::Vector3d::UnitY();  ///< unit axis, B axes
  Eigen::Matrix3d R_BE0 = Eigen::Matrix3d::Identity();  ///< E's axes at theta = 0
  double tau0 = 0;      ///< preload torque at theta = 0, N m
  double k_theta = 0;   ///< N m/rad: tau = tau0 - k_theta theta
  double c_theta = 0;   ///< viscous damping, N m s/rad
  bool driven = false;  ///< theta(t) from `driver` instead of a coordinate
  SpinUpDriver driver;
  /// The hinge fitting: the rigid part that turns with E and carries the appendage's root (the
  /// spring, damper and lock act on it), in E. Without it the spring's preload acts on a massless
  /// frame and drives a stiff, mesh-dependent root mode (docs/engine-design.md).
  body::RigidInertia fitting;
  /// The lock at the deployed angle (absent: the hinge swings freely).
  std::optional<joint::HingeLockSpec> lock;
};

class HingedSystem final : public integrate::SecondOrderSystem {
 public:
  HingedSystem(BaseSpec base, HingeSpec hinge, AppendageSpec appendage);

  int num_positions() const override { return nq_; }
  int num_velocities() const override { return nv_; }
  int num_elastic() const { return app_->num_elastic(); }
  /// The reduced model's basis (all mesh dofs x elastic coordinates; empty for a full model):
  /// mesh displacements d = basis() eta.
  const fem::RitzBasis& basis() const { return app_->basis(); }
  Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const override;
  Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& a, double t) const override;
  integrate::BlockMatrix iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                          const Eigen::VectorXd& a, double t, double c_a,
                                          double c_v, double c_q) const override;
  /// A free base conserves [P_W; H_W] (total linear momentum, angular momentum about W's origin)
  /// unless a driver prescribes theta(t) (then Pi would depend on t).
  int num_conserved() const override { return base_.free && !hinge_.driven ? 6 : 0; }
  Eigen::VectorXd momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const override;
  Eigen::MatrixXd momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v,
                                    double c_q) const override;

  /// The lock's event functions (joint::lock_events); empty without a lock or for a driven hinge.
  Eigen::VectorXd gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const override;
  void accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const override;
  void reset_history() const override { lock_history_ = {}; }
  /// The lock's limit on the hinge rate's change across its friction band
  /// (joint::friction_step_limit), as for every hinge of a HingeChain.
  double newton_step_limit(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& dv) const override;
  /// Held for the whole of a run: the lock's history is per run, so concurrent runs on one
  /// system (threads in a parameter sweep) take turns instead of corrupting each other.
  std::mutex& run_mutex() const { return run_mutex_; }

  /// The initial configuration: base at rest at the origin, theta = 0, d = 0.
  Eigen::VectorXd initial_positions() const;

  struct Outputs {
    double theta = 0, theta_rate = 0, spring_torque = 0;  // rad, rad/s, N m
    Eigen::Vector3d P_W, H_W;       // total linear (N s) and angular momentum about W's origin (N m s)
    Eigen::Vector3d H_base_W;       // the base's angular momentum about W's origin
    Eigen::Vector3d P_base_W;       // the base's linear momentum (the appendage's: P_W - P_base_W)
    double kinetic = 0, potential = 0;  // J (spring + strain energy)
    double lock_force = 0, lock_torque = 0;  // N (normal, both walls), N m (on theta)
  };
  Outputs outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) const;

 private:
  // Kinematics at one instant.
  struct Kin {
    Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity(), R_BE, R_WE;
    Eigen::Vector3d r_W = Eigen::Vector3d::Zero(), v_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d w_B = Eigen::Vector3d::Zero(), a_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d wd_B = Eigen::Vector3d::Zero();
    Eigen::Vector3d V_B = Eigen::Vector3d::Zero(), a_B = Eigen::Vector3d::Zero();  // B's origin, B axes
    double theta = 0, rate = 0, accel = 0;
    Eigen::Vector3d V_E, w_E, a_E, al_E;  // E's origin velocity/acceleration and rates, E axes
    // On inertia()'s dofs (FlexibleBody::full); empty if rigid, ddd also without accelerations.
    Eigen::VectorXd d, dd, ddd;
  };
  Kin kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd* a,
                 double t) const;
  // r without the elastic internal force (which depends on d only).
  Eigen::VectorXd inertial_residual(const Kin& k, const Eigen::VectorXd& q) const;
  // E's momentum (appendage and fitting) about E's origin, E axes: (p_E, h_E).
  Eigen::Matrix<double, 6, 1> frame_momentum(const Kin& k) const;
  struct Momenta { Eigen::Vector3d P_W, H_W, H_base_W, P_base_W; };
  Momenta momenta(const Kin& k) const;
  // The Newton matrix's and the momentum Jacobian's analytic pieces (hinged_system_jacobians.cpp).
  // (V_E, w_E) = Jr v_border and (a_E, al_E) = Jr a_border + (terms in v), (6 x nb).
  Eigen::Matrix<double, 6, Eigen::Dynamic> frame_velocity_map(const Kin& k) const;
  // c_a d/da + c_v d/dv + c_q d/dq (along retract()) of E's motion (a_E, al_E, w_E), (9 x nb).
  Eigen::Matrix<double, 9, Eigen::Dynamic> frame_motion_jacobian(const Kin& k, double c_a, double c_v,
                                                                 double c_q) const;
  // The lock torque's c_q d/dtheta + c_v d/dtheta' (central differences of a scalar law).
  double lock_stiffness(const Kin& k, double c_v, double c_q) const;

  BaseSpec base_;
  HingeSpec hinge_;
  // The appendage, compiled (shape integrals, basis, elastic force; body/flexible_body.hpp).
  std::optional<body::FlexibleBody> app_;
  const body::FloatingFrameInertia& ffi() const { return app_->inertia(); }
  // Everything rigid in E: the fitting, plus the appendage itself when its fidelity is rigid
  // (then the shape integrals are constant and ffi() is not evaluated per step).
  body::RigidInertia frame_rigid_;
  bool flexible_ = false;
  bool green_ = false;  // Green strain (full or reduced)
  // The lock's memory (latch, contact onsets): a run's data, changed only by accept(). One run
  // at a time per system: runs hold run_mutex() (see the bindings).
  mutable joint::LockHistory lock_history_;
  mutable std::mutex run_mutex_;
  int nq_ = 0, nv_ = 0;
  int iq_theta_ = -1, iv_theta_ = -1, iq_d_ = -1, iv_d_ = -1;  // block offsets (-1: absent)
};

}  // namespace deployfx::system
