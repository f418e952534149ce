#include "deployfx/system/hinged_system.hpp"

#include <cmath>
#include <stdexcept>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/math/check.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::system {

void SpinUpDriver::evaluate(double t, double* theta, double* rate, double* accel) const {
  const double w = 2 * M_PI / t_s;
  if (t <= t_s) {
    *theta = omega_s / t_s * (0.5 * t * t + (std::cos(w * t) - 1) / (w * w));
    *rate = omega_s / t_s * (t - std::sin(w * t) / w);
    *accel = omega_s / t_s * (1 - std::cos(w * t));
  } else {
    *theta = omega_s / t_s * (0.5 * t_s * t_s) + omega_s * (t - t_s);
    *rate = omega_s;
    *accel = 0;
  }
}

struct HingedSystem::Kin {
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity(), R_BE, R_WE;
  Eigen::Vector3d r_W = Eigen::Vector3d::Zero(), v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero(), a_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d wd_B = Eigen::Vector3d::Zero();
  double theta = 0, rate = 0, accel = 0;
  Eigen::Vector3d V_E, w_E, a_E, al_E;  // E's origin velocity/acceleration and rates, E axes
  Eigen::VectorXd d, dd, ddd;           // all dofs of the shell model
};

HingedSystem::HingedSystem(BaseSpec base, HingeSpec hinge, AppendageSpec appendage)
    : base_(std::move(base)), hinge_(std::move(hinge)), app_(std::move(appendage)),
      ffi_(app_.model ? *app_.model : throw std::invalid_argument("appendage.model is missing")) {
  if (base_.free) {
    require_positive("base.mass", base_.mass, "(kg)");
    if (!base_.inertia.allFinite() || base_.inertia.llt().info() != Eigen::Success ||
        (base_.inertia - base_.inertia.transpose()).norm() > 1e-12 * base_.inertia.norm())
      throw std::invalid_argument("base.inertia must be symmetric positive definite (kg m^2)");
  }
  if (!(std::abs(hinge_.axis_B.norm() - 1.0) < 1e-9))
    throw std::invalid_argument("hinge.axis must be a unit vector");
  require_finite("hinge.tau0", hinge_.tau0, "(N m)");
  if (!(hinge_.k_theta >= 0)) throw_out_of_range("hinge.k_theta", hinge_.k_theta, ">= 0 (N m/rad)");
  if (!(hinge_.c_theta >= 0)) throw_out_of_range("hinge.c_theta", hinge_.c_theta, ">= 0 (N m s/rad)");
  if (hinge_.driven) require_positive("driver.t_s", hinge_.driver.t_s, "(s)");
  if (app_.fidelity != Fidelity::kRigid) {
    free_ = fem::free_dofs(app_.model->num_dofs(), app_.fixed_dofs);
    K_free_ = fem::restrict(app_.model->stiffness(), free_);
    M_free_ = Eigen::MatrixXd(fem::restrict(ffi_.M(), free_));
  }
  nq_ = nv_ = 0;
  if (base_.free) nq_ += 7, nv_ += 6;
  if (!hinge_.driven) iq_theta_ = nq_++, iv_theta_ = nv_++;
  if (!free_.empty()) {
    iq_d_ = nq_, iv_d_ = nv_;
    nq_ += num_elastic();
    nv_ += num_elastic();
  }
}

Eigen::VectorXd HingedSystem::full(const Eigen::VectorXd& d_free) const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(ffi_.num_dofs());
  for (int k = 0; k < num_elastic(); ++k) d(free_[k]) = d_free(k);
  return d;
}

Eigen::VectorXd HingedSystem::initial_positions() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  if (base_.free) q(3) = 1.0;  // identity quaternion (w, x, y, z)
  return q;
}

Eigen::VectorXd HingedSystem::retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const {
  Eigen::VectorXd out = q;
  int iq = 0, iv = 0;
  if (base_.free) {
    out.head<3>() += dq.head<3>();
    const Eigen::Quaterniond Q(q(3), q(4), q(5), q(6));
    const Eigen::Quaterniond Q1 = (Q * quaternion_exp(dq.segment<3>(3))).normalized();  // body frame
    out.segment<4>(3) << Q1.w(), Q1.x(), Q1.y(), Q1.z();
    iq = 7, iv = 6;
  }
  out.tail(nq_ - iq) += dq.tail(nv_ - iv);
  return out;
}

HingedSystem::Kin HingedSystem::kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                           const Eigen::VectorXd* a, double t) const {
  Kin k;
  if (base_.free) {
    k.r_W = q.head<3>();
    k.R_WB = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
    k.v_W = v.head<3>();
    k.w_B = v.segment<3>(3);
    if (a) k.a_W = a->head<3>(), k.wd_B = a->segment<3>(3);
  }
  if (hinge_.driven) {
    hinge_.driver.evaluate(t, &k.theta, &k.rate, &k.accel);
  } else {
    k.theta = q(iq_theta_);
    k.rate = v(iv_theta_);
    if (a) k.accel = (*a)(iv_theta_);
  }
  const int n = ffi_.num_dofs();
  k.d = iq_d_ >= 0 ? full(q.segment(iq_d_, num_elastic())) : Eigen::VectorXd::Zero(n);
  k.dd = iv_d_ >= 0 ? full(v.segment(iv_d_, num_elastic())) : Eigen::VectorXd::Zero(n);
  k.ddd = (a && iv_d_ >= 0) ? full(a->segment(iv_d_, num_elastic())) : Eigen::VectorXd::Zero(n);

  const Eigen::Vector3d& ax = hinge_.axis_B;
  const Eigen::Vector3d& p = hinge_.point_B;
  k.R_BE = Eigen::AngleAxisd(k.theta, ax).toRotationMatrix() * hinge_.R_BE0;
  k.R_WE = k.R_WB * k.R_BE;
  const Eigen::Matrix3d R_EB = k.R_BE.transpose();
  const Eigen::Vector3d a_B = k.R_WB.transpose() * k.a_W;
  k.V_E = R_EB * (k.R_WB.transpose() * k.v_W + k.w_B.cross(p));
  k.w_E = R_EB * (k.w_B + k.rate * ax);
  k.al_E = R_EB * (k.wd_B + k.accel * ax + k.rate * k.w_B.cross(ax));
  k.a_E = R_EB * (a_B + k.wd_B.cross(p) + k.w_B.cross(k.w_B.cross(p)));
  return k;
}

Eigen::VectorXd HingedSystem::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& a, double t) const {
  const Kin k = kinematics(q, v, &a, t);
  const auto f = ffi_.inertial_forces(k.a_E, k.al_E, k.w_E, k.d, k.dd, k.ddd);
  const Eigen::Vector3d F_B = k.R_BE * f.F, M_B = k.R_BE * f.M;  // on the appendage, B axes
  Eigen::VectorXd r(nv_);
  if (base_.free) {
    // Virtual power of delta v_W and delta w_B: E's origin moves with B at point_B.
    r.head<3>() = base_.mass * k.a_W + k.R_WB * F_B;
    r.segment<3>(3) = base_.inertia * k.wd_B + k.w_B.cross(base_.inertia * k.w_B) +
                      hinge_.point_B.cross(F_B) + M_B;
  }
  if (iv_theta_ >= 0)
    r(iv_theta_) = hinge_.axis_B.dot(M_B) - (hinge_.tau0 - hinge_.k_theta * k.theta) +
                   hinge_.c_theta * k.rate;
  if (iv_d_ >= 0) {
    Eigen::VectorXd elastic;
    if (app_.fidelity == Fidelity::kNonlinear) {
      Eigen::VectorXd f_int;
      app_.model->internal_force(k.d, &f_int, nullptr);
      elastic.resize(num_elastic());
      for (int i = 0; i < num_elastic(); ++i) elastic(i) = f_int(free_[i]);
    } else {
      elastic = K_free_ * q.segment(iq_d_, num_elastic());
    }
    for (int i = 0; i < num_elastic(); ++i) r(iv_d_ + i) = f.Q(free_[i]) + elastic(i);
  }
  return r;
}

Eigen::MatrixXd HingedSystem::mass_matrix(const Kin& k) const {
  // M = J_E^T M_E J_E + base, with J_E mapping vdot to (a_E, al_E, d'') (docs/engine-design.md).
  const int nf = num_elastic();
  const Eigen::Matrix3d R_EB = k.R_BE.transpose();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6 + nf, nv_);
  if (base_.free) {
    J.block<3, 3>(0, 0) = R_EB * k.R_WB.transpose();
    J.block<3, 3>(0, 3) = -R_EB * skew(hinge_.point_B);
    J.block<3, 3>(3, 3) = R_EB;
  }
  if (iv_theta_ >= 0) J.block<3, 1>(3, iv_theta_) = R_EB * hinge_.axis_B;
  if (nf) J.bottomRightCorner(nf, nf).setIdentity();
  Eigen::MatrixXd ME = Eigen::MatrixXd::Zero(6 + nf, 6 + nf);
  const Eigen::Vector3d s = ffi_.first_moment(k.d);
  ME.block<3, 3>(0, 0) = ffi_.mass() * Eigen::Matrix3d::Identity();
  ME.block<3, 3>(0, 3) = -skew(s);
  ME.block<3, 3>(3, 0) = skew(s);
  ME.block<3, 3>(3, 3) = ffi_.inertia_tensor(k.d);
  if (nf) {
    const auto H = ffi_.rotation_coupling(k.d);
    for (int i = 0; i < nf; ++i) {
      ME.block<3, 1>(0, 6 + i) = ffi_.S1().col(free_[i]);
      ME.block<3, 1>(3, 6 + i) = H.col(free_[i]);
    }
    ME.bottomLeftCorner(nf, 6) = ME.topRightCorner(6, nf).transpose();
    ME.bottomRightCorner(nf, nf) = M_free_;
  }
  Eigen::MatrixXd M = J.transpose() * ME * J;
  if (base_.free) {
    M.block<3, 3>(0, 0) += base_.mass * Eigen::Matrix3d::Identity();
    M.block<3, 3>(3, 3) += base_.inertia;
  }
  return M;
}

Eigen::MatrixXd HingedSystem::iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                               const Eigen::VectorXd& a, double t, double c_a,
                                               double c_v, double c_q) const {
  const Kin k = kinematics(q, v, &a, t);
  Eigen::MatrixXd S = c_a * mass_matrix(k);
  // Columns of the base and hinge coordinates: central differences of the residual (at most 7).
  const int n_rigid = nv_ - num_elastic();
  for (int j = 0; j < n_rigid; ++j) {
    const double hv = 1e-7 * std::max(1.0, std::abs(v(j)));
    Eigen::VectorXd vp = v, vm = v;
    vp(j) += hv;
    vm(j) -= hv;
    S.col(j) += c_v * (residual(q, vp, a, t) - residual(q, vm, a, t)) / (2 * hv);
    const double hq = 1e-7;
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
    S.col(j) += c_q * (residual(retract(q, hq * e), v, a, t) - residual(retract(q, -hq * e), v, a, t)) / (2 * hq);
  }
  // Elastic columns, analytic (docs/engine-design.md): the d- and d'-derivatives of the body-level
  // forces (F, M, Q), projected on the rows as in residual().
  if (iv_d_ >= 0) {
    const int nf = num_elastic();
    const Eigen::Vector3d& w = k.w_E;
    const Eigen::Matrix3d W = skew(w);
    const auto& S1 = ffi_.S1();
    const auto Dw = ffi_.inertia_tensor_jacobian(k.d, w);
    const auto Hd = ffi_.rotation_coupling(k.d);
    // d/dd'
    const Eigen::MatrixXd dF_ddd = 2 * W * S1;
    const Eigen::MatrixXd dM_ddd = Dw + W * Hd;
    // d/dd
    const Eigen::MatrixXd dF_dd = (skew(k.al_E) + W * W) * S1;
    const Eigen::MatrixXd dM_dd = -skew(k.a_E) * S1 + ffi_.inertia_tensor_jacobian(k.d, k.al_E) +
                                  ffi_.rotation_coupling_jacobian(k.ddd) + W * Dw +
                                  ffi_.inertia_rate_jacobian(k.dd, w) +
                                  W * ffi_.rotation_coupling_jacobian(k.dd);
    Eigen::SparseMatrix<double> dQ_dd = ffi_.gyroscopic(k.al_E) + ffi_.centrifugal_stiffness(w);
    if (app_.fidelity == Fidelity::kNonlinear) {
      Eigen::SparseMatrix<double> KT;
      app_.model->internal_force(k.d, nullptr, &KT);
      dQ_dd += KT;
    } else {
      dQ_dd += app_.model->stiffness();
    }
    const Eigen::SparseMatrix<double> dQ = c_v * 2.0 * ffi_.gyroscopic(w) + c_q * dQ_dd;
    const Eigen::MatrixXd dF = c_v * dF_ddd + c_q * dF_dd;  // (3 x ndof)
    const Eigen::MatrixXd dM = c_v * dM_ddd + c_q * dM_dd;
    const Eigen::MatrixXd FB = k.R_BE * dF, MB = k.R_BE * dM;
    const Eigen::MatrixXd Q = Eigen::MatrixXd(fem::restrict(dQ, free_));
    for (int c = 0; c < nf; ++c) {
      const int col = iv_d_ + c, e = free_[c];
      const Eigen::Vector3d Fe = FB.col(e), Me = MB.col(e);
      if (base_.free) {
        S.block<3, 1>(0, col) += k.R_WB * Fe;
        S.block<3, 1>(3, col) += hinge_.point_B.cross(Fe) + Me;
      }
      if (iv_theta_ >= 0) S(iv_theta_, col) += hinge_.axis_B.dot(Me);
      S.block(iv_d_, col, nf, 1) += Q.col(c);
    }
  }
  return S;
}

HingedSystem::Outputs HingedSystem::outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                            double t) const {
  const Kin k = kinematics(q, v, nullptr, t);
  Outputs o;
  o.theta = k.theta;
  o.theta_rate = k.rate;
  o.spring_torque = hinge_.tau0 - hinge_.k_theta * k.theta;
  const Eigen::Vector3d s = ffi_.first_moment(k.d);
  const Eigen::Vector3d p_E = ffi_.mass() * k.V_E + k.w_E.cross(s) + ffi_.S1() * k.dd;
  const Eigen::Vector3d h_E = s.cross(k.V_E) + ffi_.inertia_tensor(k.d) * k.w_E +
                              ffi_.rotation_coupling(k.d) * k.dd;  // about E's origin
  const Eigen::Vector3d r_O = k.r_W + k.R_WB * hinge_.point_B;
  const Eigen::Vector3d p_B = base_.mass * k.v_W;
  o.H_base_W = k.r_W.cross(p_B) + k.R_WB * (base_.inertia * k.w_B);
  o.P_W = p_B + k.R_WE * p_E;
  o.H_W = o.H_base_W + r_O.cross(k.R_WE * p_E) + k.R_WE * h_E;
  o.kinetic = 0.5 * base_.mass * k.v_W.squaredNorm() + 0.5 * k.w_B.dot(base_.inertia * k.w_B) +
              ffi_.kinetic_energy(k.V_E, k.w_E, k.d, k.dd);
  o.potential = -hinge_.tau0 * k.theta + 0.5 * hinge_.k_theta * k.theta * k.theta;
  if (iq_d_ >= 0) {
    const Eigen::VectorXd df = q.segment(iq_d_, num_elastic());
    o.potential += app_.fidelity == Fidelity::kNonlinear ? app_.model->strain_energy(k.d)
                                                         : 0.5 * df.dot(K_free_ * df);
  }
  return o;
}

}  // namespace deployfx::system
