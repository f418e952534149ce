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

// The motion of every body at one instant. Each link's quantities are in its own axes C, except
// the hinge's attachment (o, n, G_o, G_w: P axes).
struct HingeChain::Kin {
  BaseMotion base;
  struct Link {
    Eigen::Matrix3d R_PC, R_WC;
    Eigen::Vector3d o_W;          // C's origin, W
    Eigen::Vector3d o, n;         // C's origin and the hinge axis in P (deformed on a flexible parent)
    Eigen::Vector3d V, w, a, al;  // C's origin velocity and acceleration, angular velocity and acceleration
    double theta = 0, rate = 0, accel = 0;
    // On a flexible parent: the origin's velocity o' = G_o d'_P and the attachment's angular
    // velocity G_w d'_P relative to P (P axes; chain_attachment.hpp).
    Eigen::Matrix<double, 3, Eigen::Dynamic> G_o, G_w;
    // A flexible panel's elastic coordinates and rates, and the same on all its dofs (FlexibleBody::full).
    Eigen::VectorXd q_d, v_d, a_d, d, dd, ddd;
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
  const int N = num_hinges();
  for (int k = 0; k < N; ++k) check_spec("hinges[" + std::to_string(k) + "]", hinges_[k]);
  links_.resize(N);
  for (int k = 0; k < N; ++k) {
    const ChainHingeSpec& h = hinges_[k];
    Link& L = links_[k];
    L.rigid = h.body;
    if (!h.appendage) continue;
    const std::string name = "hinges[" + std::to_string(k) + "].appendage";
    const body::AppendageSpec& a = *h.appendage;
    // A reduced panel carrying the next hinge adds the static responses to unit loads at the
    // attachment node to its basis (chain_attachment.hpp): the child's hinge reaction.
    Eigen::MatrixXd attachment_loads;
    const bool reduced = a.fidelity == Fidelity::kReducedLinear || a.fidelity == Fidelity::kReducedNonlinear;
    if (reduced && a.model && k + 1 < N)
      attachment_loads = node_unit_loads(*a.model, nearest_node(*a.model, hinges_[k + 1].point_P));
    L.flex.emplace(a, name, attachment_loads);
    if (!L.flex->flexible()) {
      // The undeformed panel as a rigid body, merged with the rigid parts (parallel axes).
      const body::FloatingFrameInertia& ffi = L.flex->inertia();
      const double m = ffi.mass() + L.rigid.mass;
      const Eigen::Vector3d s = ffi.S0() + L.rigid.first_moment();
      const Eigen::Matrix3d J_O = ffi.J0() + L.rigid.inertia_origin();
      const Eigen::Vector3d c = s / m;
      L.rigid = {m, c, J_O - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose())};
      L.flex.reset();
    }
  }
  for (int k = 1; k < N; ++k)
    if (links_[k - 1].flex) {
      const body::FlexibleBody& parent = *links_[k - 1].flex;
      const Eigen::Vector3d& p = hinges_[k].point_P;
      links_[k].attach = make_attachment(parent, nearest_node(*parent.spec().model, p), p);
    }
  lock_history_.assign(hinges_.size(), {});
  iq_theta_ = base_.free ? kBasePositions : 0;
  iv_theta_ = base_.free ? kBaseVelocities : 0;
  nq_ = iq_theta_ + N;
  nv_ = iv_theta_ + N;
  for (Link& L : links_) {
    if (!L.flex) continue;
    L.n_d = L.flex->num_elastic();
    L.iq_d = nq_, L.iv_d = nv_;
    nq_ += L.n_d;
    nv_ += L.n_d;
  }
  // Hinge k's diagonal entry is the inertia about its axis of the bodies it carries: zero makes
  // M singular (a chain that ends in bodies without mass, say).
  const Eigen::MatrixXd M = mass_matrix(initial_positions());
  for (int k = 0; k < N; ++k)
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
  // Forward pass, parent P to child C, with the hinge point o, axis n, the attachment's angular
  // velocity w_att and acceleration al_att relative to P, and o's velocity o' and acceleration o''
  // relative to P (all P axes; o = point, n = axis and the rest zero on a rigid parent):
  //   V_C = R_CP (V_P + w_P x o + o'),  a_C = R_CP (a_P + al_P x o + w_P x (w_P x o) + 2 w_P x o' + o''),
  //   w_C = R_CP (w_P + w_rel),         al_C = R_CP (al_P + al_att + theta'' n + theta' w_att x n + w_P x w_rel),
  // w_rel = w_att + theta' n (the derivative of w_P + w_rel in W, in P axes).
  Eigen::Matrix3d R_WP = k.base.R_WB;
  Eigen::Vector3d o_P = k.base.r_W, V = k.base.V_B, w = k.base.w_B, acc = k.base.a_B, al = k.base.wd_B;
  for (int c = 0; c < num_hinges(); ++c) {
    const ChainHingeSpec& h = hinges_[c];
    const Link& B = links_[c];
    Kin::Link& L = k.links[c];
    L.theta = q(iq_theta_ + c);
    L.rate = v(iv_theta_ + c);
    L.accel = a ? (*a)(iv_theta_ + c) : 0.0;
    if (B.flex) {
      L.q_d = q.segment(B.iq_d, B.n_d);
      L.v_d = v.segment(B.iv_d, B.n_d);
      L.a_d = a ? Eigen::VectorXd(a->segment(B.iv_d, B.n_d)) : Eigen::VectorXd::Zero(B.n_d);
      L.d = B.flex->full(L.q_d);
      L.dd = B.flex->full(L.v_d);
      L.ddd = B.flex->full(L.a_d);
    }
    Eigen::Matrix3d R_att = Eigen::Matrix3d::Identity();
    Eigen::Vector3d o_rate = Eigen::Vector3d::Zero(), o_acc = Eigen::Vector3d::Zero();
    Eigen::Vector3d w_att = Eigen::Vector3d::Zero(), al_att = Eigen::Vector3d::Zero();
    L.o = h.point_P;
    if (B.attach) {
      const Kin::Link& P = k.links[c - 1];
      AttachmentMotion m = attachment_motion(*B.attach, P.q_d, P.v_d, &P.a_d);
      R_att = m.R_att, L.o = m.o, o_rate = m.o_rate, o_acc = m.o_accel, w_att = m.w_att, al_att = m.al_att;
      L.G_o = std::move(m.G_o);
      L.G_w = std::move(m.G_w);
    }
    const Eigen::Vector3d& p = L.o;
    L.n = R_att * h.axis_P;
    const Eigen::Vector3d& n = L.n;
    L.R_PC = R_att * Eigen::AngleAxisd(L.theta, h.axis_P).toRotationMatrix() * h.R_PC0;
    const Eigen::Matrix3d R_CP = L.R_PC.transpose();
    const Eigen::Vector3d w_rel = w_att + L.rate * n;
    L.R_WC = R_WP * L.R_PC;
    L.o_W = o_P + R_WP * p;
    L.V = R_CP * (V + w.cross(p) + o_rate);
    L.a = R_CP * (acc + al.cross(p) + w.cross(w.cross(p)) + 2.0 * w.cross(o_rate) + o_acc);
    L.w = R_CP * (w + w_rel);
    L.al = R_CP * (al + al_att + L.accel * n + L.rate * w_att.cross(n) + w.cross(w_rel));
    R_WP = L.R_WC, o_P = L.o_W, V = L.V, w = L.w, acc = L.a, al = L.al;
  }
  return k;
}

Eigen::VectorXd HingeChain::inertial_residual(const Kin& k) const {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(nv_);
  // Backward pass: (F, M) is the inertial wrench of bodies c..N-1 about C_c's origin, C_c axes.
  // Virtual power of theta'_c: its twist turns them all about hinge c's axis n through o, so the
  // generalized inertial force is n . M (P axes); the springs, dampers and locks are tau. Of a
  // parent's d'_P: it moves o by G_o d'_P and turns the attachment by G_w d'_P, so the subtree
  // adds G_o^T F + G_w^T M (P axes) to the parent's elastic rows; of a panel's own d'_c: Q.
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), M = Eigen::Vector3d::Zero();
  for (int c = num_hinges() - 1; c >= 0; --c) {
    const ChainHingeSpec& h = hinges_[c];
    const Link& B = links_[c];
    const Kin::Link& L = k.links[c];
    const auto f = B.rigid.inertial_forces(L.a, L.al, L.w);
    F += f.head<3>();
    M += f.tail<3>();
    if (B.flex) {  // Shabana Ch. 5; docs/engine-design.md "Body-level equations"
      const auto fe = B.flex->inertia().inertial_forces(L.a, L.al, L.w, L.d, L.dd, L.ddd);
      F += fe.F;
      M += fe.M;
      const std::vector<int>& free = B.flex->free_dofs();
      for (int i = 0; i < B.n_d; ++i) r(B.iv_d + i) += fe.Q(free[i]);
    }
    const Eigen::Vector3d F_P = L.R_PC * F, M_P = L.R_PC * M;
    double tau = h.tau0 - h.k_theta * L.theta - h.c_theta * L.rate;
    if (h.lock) tau += joint::lock_load(*h.lock, lock_history_[c], L.theta, L.rate).torque;
    r(iv_theta_ + c) = L.n.dot(M_P) - tau;
    if (B.attach) {
      const Link& P = links_[c - 1];
      r.segment(P.iv_d, P.n_d) += L.G_o.transpose() * F_P + L.G_w.transpose() * M_P;
    }
    F = F_P;  // into P, about P's origin: the wrench the parent carries
    M = L.o.cross(F_P) + M_P;
  }
  if (base_.free) {  // virtual power of v_W (W axes) and w_B (B axes)
    const BaseMotion& b = k.base;
    const auto fb = base_.inertia.inertial_forces(b.a_B, b.wd_B, b.w_B);
    r.head<3>() = b.R_WB * (fb.head<3>() + F);
    r.segment<3>(3) = fb.tail<3>() + M;
  }
  return r;
}

Eigen::VectorXd HingeChain::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& a, double) const {
  const Kin k = kinematics(q, v, &a);
  Eigen::VectorXd r = inertial_residual(k);
  for (int c = 0; c < num_hinges(); ++c) {  // the internal force and Rayleigh damping
    const Link& B = links_[c];
    const Kin::Link& L = k.links[c];
    if (B.flex) B.flex->add_elastic_force(L.q_d, L.v_d, L.d, L.dd, r.segment(B.iv_d, B.n_d));
  }
  return r;
}

std::vector<Eigen::MatrixXd> HingeChain::jacobians(const Kin& k) const {
  // J_C = X_CP J_P + [R_CP G_o; R_CP G_w] e_d_P + [0; R_CP n] e_theta_c, X_CP = [R_CP, -R_CP o~;
  // 0, R_CP] (the forward pass's velocity relations); the base's J_B = [R_WB^T 0; 0 I] (zero for
  // a fixed base).
  std::vector<Eigen::MatrixXd> J(hinges_.size() + 1, Eigen::MatrixXd::Zero(6, nv_));
  if (base_.free) {
    J[0].block<3, 3>(0, 0) = k.base.R_WB.transpose();
    J[0].block<3, 3>(3, 3).setIdentity();
  }
  for (int c = 0; c < num_hinges(); ++c) {
    const Kin::Link& L = k.links[c];
    const Eigen::Matrix3d R_CP = L.R_PC.transpose();
    const Eigen::MatrixXd& P = J[c];
    J[c + 1].topRows<3>() = R_CP * (P.topRows<3>() - skew(L.o) * P.bottomRows<3>());
    J[c + 1].bottomRows<3>() = R_CP * P.bottomRows<3>();
    J[c + 1].block<3, 1>(3, iv_theta_ + c) += R_CP * L.n;
    if (links_[c].attach) {
      const Link& Pl = links_[c - 1];
      J[c + 1].block(0, Pl.iv_d, 3, Pl.n_d) += R_CP * L.G_o;
      J[c + 1].block(3, Pl.iv_d, 3, Pl.n_d) += R_CP * L.G_w;
    }
  }
  return J;
}

Eigen::MatrixXd HingeChain::link_inertia(const Kin& k, int c) const {
  // The kinetic energy of link c is 1/2 y^T M_c y, y = (V, w, d'): the rigid parts' spatial
  // inertia plus a panel's floating-frame inertia (FloatingFrameInertia: its T in the header),
  //   [ m I    -s(d)~   S1   ]
  //   [ s(d)~   J(d)    H(d) ]
  //   [ S1^T    H(d)^T  L_c  ],  on the free dofs.
  const Link& B = links_[c];
  Eigen::MatrixXd Mc = Eigen::MatrixXd::Zero(6 + B.n_d, 6 + B.n_d);
  Mc.topLeftCorner<6, 6>() = B.rigid.spatial();
  if (!B.flex) return Mc;
  const Kin::Link& L = k.links[c];
  const body::FloatingFrameInertia& ffi = B.flex->inertia();
  const Eigen::Matrix3d S = skew(ffi.first_moment(L.d));
  Mc.block<3, 3>(0, 0) += ffi.mass() * Eigen::Matrix3d::Identity();
  Mc.block<3, 3>(0, 3) -= S;
  Mc.block<3, 3>(3, 0) += S;
  Mc.block<3, 3>(3, 3) += ffi.inertia_tensor(L.d);
  const Eigen::Matrix<double, 3, Eigen::Dynamic> H = ffi.rotation_coupling(L.d);
  const std::vector<int>& free = B.flex->free_dofs();
  for (int i = 0; i < B.n_d; ++i) {
    Mc.block<3, 1>(0, 6 + i) = ffi.S1().col(free[i]);
    Mc.block<3, 1>(3, 6 + i) = H.col(free[i]);
  }
  Mc.bottomLeftCorner(B.n_d, 6) = Mc.topRightCorner(6, B.n_d).transpose();
  Mc.bottomRightCorner(B.n_d, B.n_d) = Eigen::MatrixXd(B.flex->mass());
  return Mc;
}

Eigen::MatrixXd HingeChain::link_jacobian(const Eigen::MatrixXd& J, int c) const {
  const Link& B = links_[c];
  Eigen::MatrixXd Jc = Eigen::MatrixXd::Zero(6 + B.n_d, nv_);
  Jc.topRows<6>() = J;
  for (int i = 0; i < B.n_d; ++i) Jc(6 + i, B.iv_d + i) = 1.0;
  return Jc;
}

Eigen::MatrixXd HingeChain::mass_matrix(const Eigen::VectorXd& q) const {
  const Kin k = kinematics(q, Eigen::VectorXd::Zero(nv_), nullptr);
  const std::vector<Eigen::MatrixXd> J = jacobians(k);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(nv_, nv_);
  if (base_.free) M += J[0].transpose() * base_.inertia.spatial() * J[0];
  for (int c = 0; c < num_hinges(); ++c) {
    const Eigen::MatrixXd Jc = link_jacobian(J[c + 1], c);
    M += Jc.transpose() * link_inertia(k, c) * Jc;
  }
  return M;
}

integrate::BlockMatrix HingeChain::iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                    const Eigen::VectorXd& a, double, double c_a,
                                                    double c_v, double c_q) const {
  Eigen::MatrixXd S = c_a * mass_matrix(q);
  // The inertial, spring, damper and lock forces' c_v d/dv + c_q d/dq, column j at once as the
  // central difference along (dq, dv) = (c_q, c_v) e_j (the configuration along retract()), with
  // steps of 1e-7 (rad, m) in q and 1e-7 max(1, |v_j|) in v for the larger of the two. Cheap: a
  // few bodies, and the reduced panels' forces on their projected integrals.
  auto r_in = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
    return inertial_residual(kinematics(qq, vv, &a));
  };
  for (int j = 0; (c_v != 0 || c_q != 0) && j < nv_; ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv_, j);
    const double s = 1e-7 / std::max(std::abs(c_q), std::abs(c_v) / std::max(1.0, std::abs(v(j))));
    const Eigen::VectorXd dq = (s * c_q) * e, dv = (s * c_v) * e;
    S.col(j) += (r_in(retract(q, dq), v + dv) - r_in(retract(q, -dq), v - dv)) / (2 * s);
  }
  // Each panel's internal force and damping, analytic (its own coordinates only).
  for (const Link& B : links_)
    if (B.flex)
      S.block(B.iv_d, B.iv_d, B.n_d, B.n_d) += B.flex->elastic_tangent(q.segment(B.iq_d, B.n_d), c_v, c_q);
  return integrate::BlockMatrix::from_dense(std::move(S));
}

Eigen::MatrixXd HingeChain::momentum_matrix(const Kin& k) const {
  // Pi = sum_b T_b M_b J_b v (the body momenta about their origins, the first six rows of
  // M_c y, to W).
  const std::vector<Eigen::MatrixXd> J = jacobians(k);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, nv_);
  if (base_.free) A += to_world(k.base.R_WB, k.base.r_W) * base_.inertia.spatial() * J[0];
  for (int c = 0; c < num_hinges(); ++c)
    A += to_world(k.links[c].R_WC, k.links[c].o_W) * link_inertia(k, c).topRows<6>() *
         link_jacobian(J[c + 1], c);
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

double HingeChain::newton_step_limit(const Eigen::VectorXd&, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& dv) const {
  double limit = 1.0;
  for (int c = 0; c < num_hinges(); ++c)
    if (hinges_[c].lock)
      limit = std::min(limit, joint::friction_step_limit(*hinges_[c].lock, lock_history_[c], v(iv_theta_ + c),
                                                         dv(iv_theta_ + c)));
  return limit;
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
  o.lock_force = o.lock_torque = o.latched = o.strain_energy = Eigen::VectorXd::Zero(N);
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
    const Link& B = links_[c];
    const Kin::Link& L = k.links[c];
    o.kinetic += B.rigid.kinetic_energy(L.V, L.w);
    if (B.flex) {
      o.kinetic += B.flex->inertia().kinetic_energy(L.V, L.w, L.d, L.dd);
      o.strain_energy(c) = B.flex->strain_energy(L.q_d, L.d);
      o.potential += o.strain_energy(c);
    }
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
