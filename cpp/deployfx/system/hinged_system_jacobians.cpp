// HingedSystem's Newton iteration matrix and momentum Jacobian, analytic: the derivatives of the
// equations of docs/engine-design.md ("Body-level equations", "System assembly").
//
// The residual's rows project E's body-level inertial forces (F, M, Q)(a_E, al_E, w_E, d, d', d'')
// (FloatingFrameInertia::inertial_force_jacobians; the fitting's by body/rigid_force_jacobian.hpp)
// and the base's Newton-Euler forces; so a border column (base or hinge coordinate) is
//   d(F, M, Q)/d(a_E, al_E, w_E) times the column of d(a_E, al_E, w_E)/d(border)
// (frame_motion_jacobian()), plus the derivatives of the projections R_WB, R_BE themselves.
// The lock's torque, a scalar law of (theta, theta'), is differenced centrally.
//
// Border perturbations (along retract()): the base rotation R_WB -> R_WB exp(dphi~) (body axes),
// so a B-axes vector x_B = R_WB^T x_W changes by x_B x dphi and R_WB y by -R_WB y~ dphi; the
// hinge angle theta -> theta + dtheta turns R_BE about the axis, so an E-axes vector
// x_E = R_EB x_B changes by x_E x axis_E dtheta (axis_E = R_EB axis) and R_BE y by
// axis x (R_BE y). r_W and v_W enter no inertial force; the momentum is linear in v.
//
// Checked against central differences of residual() and momentum() for every fidelity
// (tests/test_iteration_matrix.py).
#include <algorithm>
#include <cmath>

#include "deployfx/body/rigid_force_jacobian.hpp"
#include "deployfx/math/so3.hpp"
#include "deployfx/system/hinged_system.hpp"

namespace deployfx::system {

Eigen::Matrix<double, 6, Eigen::Dynamic> HingedSystem::frame_velocity_map(const Kin& k) const {
  // V_E = R_EB (R_WB^T v_W + w_B x p), w_E = R_EB (w_B + theta' axis).
  const int nb = nv_ - num_elastic();
  const Eigen::Matrix3d R_EB = k.R_BE.transpose();
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jr = Eigen::MatrixXd::Zero(6, nb);
  if (base_.free) {
    Jr.block<3, 3>(0, 0) = R_EB * k.R_WB.transpose();
    Jr.block<3, 3>(0, 3) = -R_EB * skew(hinge_.point_B);
    Jr.block<3, 3>(3, 3) = R_EB;
  }
  if (iv_theta_ >= 0) Jr.block<3, 1>(3, iv_theta_) = R_EB * hinge_.axis_B;
  return Jr;
}

Eigen::Matrix<double, 9, Eigen::Dynamic> HingedSystem::frame_motion_jacobian(const Kin& k, double c_a, double c_v,
                                                                             double c_q) const {
  // a_E = R_EB (a_B + w_B' x p + w_B x (w_B x p)), a_B = R_WB^T a_W;
  // al_E = R_EB (w_B' + theta'' axis + theta' w_B x axis); w_E = R_EB (w_B + theta' axis).
  const int nb = nv_ - num_elastic();
  const Eigen::Matrix3d R_EB = k.R_BE.transpose(), I3 = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d& p = hinge_.point_B;
  const Eigen::Vector3d& ax = hinge_.axis_B;
  Eigen::Matrix<double, 9, Eigen::Dynamic> D = Eigen::MatrixXd::Zero(9, nb);
  D.topRows<6>() = c_a * frame_velocity_map(k);  // the accelerations enter as the velocities do
  if (base_.free) {
    const Eigen::Vector3d& w = k.w_B;
    D.block<3, 3>(0, 3) += c_v * R_EB * (w.dot(p) * I3 + w * p.transpose() - 2.0 * p * w.transpose()) +
                           c_q * R_EB * skew(k.a_B);
    D.block<3, 3>(3, 3) -= c_v * k.rate * R_EB * skew(ax);
    D.block<3, 3>(6, 3) += c_v * R_EB;
  }
  if (iv_theta_ >= 0) {
    const Eigen::Vector3d axE = R_EB * ax;
    D.block<3, 1>(0, iv_theta_) += c_q * k.a_E.cross(axE);
    D.block<3, 1>(3, iv_theta_) += c_v * R_EB * k.w_B.cross(ax) + c_q * k.al_E.cross(axE);
    D.block<3, 1>(6, iv_theta_) += c_v * axE + c_q * k.w_E.cross(axE);
  }
  return D;
}

double HingedSystem::lock_stiffness(const Kin& k, double c_v, double c_q) const {
  if (!hinge_.lock || iv_theta_ < 0) return 0.0;
  auto torque = [&](double theta, double rate) {
    return joint::lock_load(*hinge_.lock, lock_history_, theta, rate).torque;
  };
  const double hq = 1e-7 * std::max(1.0, std::abs(k.theta)), hv = 1e-7 * std::max(1.0, std::abs(k.rate));
  double out = 0;
  if (c_q != 0) out += c_q * (torque(k.theta + hq, k.rate) - torque(k.theta - hq, k.rate)) / (2 * hq);
  if (c_v != 0) out += c_v * (torque(k.theta, k.rate + hv) - torque(k.theta, k.rate - hv)) / (2 * hv);
  return out;
}

integrate::BlockMatrix HingedSystem::iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                      const Eigen::VectorXd& a, double t, double c_a,
                                                      double c_v, double c_q) const {
  const Kin k = kinematics(q, v, &a, t);
  const int nf = num_elastic(), nb = nv_ - nf;
  integrate::BlockMatrix S;
  S.A = Eigen::MatrixXd::Zero(nb, nb);
  S.B = Eigen::MatrixXd::Zero(nb, nf);
  S.C = Eigen::MatrixXd::Zero(nf, nb);

  // E's inertial forces (appendage and fitting, E axes, about E's origin) and their derivatives
  // with respect to (a_E, al_E, w_E).
  Eigen::Matrix<double, 6, 9> G = body::rigid_force_jacobian(frame_rigid_, k.w_E);
  Eigen::Matrix<double, 6, 1> fE = frame_rigid_.inertial_forces(k.a_E, k.al_E, k.w_E);
  body::FloatingFrameInertia::ForceJacobians fj;
  if (flexible_) {
    fj = ffi().inertial_force_jacobians(k.a_E, k.al_E, k.w_E, k.d, k.dd, k.ddd);
    G += fj.FM_k;
    fE.head<3>() += fj.f.F;
    fE.tail<3>() += fj.f.M;
  }

  // Border columns. The rows project E's forces as inertial_residual() does:
  //   base: R_WB (f_b + F_B), f_b' + p x F_B + M_B;  hinge: axis . M_B;  elastic: Q,
  // with F_B = R_BE F, M_B = R_BE M.
  const Eigen::Matrix<double, 9, Eigen::Dynamic> D = frame_motion_jacobian(k, c_a, c_v, c_q);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> dfE = G * D;
  const Eigen::Vector3d& p = hinge_.point_B;
  const Eigen::Vector3d& ax = hinge_.axis_B;
  const Eigen::Vector3d F_B = k.R_BE * fE.head<3>(), M_B = k.R_BE * fE.tail<3>();
  Eigen::Matrix<double, 3, Eigen::Dynamic> dF_B = k.R_BE * dfE.topRows<3>(), dM_B = k.R_BE * dfE.bottomRows<3>();
  if (iv_theta_ >= 0) {
    dF_B.col(iv_theta_) += c_q * ax.cross(F_B);
    dM_B.col(iv_theta_) += c_q * ax.cross(M_B);
  }
  if (base_.free) {
    // The base's Newton-Euler forces in B at (a_B, w_B', w_B), a_B = R_WB^T a_W.
    const body::RigidInertia& b = base_.inertia;
    const auto fb = b.inertial_forces(k.a_B, k.wd_B, k.w_B);
    const Eigen::Matrix<double, 6, 9> Gb = body::rigid_force_jacobian(b, k.w_B);
    Eigen::Matrix<double, 9, 6> Db = Eigen::Matrix<double, 9, 6>::Zero();  // d(a_B, w_B', w_B)/d(base)
    Db.block<3, 3>(0, 0) = c_a * k.R_WB.transpose();
    Db.block<3, 3>(0, 3) = c_q * skew(k.a_B);
    Db.block<3, 3>(3, 3) = c_a * Eigen::Matrix3d::Identity();
    Db.block<3, 3>(6, 3) = c_v * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 6, 6> dfb = Gb * Db;
    S.A.topRows<3>() = k.R_WB * dF_B;
    S.A.topLeftCorner<3, 6>() += k.R_WB * dfb.topRows<3>();
    S.A.block<3, 3>(0, 3) -= c_q * k.R_WB * skew(fb.head<3>() + F_B);
    S.A.middleRows<3>(3) = skew(p) * dF_B + dM_B;
    S.A.block<3, 6>(3, 0) += dfb.bottomRows<3>();
  }
  if (iv_theta_ >= 0) {
    S.A.row(iv_theta_) = ax.transpose() * dM_B;
    S.A(iv_theta_, iv_theta_) += c_q * hinge_.k_theta + c_v * hinge_.c_theta - lock_stiffness(k, c_v, c_q);
  }
  if (iv_d_ < 0) {
    S.E.resize(0, 0);
    return S;
  }
  const std::vector<int>& free = app_->free_dofs();
  for (int i = 0; i < nf; ++i) S.C.row(i) = fj.Q_k.row(free[i]) * D;

  // Elastic block: c_a L_c + c_v 2 G_y(w) + c_q (G_y(al) + G_w(w) + K_T), with
  // G_y(x) = sum_i x_j M_ik - x_k M_ij (i, j, k cyclic) and G_w(w) = sum w_i w_l M_il - |w|^2 M_ii.
  // Summed as c_a L_c + sum_im c_im M_im, each M_im over its own nonzeros
  // (FlexibleBody::mass_combination).
  const Eigen::Vector3d& w = k.w_E;
  const Eigen::Vector3d x = 2 * c_v * w + c_q * k.al_E;
  Eigen::Matrix3d c = c_q * (w * w.transpose() - w.squaredNorm() * Eigen::Matrix3d::Identity());
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    c(i, l) += x(j);
    c(i, j) -= x(l);
  }
  Eigen::VectorXd vals = app_->mass_combination(c_a, c);
  app_->add_elastic_block(k.d, c_v, c_q, vals);  // K_T (or K_L) and Rayleigh damping
  S.E = app_->block().with_values(vals);

  // Elastic columns of the border rows: the dd''-, dd'- and d-derivatives of (F, M), projected.
  const Eigen::Matrix<double, 6, Eigen::Dynamic> FMe = c_a * fj.FM_ddd + c_v * fj.FM_dd + c_q * fj.FM_d;
  const Eigen::Matrix<double, 3, Eigen::Dynamic> FB = k.R_BE * FMe.topRows<3>(), MB = k.R_BE * FMe.bottomRows<3>();
  for (int c = 0; c < nf; ++c) {
    const int e = free[c];
    const Eigen::Vector3d Fe = FB.col(e), Me = MB.col(e);
    if (base_.free) {
      S.B.block<3, 1>(0, c) += k.R_WB * Fe;
      S.B.block<3, 1>(3, c) += p.cross(Fe) + Me;
    }
    if (iv_theta_ >= 0) S.B(iv_theta_, c) += ax.dot(Me);
  }
  return S;
}

Eigen::MatrixXd HingedSystem::momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                double c_v, double c_q) const {
  // Pi = [P_W; H_W] with P_W = R_WB P_B, H_W = r_W x P_W + R_WB H_B, where (P_B, H_B), B axes
  // about B's origin, is the base's momentum M_b (V_B, w_B) plus E's, X pE, with
  // X = [R_BE, 0; p~ R_BE, R_BE] and pE = M_E (V_E, w_E) + (S1 dd', H(d) dd') (E axes).
  const int nf = num_elastic(), nb = nv_ - nf;
  const Kin k = kinematics(q, v, nullptr, 0.0);
  const Eigen::Matrix3d R_EB = k.R_BE.transpose();
  const Eigen::Vector3d& p = hinge_.point_B;
  const Eigen::Vector3d& ax = hinge_.axis_B;
  Eigen::Matrix<double, 6, 6> ME = frame_rigid_.spatial();
  Eigen::Matrix<double, 6, 1> pE;
  Eigen::Matrix<double, 3, Eigen::Dynamic> H;
  if (flexible_) {
    const Eigen::Vector3d s = ffi().first_moment(k.d);
    ME.topLeftCorner<3, 3>() += ffi().mass() * Eigen::Matrix3d::Identity();
    ME.block<3, 3>(0, 3) -= skew(s);
    ME.block<3, 3>(3, 0) += skew(s);
    ME.bottomRightCorner<3, 3>() += ffi().inertia_tensor(k.d);
    H = ffi().rotation_coupling(k.d);
  }
  pE << k.V_E, k.w_E;
  pE = (ME * pE).eval();
  if (flexible_) pE += (Eigen::Matrix<double, 6, 1>() << ffi().S1() * k.dd, H * k.dd).finished();
  Eigen::Matrix<double, 6, 6> X = Eigen::Matrix<double, 6, 6>::Zero();
  X.topLeftCorner<3, 3>() = k.R_BE;
  X.bottomLeftCorner<3, 3>() = skew(p) * k.R_BE;
  X.bottomRightCorner<3, 3>() = k.R_BE;
  const Eigen::Matrix<double, 6, 6> XME = X * ME;
  const Eigen::Matrix<double, 6, 6> Mb = base_.inertia.spatial();
  Eigen::Matrix<double, 6, 1> PH_B = X * pE;  // (P_B, H_B)
  if (base_.free) PH_B += Mb * (Eigen::Matrix<double, 6, 1>() << k.V_B, k.w_B).finished();

  // d(P_B, H_B)/d(border): c_v (linear in v) + c_q (R_WB through V_B, R_BE through theta).
  Eigen::Matrix<double, 6, Eigen::Dynamic> D = c_v * XME * frame_velocity_map(k);
  if (base_.free) {
    D.leftCols<3>() += c_v * Mb.leftCols<3>() * k.R_WB.transpose();
    D.middleCols<3>(3) += c_v * Mb.rightCols<3>();
    Eigen::Matrix<double, 6, 3> dV = Mb.leftCols<3>() + XME.leftCols<3>() * R_EB;  // d/dV_B
    D.middleCols<3>(3) += c_q * dV * skew(k.V_B);
  }
  if (iv_theta_ >= 0) {
    const Eigen::Vector3d axE = R_EB * ax, pl = k.R_BE * pE.head<3>(), pa = k.R_BE * pE.tail<3>();
    Eigen::Matrix<double, 6, 1> dX, dmotion;
    dX << ax.cross(pl), p.cross(ax.cross(pl)) + ax.cross(pa);
    dmotion << k.V_E.cross(axE), k.w_E.cross(axE);
    D.col(iv_theta_) += c_q * (dX + XME * dmotion);
  }
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, nv_);
  J.topLeftCorner(3, nb) = k.R_WB * D.topRows<3>();
  J.bottomLeftCorner(3, nb) = skew(k.r_W) * k.R_WB * D.topRows<3>() + k.R_WB * D.bottomRows<3>();
  if (base_.free) {
    const Eigen::Vector3d P_B = PH_B.head<3>(), H_B = PH_B.tail<3>();
    J.block<3, 3>(3, 0) -= c_q * skew(k.R_WB * P_B);
    J.block<3, 3>(0, 3) -= c_q * k.R_WB * skew(P_B);
    J.block<3, 3>(3, 3) -= c_q * (skew(k.r_W) * k.R_WB * skew(P_B) + k.R_WB * skew(H_B));
  }
  if (!nf) return J;
  // Elastic columns: d(p_E, h_E)/d(dd) = (S1, H(d)); d(p_E, h_E)/dd = (w~ S1, -V~ S1 + dJ w/dd + dH dd'/dd).
  const Eigen::Vector3d r_O = k.r_W + k.R_WB * p;
  const auto& S1 = ffi().S1();
  const Eigen::MatrixXd dp = c_v * S1 + c_q * skew(k.w_E) * S1;
  const Eigen::MatrixXd dh = c_v * H + c_q * (-skew(k.V_E) * S1 + ffi().inertia_tensor_jacobian(k.d, k.w_E) +
                                              ffi().rotation_coupling_jacobian(k.dd));
  const Eigen::MatrixXd dP_W = k.R_WE * dp;
  const Eigen::MatrixXd dH_W = skew(r_O) * dP_W + k.R_WE * dh;
  for (int c = 0; c < nf; ++c) {
    J.block<3, 1>(0, nb + c) = dP_W.col(app_->free_dofs()[c]);
    J.block<3, 1>(3, nb + c) = dH_W.col(app_->free_dofs()[c]);
  }
  return J;
}

}  // namespace deployfx::system
