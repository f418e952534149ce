#include "deployfx/system/hinged_system.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/math/check.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::system {
namespace {

// A rigid body's inertia about its centre of mass: symmetric and positive (semi)definite.
void check_inertia(const std::string& name, const Eigen::Matrix3d& J, bool definite) {
  const bool symmetric = J.allFinite() && (J - J.transpose()).norm() <= 1e-12 * std::max(1.0, J.norm());
  const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J).eigenvalues();
  if (!symmetric || !(definite ? lambda.minCoeff() > 0 : lambda.minCoeff() >= -1e-12 * J.norm()))
    throw std::invalid_argument(name + " must be symmetric positive " +
                                (definite ? "definite" : "semidefinite") + " (kg m^2)");
}

}  // namespace

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
  Eigen::Vector3d V_B = Eigen::Vector3d::Zero(), a_B = Eigen::Vector3d::Zero();  // B's origin, B axes
  double theta = 0, rate = 0, accel = 0;
  Eigen::Vector3d V_E, w_E, a_E, al_E;  // E's origin velocity/acceleration and rates, E axes
  Eigen::VectorXd d, dd, ddd;           // all dofs of the shell model
};

HingedSystem::HingedSystem(BaseSpec base, HingeSpec hinge, AppendageSpec appendage)
    : base_(std::move(base)), hinge_(std::move(hinge)), app_(std::move(appendage)),
      ffi_(app_.model ? *app_.model : throw std::invalid_argument("appendage.model is missing")) {
  if (base_.free) {
    require_positive("base.mass", base_.inertia.mass, "(kg)");
    check_inertia("base.inertia", base_.inertia.inertia_com, true);
    if (!base_.inertia.com.allFinite()) throw std::invalid_argument("base.com must be finite (m)");
  }
  if (!(hinge_.fitting.mass >= 0 && std::isfinite(hinge_.fitting.mass)))
    throw_out_of_range("hinge.fitting_mass", hinge_.fitting.mass, ">= 0 (kg)");
  check_inertia("hinge.fitting_inertia", hinge_.fitting.inertia_com, false);
  if (!hinge_.fitting.com.allFinite()) throw std::invalid_argument("hinge.fitting_com must be finite (m)");
  if (!(std::abs(hinge_.axis_B.norm() - 1.0) < 1e-9))
    throw std::invalid_argument("hinge.axis must be a unit vector");
  require_finite("hinge.tau0", hinge_.tau0, "(N m)");
  if (!(hinge_.k_theta >= 0 && std::isfinite(hinge_.k_theta)))
    throw_out_of_range("hinge.k_theta", hinge_.k_theta, "finite and >= 0 (N m/rad)");
  if (!(hinge_.c_theta >= 0 && std::isfinite(hinge_.c_theta)))
    throw_out_of_range("hinge.c_theta", hinge_.c_theta, "finite and >= 0 (N m s/rad)");
  if (hinge_.driven) {
    require_positive("spin_up.t_s", hinge_.driver.t_s, "(s)");
    require_finite("spin_up.omega_s", hinge_.driver.omega_s, "(rad/s)");
  }
  if (hinge_.lock) hinge_.lock->validate();
  if (!(app_.alpha_M >= 0 && std::isfinite(app_.alpha_M)))
    throw_out_of_range("appendage.alpha_M", app_.alpha_M, "finite and >= 0 (1/s)");
  if (!(app_.beta_K >= 0 && std::isfinite(app_.beta_K)))
    throw_out_of_range("appendage.beta_K", app_.beta_K, "finite and >= 0 (s)");
  flexible_ = app_.fidelity != Fidelity::kRigid;
  green_ = app_.fidelity == Fidelity::kNonlinear || app_.fidelity == Fidelity::kReducedNonlinear;
  frame_rigid_ = hinge_.fitting;
  if (!flexible_) {
    // The undeformed appendage as a rigid body, merged with the fitting (parallel axes).
    const double m = ffi_.mass() + frame_rigid_.mass;
    const Eigen::Vector3d s = ffi_.S0() + frame_rigid_.first_moment();
    const Eigen::Matrix3d J_O = ffi_.J0() + frame_rigid_.inertia_origin();
    const Eigen::Vector3d c = s / m;
    frame_rigid_ = {m, c, J_O - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose())};
  }
  if (app_.fidelity == Fidelity::kReducedLinear || app_.fidelity == Fidelity::kReducedNonlinear) {
    const int nfree = static_cast<int>(fem::free_dofs(app_.model->num_dofs(), app_.fixed_dofs).size());
    if (!(app_.modes >= 1 && app_.modes <= nfree))
      throw_out_of_range("appendage.modes", app_.modes, "in [1, " + std::to_string(nfree) + "] (the free dofs)");
    // The loads E's acceleration puts on the appendage, int rho N^T a and int rho N^T (al x P):
    // S1^T and H(0)^T (Eq. 28).
    Eigen::MatrixXd loads(ffi_.num_dofs(), 6);
    loads << ffi_.S1().transpose(), ffi_.rotation_coupling(Eigen::VectorXd::Zero(ffi_.num_dofs())).transpose();
    if (!(app_.derivative_modes >= -1 && app_.derivative_modes <= app_.modes))
      throw_out_of_range("appendage.derivative_modes", app_.derivative_modes, "in [0, modes] or -1 (automatic)");
    const int derivatives = app_.derivative_modes >= 0 ? app_.derivative_modes : std::min(app_.modes, 6);
    basis_ = fem::ritz_basis(*app_.model, app_.fixed_dofs, {app_.modes, true, green_ ? derivatives : 0}, loads);
    modal_.emplace(*app_.model, basis_.Phi, green_);
    ffi_ = ffi_.projected(basis_.Phi);
    const int r = modal_->size();
    free_.resize(r);
    for (int i = 0; i < r; ++i) free_[i] = i;
    K_free_ = modal_->linear_stiffness().sparseView(0.0, 0.0);
    M_free_ = ffi_.M();
    // A dense r x r elastic block: its pattern stores every entry, column-major.
    block_.emplace(Eigen::SparseMatrix<double>(Eigen::MatrixXd::Ones(r, r).sparseView()), free_);
    M_vals_ = block_->aligned(ffi_.M());
    K_vals_ = block_->aligned(K_free_);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Mij_vals_[3 * i + j] = block_->aligned(ffi_.Mij(i, j));
  } else if (flexible_) {
    free_ = fem::free_dofs(app_.model->num_dofs(), app_.fixed_dofs);
    K_free_ = fem::restrict(app_.model->stiffness(), free_);
    M_free_ = fem::restrict(ffi_.M(), free_);
    // K_L, L_c, the M_ij and the tangent stiffness all live on K_L's node-block pattern.
    block_.emplace(app_.model->stiffness(), free_);
    M_vals_ = block_->aligned(ffi_.M());
    K_vals_ = block_->aligned(app_.model->stiffness());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Mij_vals_[3 * i + j] = block_->aligned(ffi_.Mij(i, j));
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
  k.a_B = k.R_WB.transpose() * k.a_W;
  k.V_B = k.R_WB.transpose() * k.v_W;
  k.V_E = R_EB * (k.V_B + k.w_B.cross(p));
  k.w_E = R_EB * (k.w_B + k.rate * ax);
  k.al_E = R_EB * (k.wd_B + k.accel * ax + k.rate * k.w_B.cross(ax));
  k.a_E = R_EB * (k.a_B + k.wd_B.cross(p) + k.w_B.cross(k.w_B.cross(p)));
  return k;
}


Eigen::VectorXd HingedSystem::inertial_residual(const Kin& k, const Eigen::VectorXd& q) const {
  (void)q;
  body::FloatingFrameInertia::InertialForces f;
  if (flexible_) f = ffi_.inertial_forces(k.a_E, k.al_E, k.w_E, k.d, k.dd, k.ddd);
  else f.F.setZero(), f.M.setZero();
  const auto fit = frame_rigid_.inertial_forces(k.a_E, k.al_E, k.w_E);
  // On the appendage and its fitting, about E's origin, B axes.
  const Eigen::Vector3d F_B = k.R_BE * (f.F + fit.head<3>()), M_B = k.R_BE * (f.M + fit.tail<3>());
  Eigen::VectorXd r(nv_);
  if (base_.free) {
    // Virtual power of delta v_W and delta w_B: E's origin moves with B at point_B.
    const auto fb = base_.inertia.inertial_forces(k.a_B, k.wd_B, k.w_B);
    r.head<3>() = k.R_WB * (fb.head<3>() + F_B);
    r.segment<3>(3) = fb.tail<3>() + hinge_.point_B.cross(F_B) + M_B;
  }
  if (iv_theta_ >= 0) {
    r(iv_theta_) = hinge_.axis_B.dot(M_B) - (hinge_.tau0 - hinge_.k_theta * k.theta) +
                   hinge_.c_theta * k.rate;
    if (hinge_.lock) r(iv_theta_) -= joint::lock_load(*hinge_.lock, lock_history_, k.theta, k.rate).torque;
  }
  for (int i = 0; i < num_elastic(); ++i) r(iv_d_ + i) = f.Q(free_[i]);
  return r;
}

Eigen::VectorXd HingedSystem::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& a, double t) const {
  const Kin k = kinematics(q, v, &a, t);
  Eigen::VectorXd r = inertial_residual(k, q);
  if (iv_d_ >= 0 && modal_ && green_) {
    // Reduced Green strain: the polynomial force and, for damping, its exact tangent.
    const auto eta = q.segment(iq_d_, num_elastic());
    const auto rate = v.segment(iv_d_, num_elastic());
    Eigen::VectorXd f;
    Eigen::MatrixXd T;
    modal_->evaluate(eta, &f, app_.beta_K > 0 ? &T : nullptr);
    r.segment(iv_d_, num_elastic()) += f + app_.alpha_M * (M_free_ * rate);
    if (app_.beta_K > 0) r.segment(iv_d_, num_elastic()) += app_.beta_K * (T * rate);
  } else if (iv_d_ >= 0) {
    if (app_.fidelity == Fidelity::kNonlinear) {
      Eigen::VectorXd f_int;
      app_.model->internal_force(k.d, &f_int, nullptr);  // Eq. 14 (Green strain)
      for (int i = 0; i < num_elastic(); ++i) r(iv_d_ + i) += f_int(free_[i]);
    } else {
      r.segment(iv_d_, num_elastic()) += K_free_ * q.segment(iq_d_, num_elastic());
    }
    // Rayleigh damping. The stiffness-proportional part acts on the strain rate: beta_K K_L d'
    // for linear strain, beta_K K_T(d) d' = beta_K d/dt f_int(d) for Green strain (K_L d' would
    // damp the in-plane motion that large, inextensional bending needs, and stiffen the plate).
    const auto dv = v.segment(iv_d_, num_elastic());
    if (app_.alpha_M > 0) r.segment(iv_d_, num_elastic()) += app_.alpha_M * (M_free_ * dv);
    if (app_.fidelity == Fidelity::kNonlinear) {
      const double speed = k.dd.lpNorm<Eigen::Infinity>();
      if (app_.beta_K > 0 && speed > 0) {  // K_T(d) d' by a central difference of f_int along d'
        const double eps = 1e-6 / speed;
        Eigen::VectorXd fp, fm;
        app_.model->internal_force(k.d + eps * k.dd, &fp, nullptr);
        app_.model->internal_force(k.d - eps * k.dd, &fm, nullptr);
        for (int i = 0; i < num_elastic(); ++i) r(iv_d_ + i) += app_.beta_K * (fp(free_[i]) - fm(free_[i])) / (2 * eps);
      }
    } else if (app_.beta_K > 0) {
      r.segment(iv_d_, num_elastic()) += app_.beta_K * (K_free_ * dv);
    }
  }
  return r;
}

void HingedSystem::add_mass_matrix(const Kin& k, double c_a, integrate::BlockMatrix& S) const {
  // M = Jr^T M_E Jr + base on the border, with Jr mapping the border accelerations to E's
  // (a_E, al_E); the elastic rows of J are the identity (docs/engine-design.md).
  const int nf = num_elastic(), nb = nv_ - nf;
  const Eigen::Matrix3d R_EB = k.R_BE.transpose();
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jr = Eigen::MatrixXd::Zero(6, nb);
  if (base_.free) {
    Jr.block<3, 3>(0, 0) = R_EB * k.R_WB.transpose();
    Jr.block<3, 3>(0, 3) = -R_EB * skew(hinge_.point_B);
    Jr.block<3, 3>(3, 3) = R_EB;
    Eigen::Matrix<double, 6, 6> Jb = Eigen::Matrix<double, 6, 6>::Identity();
    Jb.topLeftCorner<3, 3>() = k.R_WB.transpose();
    S.A.topLeftCorner<6, 6>() += c_a * Jb.transpose() * base_.inertia.spatial() * Jb;
  }
  if (iv_theta_ >= 0) Jr.block<3, 1>(3, iv_theta_) = R_EB * hinge_.axis_B;
  Eigen::Matrix<double, 6, 6> ME = frame_rigid_.spatial();
  if (flexible_) {
    const Eigen::Vector3d s = ffi_.first_moment(k.d);
    ME.topLeftCorner<3, 3>() += ffi_.mass() * Eigen::Matrix3d::Identity();
    ME.block<3, 3>(0, 3) -= skew(s);
    ME.block<3, 3>(3, 0) += skew(s);
    ME.bottomRightCorner<3, 3>() += ffi_.inertia_tensor(k.d);
  }
  S.A += c_a * Jr.transpose() * ME * Jr;
  if (nf) {
    const auto H = ffi_.rotation_coupling(k.d);
    Eigen::Matrix<double, 6, Eigen::Dynamic> Mre(6, nf);
    for (int i = 0; i < nf; ++i) {
      Mre.block<3, 1>(0, i) = ffi_.S1().col(free_[i]);
      Mre.block<3, 1>(3, i) = H.col(free_[i]);
    }
    const Eigen::MatrixXd JtM = c_a * Jr.transpose() * Mre;
    S.B += JtM;
    S.C += JtM.transpose();
  }
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
  add_mass_matrix(k, c_a, S);  // border blocks; the elastic block's L_c is added below
  // Border columns (base and hinge coordinates, at most 7): central differences of the inertial
  // residual; the elastic internal force does not depend on them.
  for (int j = 0; j < nb; ++j) {
    const double hv = 1e-7 * std::max(1.0, std::abs(v(j))), hq = 1e-7;
    Eigen::VectorXd vp = v, vm = v;
    vp(j) += hv;
    vm(j) -= hv;
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
    const Eigen::VectorXd col =
        c_v * (inertial_residual(kinematics(q, vp, &a, t), q) - inertial_residual(kinematics(q, vm, &a, t), q)) / (2 * hv) +
        c_q * (inertial_residual(kinematics(retract(q, hq * e), v, &a, t), q) -
               inertial_residual(kinematics(retract(q, -hq * e), v, &a, t), q)) / (2 * hq);
    S.A.col(j) += col.head(nb);
    S.C.col(j) += col.tail(nf);
  }
  if (iv_d_ < 0) {
    S.E.resize(0, 0);
    return S;
  }
  // Elastic columns, analytic (docs/engine-design.md): the d- and d'-derivatives of the body-level
  // forces (F, M, Q), projected on the rows as in inertial_residual().
  const Eigen::Vector3d& w = k.w_E;
  const Eigen::Matrix3d W = skew(w);
  const auto& S1 = ffi_.S1();
  const auto Dw = ffi_.inertia_tensor_jacobian(k.d, w);
  const auto Hd = ffi_.rotation_coupling(k.d);
  const Eigen::MatrixXd dF_ddd = 2 * W * S1;
  const Eigen::MatrixXd dM_ddd = Dw + W * Hd;
  const Eigen::MatrixXd dF_dd = (skew(k.al_E) + W * W) * S1;
  const Eigen::MatrixXd dM_dd = -skew(k.a_E) * S1 + ffi_.inertia_tensor_jacobian(k.d, k.al_E) +
                                ffi_.rotation_coupling_jacobian(k.ddd) + W * Dw +
                                ffi_.inertia_rate_jacobian(k.dd, w) +
                                W * ffi_.rotation_coupling_jacobian(k.dd);
  // Elastic block: c_a L_c + c_v 2 G_y(w) + c_q (G_y(al) + G_w(w) + K_T), with
  // G_y(x) = sum_i x_j M_ik - x_k M_ij (i, j, k cyclic) and G_w(w) = sum w_i w_l M_il - |w|^2 M_ii.
  Eigen::VectorXd vals = c_a * M_vals_;
  const Eigen::Vector3d x = 2 * c_v * w + c_q * k.al_E;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    vals += x(j) * Mij_vals_[3 * i + l] - x(l) * Mij_vals_[3 * i + j];
    for (int m = 0; m < 3; ++m)
      vals += c_q * (w(i) * w(m) - (i == m ? w.squaredNorm() : 0.0)) * Mij_vals_[3 * i + m];
  }
  if (modal_ && green_) {
    Eigen::MatrixXd T;  // dense, column-major: the block's value order
    modal_->evaluate(k.d, nullptr, &T);
    vals += (c_q + c_v * app_.beta_K) * Eigen::Map<const Eigen::VectorXd>(T.data(), T.size());
  } else if (app_.fidelity == Fidelity::kNonlinear) {
    Eigen::SparseMatrix<double> KT;
    app_.model->internal_force(k.d, nullptr, &KT);  // K_L + K_L* + K_s, Eq. 19, 22, 23
    block_->add(KT, c_q + c_v * app_.beta_K, vals);  // and the damping beta_K K_T (its d-derivative dropped)
  } else {
    vals += (c_q + c_v * app_.beta_K) * K_vals_;
  }
  vals += c_v * app_.alpha_M * M_vals_;  // Rayleigh damping
  S.E = block_->with_values(vals);
  const Eigen::MatrixXd FB = k.R_BE * (c_v * dF_ddd + c_q * dF_dd);  // (3 x ndof)
  const Eigen::MatrixXd MB = k.R_BE * (c_v * dM_ddd + c_q * dM_dd);
  for (int c = 0; c < nf; ++c) {
    const int e = free_[c];
    const Eigen::Vector3d Fe = FB.col(e), Me = MB.col(e);
    if (base_.free) {
      S.B.block<3, 1>(0, c) += k.R_WB * Fe;
      S.B.block<3, 1>(3, c) += hinge_.point_B.cross(Fe) + Me;
    }
    if (iv_theta_ >= 0) S.B(iv_theta_, c) += hinge_.axis_B.dot(Me);
  }
  return S;
}

Eigen::Matrix<double, 6, 1> HingedSystem::frame_momentum(const Kin& k) const {
  Eigen::Matrix<double, 6, 1> p = frame_rigid_.momentum(k.V_E, k.w_E);
  if (!flexible_) return p;
  const Eigen::Vector3d s = ffi_.first_moment(k.d);
  p.head<3>() += ffi_.mass() * k.V_E + k.w_E.cross(s) + ffi_.S1() * k.dd;
  p.tail<3>() += s.cross(k.V_E) + ffi_.inertia_tensor(k.d) * k.w_E + ffi_.rotation_coupling(k.d) * k.dd;
  return p;
}

HingedSystem::Momenta HingedSystem::momenta(const Kin& k) const {
  Momenta m;
  const auto pb = base_.inertia.momentum(k.V_B, k.w_B);
  const Eigen::Vector3d P_base_W = k.R_WB * pb.head<3>();
  m.H_base_W = k.r_W.cross(P_base_W) + k.R_WB * pb.tail<3>();
  m.P_base_W = P_base_W;
  const auto pE = frame_momentum(k);
  const Eigen::Vector3d r_O = k.r_W + k.R_WB * hinge_.point_B;
  m.P_W = P_base_W + k.R_WE * pE.head<3>();
  m.H_W = m.H_base_W + r_O.cross(k.R_WE * pE.head<3>()) + k.R_WE * pE.tail<3>();
  return m;
}

Eigen::VectorXd HingedSystem::momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  const Momenta m = momenta(kinematics(q, v, nullptr, 0.0));
  Eigen::VectorXd Pi(6);
  Pi << m.P_W, m.H_W;
  return Pi;
}

Eigen::MatrixXd HingedSystem::momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                double c_v, double c_q) const {
  const int nf = num_elastic(), nb = nv_ - nf;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, nv_);
  // Border columns: Pi is linear in v (a unit central difference is exact); q by differences.
  for (int j = 0; j < nb; ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
    J.col(j) = c_v * 0.5 * (momentum(q, v + e) - momentum(q, v - e)) +
               c_q * (momentum(retract(q, 1e-7 * e), v) - momentum(retract(q, -1e-7 * e), v)) / 2e-7;
  }
  if (!nf) return J;
  const Kin k = kinematics(q, v, nullptr, 0.0);
  const Eigen::Vector3d r_O = k.r_W + k.R_WB * hinge_.point_B;
  const auto& S1 = ffi_.S1();
  // d(p_E, h_E)/d(dd) = (S1, H(d)); d(p_E, h_E)/dd = (w~ S1, -V~ S1 + dJ w/dd + dH dd'/dd).
  const Eigen::MatrixXd dp = c_v * S1 + c_q * skew(k.w_E) * S1;
  const Eigen::MatrixXd dh = c_v * ffi_.rotation_coupling(k.d) +
                             c_q * (-skew(k.V_E) * S1 + ffi_.inertia_tensor_jacobian(k.d, k.w_E) +
                                    ffi_.rotation_coupling_jacobian(k.dd));
  const Eigen::MatrixXd dP_W = k.R_WE * dp;
  const Eigen::MatrixXd dH_W = skew(r_O) * dP_W + k.R_WE * dh;
  for (int c = 0; c < nf; ++c) {
    J.block<3, 1>(0, nb + c) = dP_W.col(free_[c]);
    J.block<3, 1>(3, nb + c) = dH_W.col(free_[c]);
  }
  return J;
}

Eigen::VectorXd HingedSystem::gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) const {
  if (!hinge_.lock || iq_theta_ < 0) return {};
  Eigen::VectorXd g(2);
  joint::lock_events(*hinge_.lock, lock_history_, q(iq_theta_), v(iv_theta_), &g(0), &g(1));
  return g;
}

void HingedSystem::accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) const {
  if (hinge_.lock && iq_theta_ >= 0)
    joint::update_lock_history(*hinge_.lock, lock_history_, q(iq_theta_), v(iv_theta_));
}

HingedSystem::Outputs HingedSystem::outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                            double t) const {
  const Kin k = kinematics(q, v, nullptr, t);
  Outputs o;
  o.theta = k.theta;
  o.theta_rate = k.rate;
  o.spring_torque = hinge_.tau0 - hinge_.k_theta * k.theta;
  if (hinge_.lock) {
    const auto L = joint::lock_load(*hinge_.lock, lock_history_, k.theta, k.rate);
    o.lock_force = std::max(L.normal_force, 0.0);
    o.lock_torque = L.torque;
  }
  const Momenta m = momenta(k);
  o.P_W = m.P_W;
  o.H_W = m.H_W;
  o.H_base_W = m.H_base_W;
  o.P_base_W = m.P_base_W;
  o.kinetic = (base_.free ? base_.inertia.kinetic_energy(k.V_B, k.w_B) : 0.0) +
              frame_rigid_.kinetic_energy(k.V_E, k.w_E) +
              (flexible_ ? ffi_.kinetic_energy(k.V_E, k.w_E, k.d, k.dd) : 0.0);
  o.potential = -hinge_.tau0 * k.theta + 0.5 * hinge_.k_theta * k.theta * k.theta;
  if (iq_d_ >= 0) {
    const Eigen::VectorXd df = q.segment(iq_d_, num_elastic());
    o.potential += modal_ && green_ ? modal_->strain_energy(df)
                   : green_         ? app_.model->strain_energy(k.d)
                                    : 0.5 * df.dot(K_free_ * df);
  }
  return o;
}

}  // namespace deployfx::system
