#include "deployfx/multibody/newton_matrix.hpp"

#include <algorithm>

#include "deployfx/body/rigid_force_jacobian.hpp"
#include "deployfx/multibody/forces.hpp"
#include "deployfx/multibody/momentum.hpp"
#include "deployfx/multibody/seeds.hpp"

namespace deployfx::multibody {
namespace {

using Matrix69 = Eigen::Matrix<double, 6, 9>;

// The attachments a wrench at body j passes on its way to the base: j's and its ancestors'.
std::vector<int> attachments_above(const Model& m, int j) {
  std::vector<int> out;
  if (m.body(j).attachment) out.push_back(j);
  for (int a : m.body(j).ancestors)
    if (m.body(a).attachment) out.push_back(a);
  return out;
}

// Panel j's own elastic block at the staged state: c_a L_c + c_v 2 G_y(w) + c_q (G_y(al) +
// G_w(w) + K_T) with damping (FlexibleBody::elastic_block; Q: the force on a manifold panel's
// coordinates, unused on the others).
void panel_block(const Model& m, Data& d, int j, const Eigen::VectorXd& Q, double c_a, double c_v, double c_q,
                 Eigen::Ref<Eigen::VectorXd> vals) {
  const BodyMotion<double>& C = d.motion.body[j];
  m.body(j).panel->elastic_block(d.elastic[j], Q, C.w, C.al, c_a, c_v, c_q, vals, &d.panels[j]);
}

}  // namespace

bool refresh_panel_blocks(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                          const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q,
                          integrate::BlockMatrix& S) {
  if (m.panels().empty() || S.elastic() != m.elastic() || S.border() != m.border()) return false;
  const ElasticPattern& pattern = m.pattern();
  if (S.E.nonZeros() != pattern.matrix.nonZeros()) return false;
  for (int k = 0; k < m.num_hinges(); ++k)
    if (m.body(k).attachment) return false;  // a coupling may share the parent's slots
  for (int j : m.panels())
    if (m.body(j).panel->manifold()) return false;  // its block needs the whole force on eta
  forward_kinematics(m, d, q, v, &a, t);
  Eigen::VectorXd own;
  for (int j : m.panels()) {
    const Eigen::Index n = m.body(j).panel->block().nonzeros();
    if (pattern.identity) {  // the panel's block is all of E, in its value order
      panel_block(m, d, j, Eigen::VectorXd(), c_a, c_v, c_q, Eigen::Map<Eigen::VectorXd>(S.E.valuePtr(), n));
      continue;
    }
    own.resize(n);
    panel_block(m, d, j, Eigen::VectorXd(), c_a, c_v, c_q, own);
    const std::vector<int>& slots = pattern.body_slots[j];  // no other term shares them (above)
    for (std::size_t i = 0; i < slots.size(); ++i) S.E.valuePtr()[slots[i]] = own(static_cast<Eigen::Index>(i));
  }
  return true;
}

integrate::BlockMatrix newton_matrix(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q,
                                     Eigen::MatrixXd* momentum_jacobian) {
  forward_kinematics(m, d, q, v, &a, t);
  const int N = m.num_hinges(), nb = m.border(), ne = m.elastic();

  // 1. Each body's wrench and its derivatives in its motion (a, al, w); the hinges' torques.
  std::vector<Vector6<double>> f(N);
  std::vector<Matrix69> G(N);
  std::vector<body::FloatingFrameInertia::ForceJacobians> fj(N);
  for (int k = 0; k < N; ++k) {
    const Body& b = m.body(k);
    const BodyMotion<double>& C = d.motion.body[k];
    f[k] = b.rigid.inertial_forces(C.a, C.al, C.w);
    G[k] = body::rigid_force_jacobian(b.rigid, C.w);
    if (!b.panel) continue;
    const PanelState& s = d.elastic[k];
    fj[k] = b.panel->inertia().inertial_force_jacobians(C.a, C.al, C.w, s.d, s.dd, s.ddd, &d.panels[k].products);
    f[k].head<3>() += fj[k].f.F;
    f[k].tail<3>() += fj[k].f.M;
    G[k] += fj[k].FM_k;
  }
  Vector6<double> fb = Vector6<double>::Zero();
  Matrix69 Gb = Matrix69::Zero();
  if (m.base_free()) {
    fb = base_inertial_wrench(m, d);
    Gb = body::rigid_force_jacobian(m.spec().base.inertia, d.motion.base.w_B);
  }
  // The attachments' generalized forces tau_z at the state (a manifold parent's block needs them).
  Wrenches<double> Wf;
  bool have_Wf = false;
  auto attach_forces = [&]() -> const std::vector<Vector6<double>>& {
    if (!have_Wf) backward_pass<double>(m, d.motion, f, Wf), have_Wf = true;
    return Wf.attach;
  };
  std::vector<HingeTorque> torque(N);
  for (int k = 0; k < N; ++k)
    if (m.body(k).iv_theta >= 0) torque[k] = hinge_torque(m, d, k);

  // 2. The derivative passes (seeds.hpp): the border rows' tangents BR, each panel's motion
  // tangent T9 = d(a, al, w) and each attachment's generalized force's tangent TZ, per column.
  const std::vector<Seed>& seeds = m.seeds();
  const int nc = static_cast<int>(seeds.size());
  const bool with_momentum = momentum_jacobian && c_v > 0;
  MomentumTangent momentum;
  Eigen::MatrixXd PT;  // the momentum's tangents, (6 x nc)
  if (with_momentum) {
    momentum.prepare(m, d);
    PT.resize(6, nc);
  }
  Eigen::MatrixXd BR = Eigen::MatrixXd::Zero(nb, nc);
  std::vector<Eigen::Matrix<double, 9, Eigen::Dynamic>> T9(N);
  std::vector<Eigen::Matrix<double, 6, Eigen::Dynamic>> TZ(N);
  for (int k : m.panels()) T9[k].resize(9, nc);
  for (int k = 0; k < N; ++k)
    if (m.body(k).attachment) TZ[k].resize(6, nc);
  BaseMotion<Dual>& base = d.pass.base;
  std::vector<JointState<Dual>>& joints = d.pass.joints;
  TreeMotion<Dual>& motion = d.pass.motion;
  Wrenches<Dual>& W = d.pass.wrenches;
  std::vector<Vector6<Dual>>& fd = d.pass.wrench;
  fd.resize(N);
  // One derivative pass over the seeds [first, first + count) with the coefficients (cq, cv, ca):
  // the border rows' tangents into BRo, the panels' motion tangents into T9o, the attachments'
  // generalized forces' into TZo, the momentum's into PTo (if not null), at columns col0 + j.
  using Tangents9 = std::vector<Eigen::Matrix<double, 9, Eigen::Dynamic>>;
  using Tangents6 = std::vector<Eigen::Matrix<double, 6, Eigen::Dynamic>>;
  auto pass = [&](int first, int count, double cq, double cv, double ca, Eigen::MatrixXd& BRo, Tangents9& T9o,
                  Tangents6& TZo, Eigen::MatrixXd* PTo, int col0) {
    seeded_state(m, d, first, count, cq, cv, ca, base, joints);
    forward_kinematics<Dual>(m, base, joints, motion);
    for (int k = 0; k < N; ++k) {
      const BodyMotion<Dual>& C = motion.body[k];
      fd[k] = dual(f[k]);
      for (int j = 0; j < count; ++j) {
        const Eigen::Matrix<double, 9, 1> t9 = motion_tangent(C.a, C.al, C.w, j);
        seed(fd[k], j, Vector6<double>(G[k] * t9));
        if (m.body(k).panel) T9o[k].col(col0 + j) = t9;
      }
    }
    backward_pass<Dual>(m, motion, fd, W);
    if (PTo) PTo->middleCols(col0, count) = momentum.tangents(m, base, motion, count);
    Vector6<Dual> fbd;
    if (m.base_free()) {
      fbd = dual(fb);
      for (int j = 0; j < count; ++j)
        seed(fbd, j, Vector6<double>(Gb * motion_tangent(base.a_B, base.wd_B, base.w_B, j)));
      fbd += W.root;
    }
    const Vector3<Dual> F_W = base.R_WB * fbd.head<3>();
    for (int j = 0; j < count; ++j) {
      const int col = col0 + j;
      if (m.base_free()) {
        BRo.block<3, 1>(0, col) = tangent(F_W, j);
        BRo.block<3, 1>(3, col) = tangent(Vector3<Dual>(fbd.tail<3>()), j);
      }
      for (int k = 0; k < N; ++k) {
        const Body& b = m.body(k);
        if (b.iv_theta >= 0)
          BRo(b.iv_theta, col) = W.hinge[k].d[j] - (torque[k].d_theta * joints[k].theta.d[j] +
                                                    torque[k].d_rate * joints[k].rate.d[j]);
        if (b.attachment) TZo[k].col(col) = tangent(W.attach[k], j);
      }
    }
  };
  for (int first = 0; first < nc; first += kDualDirections)  // kDualDirections columns a pass
    pass(first, std::min(kDualDirections, nc - first), c_q, c_v, c_a, BR, T9, TZ, with_momentum ? &PT : nullptr, first);
  // The elastic rows' tangents (ne x columns of T9o): each panel's dQ/d(a, al, w) T9 and the
  // attachments' P^T TZ (on a manifold parent G^T P^T TZ).
  auto elastic_rows = [&](const Tangents9& T9o, const Tangents6& TZo, Eigen::Index cols) {
    Eigen::MatrixXd Yo = Eigen::MatrixXd::Zero(ne, cols);
    for (int k : m.panels()) {
      const Body& b = m.body(k);
      Yo.middleRows(b.ie, b.n_el) = b.panel->projected(d.elastic[k], fj[k].Q_k) * T9o[k];
    }
    for (int k = 0; k < N; ++k) {
      const Body& b = m.body(k);
      if (!b.attachment) continue;
      const Attachment& att = *b.attachment;
      const Body& parent = m.body(b.parent);
      const Eigen::MatrixXd Z = force_on_parent(att, *parent.panel, d.elastic[b.parent], TZo[k]);
      for (std::size_t i = 0; i < att.parent_cols.size(); ++i)
        Yo.row(parent.ie + att.parent_cols[i]) += Z.row(static_cast<Eigen::Index>(i));
    }
    return Yo;
  };
  const Eigen::MatrixXd Y = elastic_rows(T9, TZ, nc);

  // A hinge on a manifold panel: its seeds' tangents along z' and z'' alone, [border; elastic]
  // rows (R_rate, R_accel), for the chain rule through z = P g(q) (step 3), and the momentum's
  // along z' (momentum_columns).
  std::vector<Eigen::MatrixXd> R_rate(N), R_accel(N);
  Eigen::MatrixXd PT_rate;
  for (int k = 0; k < N; ++k) {
    if (!m.body(k).attachment || !m.body(k).attachment->manifold) continue;
    const int seed = m.attachment_seed(k);
    for (int which = 0; which < 2; ++which) {
      Eigen::MatrixXd BRo = Eigen::MatrixXd::Zero(nb, 6), PTo;
      Tangents9 T9o(N);
      Tangents6 TZo(N);
      for (int j : m.panels()) T9o[j].resize(9, 6);
      for (int j = 0; j < N; ++j)
        if (m.body(j).attachment) TZo[j].resize(6, 6);
      const bool rate = which == 0;
      if (rate && with_momentum) PTo.resize(6, 6);
      pass(seed, 6, 0.0, rate ? 1.0 : 0.0, rate ? 0.0 : 1.0, BRo, T9o, TZo, PTo.size() ? &PTo : nullptr, 0);
      Eigen::MatrixXd R(nb + ne, 6);
      R << BRo, elastic_rows(T9o, TZo, 6);
      (rate ? R_rate : R_accel)[k] = std::move(R);
      if (PTo.size()) {
        if (!PT_rate.size()) PT_rate = Eigen::MatrixXd::Zero(6, nc);
        PT_rate.middleCols(seed, 6) = PTo;
      }
    }
  }

  if (with_momentum)
    *momentum_jacobian = momentum_columns(m, d, PT / c_v, 1.0, c_q / c_v, PT_rate.size() ? &PT_rate : nullptr);

  integrate::BlockMatrix S;
  S.A = BR.leftCols(nb);
  S.C = Y.leftCols(nb);
  S.B = Eigen::MatrixXd::Zero(nb, ne);
  if (ne == 0) {
    S.E.resize(0, 0);
    return S;
  }
  const ElasticPattern& pattern = m.pattern();
  Eigen::VectorXd Ev;
  if (!pattern.identity) Ev = Eigen::VectorXd::Zero(pattern.matrix.nonZeros());

  // 3. The attachment columns, into the parent panel's coordinates through z = P eta (on a
  // manifold parent through z = P g(q) by the chain rule, FlexibleBody::chain).
  for (int k = 0; k < N; ++k) {
    const Body& b = m.body(k);
    if (!b.attachment) continue;
    const Attachment& att = *b.attachment;
    const Body& parent = m.body(b.parent);
    const int p = parent.ie;
    const int seed = m.attachment_seed(k);
    Eigen::MatrixXd Ez;
    if (att.manifold) {
      Eigen::MatrixXd R(nb + ne, 6);
      R << BR.middleCols(seed, 6), Y.middleCols(seed, 6);
      const Eigen::MatrixXd Cq = parent.panel->chain(d.elastic[b.parent], R * att.P,
                                                     (c_q * R_rate[k] + 2.0 * c_v * R_accel[k]) * att.P,
                                                     c_q * R_accel[k] * att.P);
      S.B.middleCols(p, parent.n_el) += Cq.topRows(nb);
      Ez = Cq.bottomRows(ne);
    } else {
      const Eigen::MatrixXd Bz = BR.middleCols(seed, 6) * att.P_cols;
      Ez = Y.middleCols(seed, 6) * att.P_cols;
      for (std::size_t i = 0; i < att.cols.size(); ++i) S.B.col(p + att.cols[i]) += Bz.col(static_cast<Eigen::Index>(i));
    }
    const ElasticPattern::Coupling& cp = *pattern.couplings[k];
    for (std::size_t r = 0; r < cp.rows.size(); ++r)
      for (std::size_t j = 0; j < cp.cols.size(); ++j)
        Ev(cp.slots_RA(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j))) +=
            Ez(cp.rows[r], static_cast<Eigen::Index>(j));
  }

  // 4. Each panel's own coordinates: its wrench's derivatives carried up by the backward pass's
  // linear map (a unit wrench at body j to the border rows and the attachments above j), and its
  // elastic block.
  std::vector<Vector6<double>> unit(N);
  Wrenches<double> Wu;
  for (int j : m.panels()) {
    const Body& b = m.body(j);
    const auto& F = fj[j];
    const Eigen::MatrixXd FMe = b.panel->chain(d.elastic[j], c_a, F.FM_ddd, c_v, F.FM_dd, c_q, F.FM_d);
    const std::vector<int> above = attachments_above(m, j);
    Eigen::Matrix<double, Eigen::Dynamic, 6> Lb = Eigen::MatrixXd::Zero(nb, 6);
    std::vector<Eigen::Matrix<double, 6, 6>> Lz(above.size());
    for (int i = 0; i < 6; ++i) {
      std::fill(unit.begin(), unit.end(), Vector6<double>::Zero());
      unit[j](i) = 1.0;
      backward_pass<double>(m, d.motion, unit, Wu);
      if (m.base_free()) {
        Lb.block<3, 1>(0, i) = d.motion.base.R_WB * Wu.root.head<3>();
        Lb.block<3, 1>(3, i) = Wu.root.tail<3>();
      }
      for (int k = 0; k < N; ++k)
        if (m.body(k).iv_theta >= 0) Lb(m.body(k).iv_theta, i) = Wu.hinge[k];
      for (std::size_t c = 0; c < above.size(); ++c) Lz[c].col(i) = Wu.attach[above[c]];
    }
    S.B.middleCols(b.ie, b.n_el) += Lb * FMe;
    for (std::size_t c = 0; c < above.size(); ++c) {
      const Body& a = m.body(above[c]);
      const Attachment& att = *a.attachment;
      const ElasticPattern::Coupling& cp = *pattern.couplings[above[c]];
      const Eigen::MatrixXd Mz = force_on_parent(att, *m.body(a.parent).panel, d.elastic[a.parent], Lz[c] * FMe);
      const auto first = std::lower_bound(cp.rows.begin(), cp.rows.end(), b.ie) - cp.rows.begin();
      for (Eigen::Index i = 0; i < Mz.rows(); ++i)
        for (int jj = 0; jj < b.n_el; ++jj) Ev(cp.slots_AR(i, first + jj)) += Mz(i, jj);
    }

    // Elastic block (FlexibleBody::elastic_block). With the panel's block as the whole elastic
    // block, its values are formed in S.E itself.
    const fem::FreeBlock& block = b.panel->block();
    Eigen::VectorXd own;
    if (pattern.identity) {  // the pattern alone: elastic_block() writes every value
      const Eigen::SparseMatrix<double>& P = block.matrix();
      S.E.resize(P.rows(), P.cols());
      S.E.resizeNonZeros(P.nonZeros());
      std::copy(P.outerIndexPtr(), P.outerIndexPtr() + P.outerSize() + 1, S.E.outerIndexPtr());
      std::copy(P.innerIndexPtr(), P.innerIndexPtr() + P.nonZeros(), S.E.innerIndexPtr());
    } else {
      own.resize(block.nonzeros());
    }
    Eigen::Map<Eigen::VectorXd> vals(pattern.identity ? S.E.valuePtr() : own.data(), block.nonzeros());
    // On a manifold the block carries G^T's own derivative contracted with the whole force on
    // eta, the children's attachment forces P^T tau_z among it (residual()).
    Eigen::VectorXd Q_eta;
    if (b.panel->manifold()) {
      Q_eta = F.f.Q;
      for (int k : b.children)
        if (m.body(k).attachment) Q_eta += m.body(k).attachment->P.transpose() * attach_forces()[k];
    }
    panel_block(m, d, j, b.panel->manifold() ? Q_eta : F.f.Q, c_a, c_v, c_q, vals);
    if (!pattern.identity) {
      const std::vector<int>& slots = pattern.body_slots[j];
      for (std::size_t i = 0; i < slots.size(); ++i) Ev(slots[i]) += vals(static_cast<Eigen::Index>(i));
    }
  }
  if (!pattern.identity) {
    S.E = pattern.matrix;
    std::copy(Ev.data(), Ev.data() + Ev.size(), S.E.valuePtr());
  }
  return S;
}

}  // namespace deployfx::multibody
