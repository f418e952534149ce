#include "deployfx/multibody/momentum.hpp"

#include <algorithm>
#include <stdexcept>

#include "deployfx/multibody/seeds.hpp"

namespace deployfx::multibody {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// A body's momentum (p; h about its origin, its axes) to W: (R p; o x (R p) + R h).
template <class S>
Vector6<S> to_world(const Matrix3<S>& R, const Vector3<S>& o, const Vector6<S>& p) {
  Vector6<S> out;
  out.template head<3>() = R * p.template head<3>();
  out.template tail<3>() = o.cross(Vector3<S>(out.template head<3>())) + R * p.template tail<3>();
  return out;
}

// Body k's momentum as ME (V; w) + e: ME its spatial inertia at the staged d (rigid parts and
// panel: [m I, -s~; s~, J(d)]), e the panel's elastic part (S1 d'; H(d) d').
Matrix6d spatial_inertia(const Model& m, Data& d, int k, Vector6<double>* e) {
  const Body& b = m.body(k);
  Matrix6d ME = b.rigid.spatial();
  e->setZero();
  if (!b.panel) return ME;
  const body::FloatingFrameInertia& ffi = b.panel->inertia();
  const PanelState& s = d.elastic[k];
  auto* memo = &d.panels[k].products;
  const Eigen::Matrix3d S = skew(ffi.first_moment(s.d));
  ME.topLeftCorner<3, 3>() += ffi.mass() * Eigen::Matrix3d::Identity();
  ME.block<3, 3>(0, 3) -= S;
  ME.block<3, 3>(3, 0) += S;
  ME.bottomRightCorner<3, 3>() += ffi.inertia_tensor(s.d, memo);
  *e << ffi.S1() * s.dd, ffi.rotation_coupling(s.d, memo) * s.dd;
  return ME;
}

Vector6<double> velocity(const BodyMotion<double>& C) {
  Vector6<double> nu;
  nu << C.V, C.w;
  return nu;
}

}  // namespace

Vector6<double> body_momentum(const Model& m, Data& d, int k) {
  Vector6<double> e;
  const Matrix6d ME = spatial_inertia(m, d, k, &e);
  return ME * velocity(d.motion.body[k]) + e;
}

Vector6<double> base_momentum(const Model& m, const Data& d) {
  if (!m.base_free()) return Vector6<double>::Zero();
  const BaseMotion<double>& b = d.motion.base;
  return to_world<double>(b.R_WB, b.r_W, m.spec().base.inertia.momentum(b.V_B, b.w_B));
}

Eigen::VectorXd momentum(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
  forward_kinematics(m, d, q, v, nullptr, t);
  Vector6<double> Pi = base_momentum(m, d);
  for (int k = 0; k < m.num_hinges(); ++k) {
    const BodyMotion<double>& C = d.motion.body[k];
    Pi += to_world<double>(C.R_WC, C.o_W, body_momentum(m, d, k));
  }
  return Pi;
}

Eigen::Matrix<double, 6, 6> base_velocity_jacobian(const Model& m, Data& d, const Eigen::VectorXd& q,
                                                   const Eigen::VectorXd& v, double t) {
  forward_kinematics(m, d, q, v, nullptr, t);  // only the positions are read
  // X = [R 0; o~ R R] carries a body's momentum (its axes, about its origin) to W about W's
  // origin; X^T its velocity the other way.
  auto congruence = [](const Matrix6d& M, const Eigen::Matrix3d& R, const Eigen::Vector3d& o) {
    Matrix6d X = Matrix6d::Zero();
    X.topLeftCorner<3, 3>() = R;
    X.bottomLeftCorner<3, 3>() = skew(o) * R;
    X.bottomRightCorner<3, 3>() = R;
    return Matrix6d(X * M * X.transpose());
  };
  const BaseMotion<double>& b = d.motion.base;
  Matrix6d I_O = congruence(m.spec().base.inertia.spatial(), b.R_WB, b.r_W);
  for (int k = 0; k < m.num_hinges(); ++k) {
    Vector6<double> e;
    const BodyMotion<double>& C = d.motion.body[k];
    I_O += congruence(spatial_inertia(m, d, k, &e), C.R_WC, C.o_W);
  }
  Matrix6d T = Matrix6d::Zero();  // (v_W, w_B) -> (velocity of the point at W's origin, w), W axes
  T.topLeftCorner<3, 3>().setIdentity();
  T.topRightCorner<3, 3>() = skew(b.r_W) * b.R_WB;
  T.bottomRightCorner<3, 3>() = b.R_WB;
  return I_O * T;
}

void MomentumTangent::prepare(const Model& m, Data& d) {
  const int N = m.num_hinges();
  ME.resize(N);
  p.resize(N);
  for (int k = 0; k < N; ++k) {
    Vector6<double> e;
    ME[k] = spatial_inertia(m, d, k, &e);
    p[k] = ME[k] * velocity(d.motion.body[k]) + e;
  }
  Mb = m.spec().base.inertia.spatial();
  const BaseMotion<double>& b = d.motion.base;
  pb << b.V_B, b.w_B;
  pb = (Mb * pb).eval();
}

Eigen::Matrix<double, 6, Eigen::Dynamic> MomentumTangent::tangents(const Model& m, const BaseMotion<Dual>& base,
                                                                   const TreeMotion<Dual>& motion, int count) const {
  // Each body's momentum is linear in its (V, w) for the staged d, d': its tangent is M (V, w)'.
  auto body = [&](const Matrix6d& M, const Vector6<double>& p, const Vector3<Dual>& V, const Vector3<Dual>& w) {
    Vector6<Dual> x = dual(p);
    Vector6<double> nu;
    for (int j = 0; j < count; ++j) {
      nu << multibody::tangent(V, j), multibody::tangent(w, j);
      seed(x, j, Vector6<double>(M * nu));
    }
    return x;
  };
  Vector6<Dual> Pi = Vector6<Dual>::Zero();
  if (m.base_free()) Pi += to_world<Dual>(base.R_WB, base.r_W, body(Mb, pb, base.V_B, base.w_B));
  for (int k = 0; k < m.num_hinges(); ++k) {
    const BodyMotion<Dual>& C = motion.body[k];
    Pi += to_world<Dual>(C.R_WC, C.o_W, body(ME[k], p[k], C.V, C.w));
  }
  Eigen::Matrix<double, 6, Eigen::Dynamic> T(6, count);
  for (int j = 0; j < count; ++j) T.col(j) = multibody::tangent(Pi, j);
  return T;
}

Eigen::MatrixXd momentum_columns(const Model& m, Data& d, const Eigen::MatrixXd& T, double c_v, double c_q,
                                 const Eigen::MatrixXd* T_rate) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, m.num_velocities());
  J.leftCols(m.border()) = T.leftCols(m.border());
  for (int k = 0; k < m.num_hinges(); ++k) {
    const Body& b = m.body(k);
    if (!b.attachment) continue;
    const Body& parent = m.body(b.parent);
    if (b.attachment->manifold) {  // through z = P g(q), z' = P G q' (FlexibleBody::chain)
      if (!T_rate) throw std::logic_error("momentum_columns: a hinge on a manifold panel needs T_rate");
      const Attachment& att = *b.attachment;
      const int seed = m.attachment_seed(k);
      J.middleCols(parent.iv_el, parent.n_el) +=
          parent.panel->chain(d.elastic[b.parent], T.middleCols(seed, 6) * att.P,
                              c_q * T_rate->middleCols(seed, 6) * att.P, Eigen::MatrixXd());
      continue;
    }
    const Eigen::MatrixXd Jz = T.middleCols(m.attachment_seed(k), 6) * b.attachment->P_cols;
    for (std::size_t i = 0; i < b.attachment->cols.size(); ++i)
      J.col(parent.iv_el + b.attachment->cols[i]) += Jz.col(static_cast<Eigen::Index>(i));
  }
  // Each panel's own coordinates: d(p, h)/d(d', d) = c_v (S1, H(d)) + c_q (w~ S1,
  // -V~ S1 + d(J(d) w)/dd + d(H(d) d')/dd), carried to W, then to the elastic coordinates through
  // the staging (FlexibleBody::chain; on the manifold d' = G q' also moves with q: c_q (S1, H(d))
  // C(q', .)).
  for (int k : m.panels()) {
    const Body& b = m.body(k);
    const body::FloatingFrameInertia& ffi = b.panel->inertia();
    const PanelState& s = d.elastic[k];
    const BodyMotion<double>& C = d.motion.body[k];
    auto* memo = &d.panels[k].products;
    const auto& S1 = ffi.S1();
    auto to_world = [&](const Eigen::MatrixXd& dp, const Eigen::MatrixXd& dh) {
      Eigen::MatrixXd X(6, dp.cols());
      X.topRows<3>() = C.R_WC * dp;
      X.bottomRows<3>() = skew(C.o_W) * X.topRows<3>() + C.R_WC * dh;
      return X;
    };
    const Eigen::MatrixXd dp = c_v * S1 + c_q * skew(C.w) * S1;
    const Eigen::MatrixXd dh = c_v * ffi.rotation_coupling(s.d, memo) +
                               c_q * (-skew(C.V) * S1 + ffi.inertia_tensor_jacobian(s.d, C.w, memo) +
                                      ffi.rotation_coupling_jacobian(s.dd, memo));
    const Eigen::MatrixXd W_v =
        b.panel->manifold() ? Eigen::MatrixXd(c_q * to_world(S1, ffi.rotation_coupling(s.d, memo))) : Eigen::MatrixXd();
    J.middleCols(b.iv_el, b.n_el) += b.panel->chain(s, to_world(dp, dh), W_v, Eigen::MatrixXd());
  }
  return J;
}

Eigen::MatrixXd momentum_jacobian(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                  double c_v, double c_q) {
  forward_kinematics(m, d, q, v, nullptr, d.t);
  MomentumTangent pass;
  pass.prepare(m, d);
  // Border and attachment coordinates: derivative passes of the kinematics (no accelerations).
  const std::vector<Seed>& seeds = m.seeds();
  BaseMotion<Dual>& base = d.pass.base;
  std::vector<JointState<Dual>>& joints = d.pass.joints;
  TreeMotion<Dual>& motion = d.pass.motion;
  const int nc = static_cast<int>(seeds.size());
  Eigen::MatrixXd T(6, nc);
  for (int first = 0; first < nc; first += kDualDirections) {
    const int count = std::min(kDualDirections, nc - first);
    seeded_state(m, d, first, count, c_q, c_v, 0.0, base, joints);
    forward_kinematics<Dual>(m, base, joints, motion);
    T.middleCols(first, count) = pass.tangents(m, base, motion, count);
  }
  // A hinge on a manifold panel: its seeds' tangents along z' alone (momentum_columns).
  Eigen::MatrixXd T_rate;
  for (int k = 0; k < m.num_hinges(); ++k) {
    if (!m.body(k).attachment || !m.body(k).attachment->manifold) continue;
    if (!T_rate.size()) T_rate = Eigen::MatrixXd::Zero(6, nc);
    const int seed = m.attachment_seed(k);
    seeded_state(m, d, seed, 6, 0.0, 1.0, 0.0, base, joints);
    forward_kinematics<Dual>(m, base, joints, motion);
    T_rate.middleCols(seed, 6) = pass.tangents(m, base, motion, 6);
  }
  return momentum_columns(m, d, T, c_v, c_q, T_rate.size() ? &T_rate : nullptr);
}

}  // namespace deployfx::multibody
