#pragma once
// Forward kinematics of the tree, written once for any scalar: on doubles for the residual and
// the outputs, on Duals (math/dual.hpp) for the Newton matrix's and the momentum Jacobian's
// columns, which are the same relations differentiated along one coordinate.
//
// Parent P to child C over hinge k (docs/engine-design.md, "One engine for a tree"), with the
// hinge point o, the axis n, and for a hinge on a panel the attachment's motion relative to P
// (multibody/attachment.hpp; o = point, n = axis and the rest zero on a rigid parent), all in P:
//   R_PC = R_att Rot(axis, theta) R_PC0,   n = R_att axis,   w_rel = w_att + theta' n,
//   V_C  = R_CP (V_P + w_P x o + o'),
//   a_C  = R_CP (a_P + al_P x o + w_P x (w_P x o) + 2 w_P x o' + o''),
//   w_C  = R_CP (w_P + w_rel),
//   al_C = R_CP (al_P + al_att + theta'' n + theta' w_att x n + w_P x w_rel),
// (V, a: the frame origin's velocity and acceleration; w, al: angular velocity and acceleration;
// each body's own axes), and R_WC = R_WP R_PC, o_W = o_WP + R_WP o.
#include <Eigen/Core>
#include <vector>

#include "deployfx/math/so3.hpp"
#include "deployfx/multibody/attachment.hpp"
#include "deployfx/multibody/model.hpp"

namespace deployfx::multibody {

/// The base frame B's motion. A fixed base rests at W's origin with R_WB = I.
template <class S>
struct BaseMotion {
  Matrix3<S> R_WB = Matrix3<S>::Identity();
  Vector3<S> r_W = Vector3<S>::Zero(), v_W = Vector3<S>::Zero(), a_W = Vector3<S>::Zero();  ///< W axes
  Vector3<S> V_B = Vector3<S>::Zero(), a_B = Vector3<S>::Zero();    ///< B's origin, B axes
  Vector3<S> w_B = Vector3<S>::Zero(), wd_B = Vector3<S>::Zero();   ///< rad/s, rad/s^2, B axes
};

/// Hinge k's coordinates: its angle and, on a panel, the attachment's z = P eta_parent.
template <class S>
struct JointState {
  S theta = 0, rate = 0, accel = 0;  ///< rad, rad/s, rad/s^2
  Vector6<S> z = Vector6<S>::Zero(), z_rate = Vector6<S>::Zero(), z_accel = Vector6<S>::Zero();
};

/// Body k's frame C at one instant.
template <class S>
struct BodyMotion {
  Matrix3<S> R_PC;  ///< C's axes in the parent P
  Vector3<S> o, n;  ///< the hinge point (C's origin) and axis, P (deformed on a panel)
  Matrix3<S> R_WC;
  Vector3<S> o_W;   ///< C's origin in W, m
  Vector3<S> V, w, a, al;  ///< C's origin velocity, acceleration; angular velocity, acceleration: C axes
  /// On a panel: the attachment's arm rho = R_att r and T(psi) (P axes; its generalized force).
  Vector3<S> rho = Vector3<S>::Zero();
  Matrix3<S> T = Matrix3<S>::Identity();
};

template <class S>
struct TreeMotion {
  BaseMotion<S> base;
  std::vector<BodyMotion<S>> body;  ///< per hinge k
};

/// B's motion from q, v and a (a may be null: zero accelerations).
BaseMotion<double> base_motion(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                               const Eigen::VectorXd* a);

/// Parent to child over every hinge, parents first (their indices are lower).
template <class S>
void forward_kinematics(const Model& m, const BaseMotion<S>& base, const std::vector<JointState<S>>& joints,
                        TreeMotion<S>& out) {
  out.base = base;
  out.body.resize(static_cast<std::size_t>(m.num_hinges()));
  for (int k = 0; k < m.num_hinges(); ++k) {
    const HingeSpec& h = m.hinge(k);
    const Body& b = m.body(k);
    const JointState<S>& J = joints[static_cast<std::size_t>(k)];
    BodyMotion<S>& C = out.body[static_cast<std::size_t>(k)];
    const bool on_base = b.parent < 0;
    const BodyMotion<S>* P = on_base ? nullptr : &out.body[static_cast<std::size_t>(b.parent)];
    const Matrix3<S>& R_WP = on_base ? base.R_WB : P->R_WC;
    const Vector3<S>& o_WP = on_base ? base.r_W : P->o_W;
    const Vector3<S>& V = on_base ? base.V_B : P->V;
    const Vector3<S>& w = on_base ? base.w_B : P->w;
    const Vector3<S>& acc = on_base ? base.a_B : P->a;
    const Vector3<S>& al = on_base ? base.wd_B : P->al;

    Matrix3<S> R_att = Matrix3<S>::Identity();
    Vector3<S> o_rate = Vector3<S>::Zero(), o_acc = Vector3<S>::Zero();
    Vector3<S> w_att = Vector3<S>::Zero(), al_att = Vector3<S>::Zero();
    if (b.attachment) {
      const AttachmentMotion<S> am = attachment_motion<S>(*b.attachment, J.z, J.z_rate, J.z_accel);
      R_att = am.R_att, C.o = am.o, o_rate = am.o_rate, o_acc = am.o_accel, w_att = am.w_att, al_att = am.al_att;
      C.rho = am.rho;
      C.T = am.T;
    } else {
      C.o = h.point.cast<S>();
    }
    const Vector3<S>& o = C.o;
    C.n = R_att * h.axis.cast<S>();
    const Vector3<S>& n = C.n;
    const Matrix3<S> R_rel = times_constant<S>(rotation_about<S>(b.axis_skew, b.axis_skew2, J.theta), h.R_PC0);
    C.R_PC = b.attachment ? Matrix3<S>(R_att * R_rel) : R_rel;
    const Matrix3<S> R_CP = C.R_PC.transpose();
    const Vector3<S> w_rel = w_att + J.rate * n;
    C.R_WC = R_WP * C.R_PC;
    C.o_W = o_WP + R_WP * o;
    C.V = R_CP * (V + w.cross(o) + o_rate);
    C.a = R_CP * (acc + al.cross(o) + w.cross(w.cross(o)) + 2.0 * w.cross(o_rate) + o_acc);
    C.w = R_CP * (w + w_rel);
    C.al = R_CP * (al + al_att + J.accel * n + J.rate * w_att.cross(n) + w.cross(w_rel));
  }
}

/// The subtree wrenches of a backward pass (Featherstone, "Rigid Body Dynamics Algorithms",
/// 2008, Sec. 5.3): body k's inertial wrench f_k (force; moment about C's origin; C axes) plus its
/// children's, carried into the parent about its origin,
///   F_P = R_PC F,   M_P = o x F_P + R_PC M.
template <class S>
struct Wrenches {
  Vector6<S> root = Vector6<S>::Zero();  ///< the base's hinges' subtrees, about B's origin, B axes
  std::vector<S> hinge;                  ///< per hinge: n . (R_PC M) (the subtree's moment about the axis)
  std::vector<Vector6<S>> attach;        ///< per hinge on a panel: the generalized force on z, [F_P; T^T (rho x F_P + M_P)]
  std::vector<Vector6<S>> subtree;       ///< per hinge: its subtree's wrench about C's origin, C axes
};

template <class S>
void backward_pass(const Model& m, const TreeMotion<S>& motion, const std::vector<Vector6<S>>& f, Wrenches<S>& out) {
  const int N = m.num_hinges();
  out.root.setZero();
  out.hinge.assign(static_cast<std::size_t>(N), S(0.0));
  out.attach.assign(static_cast<std::size_t>(N), Vector6<S>::Zero());
  out.subtree.assign(f.begin(), f.end());  // accumulated in place, children (higher indices) first
  std::vector<Vector6<S>>& W_all = out.subtree;
  for (int k = N - 1; k >= 0; --k) {
    const BodyMotion<S>& C = motion.body[static_cast<std::size_t>(k)];
    const Vector6<S>& W = W_all[static_cast<std::size_t>(k)];
    const Vector3<S> F_P = C.R_PC * W.template head<3>(), M_P = C.R_PC * W.template tail<3>();
    out.hinge[static_cast<std::size_t>(k)] = C.n.dot(M_P);
    if (m.body(k).attachment) {
      Vector6<S>& tz = out.attach[static_cast<std::size_t>(k)];
      tz.template head<3>() = F_P;
      tz.template tail<3>() = C.T.transpose() * (C.rho.cross(F_P) + M_P);
    }
    const int p = m.body(k).parent;
    Vector6<S>& into = p < 0 ? out.root : W_all[static_cast<std::size_t>(p)];
    into.template head<3>() += F_P;
    into.template tail<3>() += C.o.cross(F_P) + M_P;
  }
}

}  // namespace deployfx::multibody
