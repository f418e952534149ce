#include "deployfx/system/hinged_system.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/math/check.hpp"
#include "deployfx/system/base_frame.hpp"

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

HingedSystem::HingedSystem(BaseSpec base, HingeSpec hinge, AppendageSpec appendage)
    : base_(std::move(base)), hinge_(std::move(hinge)) {
  if (!appendage.model) throw std::invalid_argument("appendage.model is missing");
  if (base_.free) check_rigid_inertia("base", base_.inertia, true);
  check_rigid_inertia("hinge.fitting", hinge_.fitting, false);
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
  // The appendage's checks (appendage.alpha_M, .beta_K, .modes, .derivative_modes), its shape
  // integrals, basis and elastic force.
  app_.emplace(std::move(appendage), "appendage");
  flexible_ = app_->flexible();
  green_ = app_->green();
  frame_rigid_ = hinge_.fitting;
  if (!flexible_) {
    // The undeformed appendage as a rigid body, merged with the fitting (parallel axes).
    const double m = ffi().mass() + frame_rigid_.mass;
    const Eigen::Vector3d s = ffi().S0() + frame_rigid_.first_moment();
    const Eigen::Matrix3d J_O = ffi().J0() + frame_rigid_.inertia_origin();
    const Eigen::Vector3d c = s / m;
    frame_rigid_ = {m, c, J_O - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose())};
  }
  nq_ = nv_ = 0;
  if (base_.free) nq_ += 7, nv_ += 6;
  if (!hinge_.driven) iq_theta_ = nq_++, iv_theta_ = nv_++;
  if (num_elastic() > 0) {
    iq_d_ = nq_, iv_d_ = nv_;
    nq_ += num_elastic();
    nv_ += num_elastic();
  }
}

Eigen::VectorXd HingedSystem::initial_positions() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  if (base_.free) q(3) = 1.0;  // identity quaternion (w, x, y, z)
  return q;
}

Eigen::VectorXd HingedSystem::retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const {
  return retract_with_base(base_.free, q, dq);
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
  if (flexible_) {  // a rigid appendage's d stays empty: its integrals are frame_rigid_'s
    const int n = num_elastic();
    k.d = app_->full(q.segment(iq_d_, n));
    k.dd = app_->full(v.segment(iv_d_, n));
    if (a) k.ddd = app_->full(a->segment(iv_d_, n));
  }

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
  if (flexible_) f = ffi().inertial_forces(k.a_E, k.al_E, k.w_E, k.d, k.dd, k.ddd);
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
  for (int i = 0; i < num_elastic(); ++i) r(iv_d_ + i) = f.Q(app_->free_dofs()[i]);
  return r;
}

Eigen::VectorXd HingedSystem::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& a, double t) const {
  const Kin k = kinematics(q, v, &a, t);
  Eigen::VectorXd r = inertial_residual(k, q);
  if (iv_d_ >= 0)  // the internal force and Rayleigh damping (body/flexible_body.hpp)
    app_->add_elastic_force(q.segment(iq_d_, num_elastic()), v.segment(iv_d_, num_elastic()), k.d, k.dd,
                            r.segment(iv_d_, num_elastic()));
  return r;
}

Eigen::Matrix<double, 6, 1> HingedSystem::frame_momentum(const Kin& k) const {
  Eigen::Matrix<double, 6, 1> p = frame_rigid_.momentum(k.V_E, k.w_E);
  if (!flexible_) return p;
  const body::FloatingFrameInertia& ffi = this->ffi();
  const Eigen::Vector3d s = ffi.first_moment(k.d);
  p.head<3>() += ffi.mass() * k.V_E + k.w_E.cross(s) + ffi.S1() * k.dd;
  p.tail<3>() += s.cross(k.V_E) + ffi.inertia_tensor(k.d) * k.w_E + ffi.rotation_coupling(k.d) * k.dd;
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
              (flexible_ ? ffi().kinetic_energy(k.V_E, k.w_E, k.d, k.dd) : 0.0);
  o.potential = -hinge_.tau0 * k.theta + 0.5 * hinge_.k_theta * k.theta * k.theta;
  if (iq_d_ >= 0) o.potential += app_->strain_energy(q.segment(iq_d_, num_elastic()), k.d);
  return o;
}

double HingedSystem::newton_step_limit(const Eigen::VectorXd&, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& dv) const {
  if (!hinge_.lock || iv_theta_ < 0) return 1.0;
  return joint::friction_step_limit(*hinge_.lock, lock_history_, v(iv_theta_), dv(iv_theta_));
}

}  // namespace deployfx::system
