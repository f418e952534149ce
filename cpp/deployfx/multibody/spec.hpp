#pragma once
// The description of a scene, as the user builds it: a base (free-floating or fixed) and a tree
// of bodies on revolute hinges. Hinge k carries body k; its parent is the base or the body of an
// earlier hinge, rigid or a deforming panel (then the hinge rides on the panel's mesh:
// multibody/attachment.hpp). Plain data, checked and compiled by multibody::Model.
//
// Frames (docs/notation.md): W world, B the base, C_k body k's frame. C_k's origin lies on hinge
// k's axis; in its parent P (B, or C_parent), R_PC(theta) = Rot(axis, theta) R_PC0 (on a rigid
// parent), theta the hinge travel from the stowed position (rad).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "deployfx/body/flexible_body.hpp"
#include "deployfx/body/rigid_inertia.hpp"
#include "deployfx/joint/lock.hpp"

namespace deployfx::multibody {

using body::AppendageSpec;
using body::Fidelity;
using body::RigidInertia;

struct BaseSpec {
  bool free = true;      ///< false: fixed to W (no coordinates; the inertia is then unused)
  RigidInertia inertia;  ///< in B: everything rigidly fixed to the base (body, a fixed yoke)
};

/// Prescribed hinge travel of Kane, Ryan & Banerjee (1987): rate
/// Omega(t) = (Omega_s/T_s)[t - (T_s/2 pi) sin(2 pi t/T_s)] for t <= T_s, then Omega_s.
struct SpinUpDriver {
  double omega_s = 0;  ///< rad/s
  double t_s = 1;      ///< s
  /// theta(t) (rad), its rate (rad/s) and acceleration (rad/s^2).
  void evaluate(double t, double* theta, double* rate, double* accel) const;
};

struct HingeSpec {
  int parent = -1;  ///< -1: the base; k: the body of hinge k (an earlier hinge)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      ///< a point of the axis and C's origin, m, P
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();      ///< unit axis, P axes
  Eigen::Matrix3d R_PC0 = Eigen::Matrix3d::Identity();  ///< C's axes at theta = 0, in P
  double tau0 = 0;     ///< spring preload at theta = 0, N m: tau = tau0 - k_theta theta
  double k_theta = 0;  ///< N m/rad
  double c_theta = 0;  ///< viscous damping, N m s/rad
  /// theta(t) prescribed (no coordinate) instead of the spring's dynamics.
  std::optional<SpinUpDriver> driver;
  /// The lock at the deployed angle, stop-and-latch walls or a pin in a groove (joint/lock.hpp;
  /// absent: the hinge swings freely).
  std::optional<joint::LockSpec> lock;
  /// The rigid parts turning with C, in C: the hinge fitting the spring, damper and lock act on,
  /// a yoke, brackets. Without a fitting the preload acts on a massless frame and drives a stiff,
  /// mesh-dependent root mode of a flexible panel (docs/engine-design.md).
  RigidInertia body;
  /// A panel in C (nodes in C, m; its root clamped to C), of any fidelity, or none.
  std::optional<AppendageSpec> panel;
};

struct TreeSpec {
  BaseSpec base;
  std::vector<HingeSpec> hinges;
};

}  // namespace deployfx::multibody
