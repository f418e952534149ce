#include "deployfx/system/hinge_chain.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deployfx/math/check.hpp"
#include "deployfx/math/so3.hpp"

namespace deployfx::system {

// The motion of every body at one instant. Each link's quantities are in its own axes C.
struct HingeChain::Kin {
  BaseMotion base;
  struct Link {
    Eigen::Matrix3d R_PC, R_WC;
    Eigen::Vector3d o_W;          // C's origin, W
    Eigen::Vector3d V, w, a, al;  // C's origin velocity and acceleration, angular velocity and acceleration
    double theta = 0, rate = 0, accel = 0;
  };
  std::vector<Link> links;
};

namespace {

void check_spec(const std::string& name, const ChainHingeSpec& h) {
  if (!h.point_P.allFinite()) throw std::invalid_argument(name + ".point must be 3 finite numbers (m)");
  if (!(std::abs(h.axis_P.norm() - 1.0) < 1e-9))
    throw_out_of_range(name + ".axis (its norm)", h.axis_P.norm(), "1 (a unit vector)");
  const Eigen::Matrix3d& R = h.R_PC0;
  if (!R.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-9 || R.determinant() < 0)
    throw std::invalid_argument(name + ".R_PC0 must be a rotation matrix");
  require_finite(name + ".tau0", h.tau0, "(N m)");
  if (!(h.k_theta >= 0 && std::isfinite(h.k_theta)))
    throw_out_of_range(name + ".k_theta", h.k_theta, "finite and >= 0 (N m/rad)");
  if (!(h.c_theta >= 0 && std::isfinite(h.c_theta)))
    throw_out_of_range(name + ".c_theta", h.c_theta, "finite and >= 0 (N m s/rad)");
  if (h.lock) {
    try {
      h.lock->validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(name + "." + e.what());
    }
  }
  check_rigid_inertia(name + ".body", h.body, false);
}

// [R_Wb 0; r_W~ R_Wb R_Wb]: a body's momentum (p; h about its origin, body axes) to (P_W; H_W
// about W's origin).
Eigen::Matrix<double, 6, 6> to_world(const Eigen::Matrix3d& R_Wb, const Eigen::Vector3d& o_W) {
  Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Zero();
  T.topLeftCorner<3, 3>() = R_Wb;
  T.bottomLeftCorner<3, 3>() = skew(o_W) * R_Wb;
  T.bottomRightCorner<3, 3>() = R_Wb;
  return T;
}

}  // namespace

HingeChain::HingeChain(BaseSpec base, std::vector<ChainHingeSpec> hinges)
    : base_(std::move(base)), hinges_(std::move(hinges)) {
  if (hinges_.empty()) throw std::invalid_argument("hinges must hold at least one hinge, got 0");
  if (base_.free) check_rigid_inertia("base", base_.inertia, true);
  for (int k = 0; k < num_hinges(); ++k) check_spec("hinges[" + std::to_string(k) + "]", hinges_[k]);
  lock_history_.assign(hinges_.size(), {});
  iq_theta_ = base_.free ? kBasePositions : 0;
  iv_theta_ = base_.free ? kBaseVelocities : 0;
  nq_ = iq_theta_ + num_hinges();
  nv_ = iv_theta_ + num_hinges();
  // Hinge k's diagonal entry is the inertia about its axis of the bodies it carries: zero makes
  // M singular (a chain that ends in bodies without mass, say).
  const Eigen::MatrixXd M = mass_matrix(initial_positions());
  for (int k = 0; k < num_hinges(); ++k)
    if (!(M(iv_theta_ + k, iv_theta_ + k) > 1e-300))
      throw std::invalid_argument("hinges[" + std::to_string(k) + "].body: the bodies from hinge " +
                                  std::to_string(k) + " on have no inertia about its axis (kg m^2)");
  if (M.llt().info() != Eigen::Success)
    throw std::invalid_argument("hinges: the mass matrix is singular at the stowed configuration");
}

Eigen::VectorXd HingeChain::initial_positions() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  if (base_.free) q(3) = 1.0;  // identity quaternion (w, x, y, z)
  return q;
}

HingeChain::Kin HingeChain::kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd* a) const {
  Kin k;
  k.base = base_motion(base_.free, q, v, a);
  k.links.resize(hinges_.size());
  // Forward pass, parent P to child C, with the hinge point p and axis fixed in P:
  //   V_C = R_CP (V_P + w_P x p),   a_C = R_CP (a_P + al_P x p + w_P x (w_P x p)),
  //   w_C = R_CP (w_P + theta' n),  al_C = R_CP (al_P + theta'' n + theta' w_P x n).
  Eigen::Matrix3d R_WP = k.base.R_WB;
  Eigen::Vector3d o_P = k.base.r_W, V = k.base.V_B, w = k.base.w_B, acc = k.base.a_B, al = k.base.wd_B;
  for (int c = 0; c < num_hinges(); ++c) {
    const ChainHingeSpec& h = hinges_[c];
    Kin::Link& L = k.links[c];
    L.theta = q(iq_theta_ + c);
    L.rate = v(iv_theta_ + c);
    L.accel = a ? (*a)(iv_theta_ + c) : 0.0;
    const Eigen::Vector3d& p = h.point_P;
    const Eigen::Vector3d& n = h.axis_P;
    L.R_PC = Eigen::AngleAxisd(L.theta, n).toRotationMatrix() * h.R_PC0;
    const Eigen::Matrix3d R_CP = L.R_PC.transpose();
    L.R_WC = R_WP * L.R_PC;
    L.o_W = o_P + R_WP * p;
    L.V = R_CP * (V + w.cross(p));
    L.a = R_CP * (acc + al.cross(p) + w.cross(w.cross(p)));
    L.w = R_CP * (w + L.rate * n);
    L.al = R_CP * (al + L.accel * n + L.rate * w.cross(n));
    R_WP = L.R_WC, o_P = L.o_W, V = L.V, w = L.w, acc = L.a, al = L.al;
  }
  return k;
}

Eigen::VectorXd HingeChain::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& a, double) const {
  const Kin k = kinematics(q, v, &a);
  Eigen::VectorXd r(nv_);
  // Backward pass: (F, M) is the inertial wrench of bodies c..N-1 about C_c's origin, C_c axes.
  // Virtual power of theta'_c: its twist moves them all about hinge c's axis, so the generalized
  // inertial force is n . M (n through C_c's origin); the springs, dampers and locks are tau.
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), M = Eigen::Vector3d::Zero();
  for (int c = num_hinges() - 1; c >= 0; --c) {
    const ChainHingeSpec& h = hinges_[c];
    const Kin::Link& L = k.links[c];
    const auto f = h.body.inertial_forces(L.a, L.al, L.w);
    F += f.head<3>();
    M += f.tail<3>();
    const Eigen::Vector3d F_P = L.R_PC * F, M_P = L.R_PC * M;
    double tau = h.tau0 - h.k_theta * L.theta - h.c_theta * L.rate;
    if (h.lock) tau += joint::lock_load(*h.lock, lock_history_[c], L.theta, L.rate).torque;
    r(iv_theta_ + c) = h.axis_P.dot(M_P) - tau;
    F = F_P;                         // into P, about P's origin: the wrench the parent carries
    M = h.point_P.cross(F_P) + M_P;
  }
  if (base_.free) {  // virtual power of v_W (W axes) and w_B (B axes)
    const BaseMotion& b = k.base;
    const auto fb = base_.inertia.inertial_forces(b.a_B, b.wd_B, b.w_B);
    r.head<3>() = b.R_WB * (fb.head<3>() + F);
    r.segment<3>(3) = fb.tail<3>() + M;
  }
  return r;
}

std::vector<Eigen::MatrixXd> HingeChain::jacobians(const Kin& k) const {
  // J_C = X_CP J_P + [0; R_CP n] e_theta_c, X_CP = [R_CP, -R_CP p~; 0, R_CP] (the forward pass's
  // velocity relations); the base's J_B = [R_WB^T 0; 0 I] (zero for a fixed base).
  std::vector<Eigen::MatrixXd> J(hinges_.size() + 1, Eigen::MatrixXd::Zero(6, nv_));
  if (base_.free) {
    J[0].block<3, 3>(0, 0) = k.base.R_WB.transpose();
    J[0].block<3, 3>(3, 3).setIdentity();
  }
  for (int c = 0; c < num_hinges(); ++c) {
    const ChainHingeSpec& h = hinges_[c];
    const Eigen::Matrix3d R_CP = k.links[c].R_PC.transpose();
    const Eigen::MatrixXd& P = J[c];
    J[c + 1].topRows<3>() = R_CP * (P.topRows<3>() - skew(h.point_P) * P.bottomRows<3>());
    J[c + 1].bottomRows<3>() = R_CP * P.bottomRows<3>();
    J[c + 1].block<3, 1>(3, iv_theta_ + c) += R_CP * h.axis_P;
  }
  return J;
}

Eigen::MatrixXd HingeChain::mass_matrix(const Eigen::VectorXd& q) const {
  const Kin k = kinematics(q, Eigen::VectorXd::Zero(nv_), nullptr);
  const std::vector<Eigen::MatrixXd> J = jacobians(k);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(nv_, nv_);
  if (base_.free) M += J[0].transpose() * base_.inertia.spatial() * J[0];
  for (int c = 0; c < num_hinges(); ++c) M += J[c + 1].transpose() * hinges_[c].body.spatial() * J[c + 1];
  return M;
}

integrate::BlockMatrix HingeChain::iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                    const Eigen::VectorXd& a, double t, double c_a,
                                                    double c_v, double c_q) const {
  Eigen::MatrixXd S = c_a * mass_matrix(q);
  // The velocity- and configuration-dependent forces by central differences (at most 6 + N
  // columns of a few-body residual: cheap), the configuration along retract().
  for (int j = 0; j < nv_; ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
    if (c_v != 0) {
      const double h = 1e-7 * std::max(1.0, std::abs(v(j)));
      S.col(j) += c_v * (residual(q, v + h * e, a, t) - residual(q, v - h * e, a, t)) / (2 * h);
    }
    if (c_q != 0) {
      const double h = 1e-7;
      S.col(j) += c_q * (residual(retract(q, h * e), v, a, t) - residual(retract(q, -h * e), v, a, t)) / (2 * h);
    }
  }
  return integrate::BlockMatrix::from_dense(std::move(S));
}

Eigen::MatrixXd HingeChain::momentum_matrix(const Kin& k) const {
  // Pi = sum_b T_b M_b J_b v (the body momenta M_b (V_b; w_b) about their origins, to W).
  const std::vector<Eigen::MatrixXd> J = jacobians(k);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, nv_);
  if (base_.free) A += to_world(k.base.R_WB, k.base.r_W) * base_.inertia.spatial() * J[0];
  for (int c = 0; c < num_hinges(); ++c)
    A += to_world(k.links[c].R_WC, k.links[c].o_W) * hinges_[c].body.spatial() * J[c + 1];
  return A;
}

Eigen::VectorXd HingeChain::momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  return momentum_matrix(kinematics(q, v, nullptr)) * v;
}

Eigen::MatrixXd HingeChain::momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                              double c_v, double c_q) const {
  Eigen::MatrixXd JP = c_v * momentum_matrix(kinematics(q, v, nullptr));
  if (c_q != 0) {
    const double h = 1e-7;
    for (int j = 0; j < nv_; ++j) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
      JP.col(j) += c_q * (momentum(retract(q, h * e), v) - momentum(retract(q, -h * e), v)) / (2 * h);
    }
  }
  return JP;
}

Eigen::VectorXd HingeChain::gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) const {
  std::vector<double> g;
  for (int c = 0; c < num_hinges(); ++c) {
    if (!hinges_[c].lock) continue;
    double stop = 0, latch = 0;
    joint::lock_events(*hinges_[c].lock, lock_history_[c], q(iq_theta_ + c), v(iv_theta_ + c), &stop, &latch);
    g.push_back(stop);
    g.push_back(latch);
  }
  return Eigen::Map<const Eigen::VectorXd>(g.data(), static_cast<Eigen::Index>(g.size()));
}

void HingeChain::accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) const {
  for (int c = 0; c < num_hinges(); ++c)
    if (hinges_[c].lock)
      joint::update_lock_history(*hinges_[c].lock, lock_history_[c], q(iq_theta_ + c), v(iv_theta_ + c));
}

void HingeChain::reset_history() const { lock_history_.assign(hinges_.size(), {}); }

HingeChain::Outputs HingeChain::outputs(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) const {
  const Kin k = kinematics(q, v, nullptr);
  const int N = num_hinges();
  Outputs o;
  o.theta = q.segment(iq_theta_, N);
  o.theta_rate = v.segment(iv_theta_, N);
  o.spring_torque.resize(N);
  o.lock_force = o.lock_torque = o.latched = Eigen::VectorXd::Zero(N);
  o.potential = 0;
  o.kinetic = 0;
  for (int c = 0; c < N; ++c) {
    const ChainHingeSpec& h = hinges_[c];
    const double th = o.theta(c);
    o.spring_torque(c) = h.tau0 - h.k_theta * th;
    o.potential += -h.tau0 * th + 0.5 * h.k_theta * th * th;
    if (h.lock) {
      const auto L = joint::lock_load(*h.lock, lock_history_[c], th, o.theta_rate(c));
      o.lock_force(c) = std::max(L.normal_force, 0.0);
      o.lock_torque(c) = L.torque;
      o.latched(c) = lock_history_[c].latched ? 1.0 : 0.0;
    }
    o.kinetic += h.body.kinetic_energy(k.links[c].V, k.links[c].w);
  }
  const Eigen::VectorXd Pi = momentum_matrix(k) * v;
  o.P_W = Pi.head<3>();
  o.H_W = Pi.tail<3>();
  o.P_base_W.setZero();
  o.H_base_W.setZero();
  if (base_.free) {
    const BaseMotion& b = k.base;
    const Eigen::Matrix<double, 6, 1> pb = to_world(b.R_WB, b.r_W) * base_.inertia.momentum(b.V_B, b.w_B);
    o.P_base_W = pb.head<3>();
    o.H_base_W = pb.tail<3>();
    o.kinetic += base_.inertia.kinetic_energy(b.V_B, b.w_B);
  }
  return o;
}

std::pair<Eigen::MatrixXd, Eigen::MatrixXd> HingeChain::frames(const Eigen::VectorXd& q) const {
  const Kin k = kinematics(q, Eigen::VectorXd::Zero(nv_), nullptr);
  Eigen::MatrixXd R(3, 3 * num_hinges()), o(3, num_hinges());
  for (int c = 0; c < num_hinges(); ++c) {
    R.middleCols<3>(3 * c) = k.links[c].R_WC;
    o.col(c) = k.links[c].o_W;
  }
  return {R, o};
}

}  // namespace deployfx::system
