#include "deployfx/body/floating_frame_inertia.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deployfx/math/so3.hpp"
#include "deployfx/math/sparse_rows.hpp"

namespace deployfx::body {

using fem::kElementDofs;
using fem::kNodeDofs;

FloatingFrameInertia::FloatingFrameInertia(const fem::ShellModel& model) : M_(model.mass()) {
  // The mesh's mass matrix is stored on the node-block pattern of its stiffness, 72 % zeros (the
  // consistent mass couples like components only): M_ keeps its nonzeros alone, so the products
  // with it (the inertial force's M ddd once per residual) do 28 % of the work for the same sums.
  M_.prune([](Eigen::Index, Eigen::Index, double value) { return value != 0.0; });
  M_rows_ = M_;
  const int n = model.num_dofs();
  S0_.setZero();
  E0_.setZero();
  S1_.setZero(3, n);
  C_.setZero(9, n);
  std::array<std::vector<Eigen::Triplet<double>>, 9> t;
  for (int e = 0; e < model.num_elements(); ++e) {
    const fem::ShellElement& el = model.elements()[e];
    const double I0 = el.I0(), I1 = el.I1(), I2 = el.I2();
    // Global dof of each element dof.
    std::array<int, kElementDofs> dof;
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < kNodeDofs; ++k) dof[kNodeDofs * a + k] = kNodeDofs * model.quads()(e, a) + k;
    for (int q = 0; q < 4; ++q) {
      const fem::ShellElement::Kinematics g = el.kinematics(q);
      const double w = g.weight;
      const Eigen::Vector3d& X = g.X_W;
      const Eigen::Vector3d& nv = g.n_W;
      // Through the thickness, P = X + z n and N = N0 + z N1: int rho (a + b z + c z^2) dz =
      // I0 a + I1 b + I2 c.
      m_ += w * I0;
      S0_ += w * (I0 * X + I1 * nv);
      E0_ += w * (I0 * X * X.transpose() + I1 * (X * nv.transpose() + nv * X.transpose()) +
                  I2 * nv * nv.transpose());
      const Eigen::Matrix<double, 3, kElementDofs> S1e = w * (I0 * g.N0 + I1 * g.N1);
      for (int i = 0; i < 3; ++i) {
        const Eigen::Matrix<double, 3, kElementDofs> Ci =
            w * (I0 * X(i) * g.N0 + I1 * (X(i) * g.N1 + nv(i) * g.N0) + I2 * nv(i) * g.N1);
        for (int c = 0; c < kElementDofs; ++c) {
          for (int j = 0; j < 3; ++j) C_(3 * i + j, dof[c]) += Ci(j, c);
          S1_(i, dof[c]) += S1e(i, c);
        }
        for (int j = 0; j < 3; ++j) {
          const Eigen::Matrix<double, kElementDofs, kElementDofs> Me =
              w * (I0 * g.N0.row(i).transpose() * g.N0.row(j) +
                   I1 * (g.N0.row(i).transpose() * g.N1.row(j) + g.N1.row(i).transpose() * g.N0.row(j)) +
                   I2 * g.N1.row(i).transpose() * g.N1.row(j));
          for (int r = 0; r < kElementDofs; ++r)
            for (int c = 0; c < kElementDofs; ++c)
              if (Me(r, c) != 0.0) t[3 * i + j].emplace_back(dof[r], dof[c], Me(r, c));
        }
      }
    }
  }
  for (int k = 0; k < 9; ++k) {
    Mij_[k].resize(n, n);
    Mij_[k].setFromTriplets(t[k].begin(), t[k].end());
  }
  for (int i = 0; i < 3; ++i) Mii_rows_[i] = Mij_[4 * i];
  node_mass_ = node_mass(model);
}

FloatingFrameInertia FloatingFrameInertia::projected(const Eigen::MatrixXd& Phi) const {
  if (Phi.rows() != num_dofs())
    throw std::invalid_argument("projected: the basis must have " + std::to_string(num_dofs()) + " rows");
  FloatingFrameInertia p;
  p.m_ = m_;
  p.S0_ = S0_;
  p.E0_ = E0_;
  p.S1_ = S1_ * Phi;
  p.C_ = C_ * Phi;
  // Dense r x r, stacked: the nine products with them are one dense matrix-vector product.
  p.dense_ = true;
  const Eigen::Index r = Phi.cols(), n = num_dofs();
  p.Mij_stacked_.resize(9 * r, r);
  for (int k = 0; k < 9; ++k) {
    if (dense_) p.Mij_stacked_.middleRows(k * r, r) = Phi.transpose() * Mij_stacked_.middleRows(k * n, n) * Phi;
    else p.Mij_stacked_.middleRows(k * r, r) = Phi.transpose() * (Mij_[k] * Phi);
  }
  const Eigen::MatrixXd M = Phi.transpose() * (M_ * Phi);
  p.M_ = M.sparseView(0.0, 0.0);  // keep every nonzero
  p.M_dense_ = M;
  return p;
}

Eigen::VectorXd FloatingFrameInertia::mass_product(const Eigen::VectorXd& z) const {
  check(z, "z");
  if (dense_) return M_dense_ * z;
  Eigen::VectorXd y(z.size());
  rows_product<1, false>(M_rows_, {z.data()}, {y.data()});  // M_ z as Eigen forms it
  return y;
}

void FloatingFrameInertia::mass_product_add(const Eigen::VectorXd& z, Eigen::VectorXd& y) const {
  if (dense_) y.noalias() += M_dense_ * z;
  else rows_product<1, true>(M_rows_, {z.data()}, {y.data()});  // Eigen's sums, without its scatter
}

Eigen::Matrix3d FloatingFrameInertia::J0() const {
  return E0_.trace() * Eigen::Matrix3d::Identity() - E0_;
}

FloatingFrameInertia::SparseMatrix FloatingFrameInertia::Mij(int i, int j) const {
  if (i < 0 || i > 2 || j < 0 || j > 2)
    throw std::invalid_argument("Mij: components i, j must be in {0, 1, 2}");
  const int n = num_dofs();
  if (dense_) return Eigen::MatrixXd(Mij_stacked_.middleRows((3 * i + j) * n, n)).sparseView(0.0, 0.0);
  return Mij_[3 * i + j];
}

const FloatingFrameInertia::Products* FloatingFrameInertia::recalled(const Eigen::VectorXd& z,
                                                                     const ProductsMemo* memo) {
  if (memo)
    for (int s = 0; s < ProductsMemo::kSlots; ++s)
      if (memo->z[s].size() == z.size() && memo->z[s] == z) return &memo->products[s];
  return nullptr;
}

FloatingFrameInertia::Products FloatingFrameInertia::recorded(const Eigen::VectorXd& z, ProductsMemo* memo) {
  Products P;
  P.n_ = z.size();
  std::shared_ptr<Eigen::VectorXd>* evicted = memo ? &memo->products[memo->next].p_ : nullptr;
  if (evicted && *evicted && evicted->use_count() == 1) P.p_ = std::move(*evicted);  // held by the memo only
  else P.p_ = std::make_shared<Eigen::VectorXd>();
  if (memo) {
    memo->z[memo->next] = z;
    memo->products[memo->next] = P;
    memo->next = (memo->next + 1) % ProductsMemo::kSlots;
  }
  return P;
}

FloatingFrameInertia::Products FloatingFrameInertia::products(const Eigen::VectorXd& z, ProductsMemo* memo) const {
  check(z, "z");
  if (const Products* P = recalled(z, memo)) return *P;
  Products P = recorded(z, memo);
  compute_products<1>({&z}, {P.p_.get()});
  return P;
}

void FloatingFrameInertia::products(const Eigen::VectorXd& z1, const Eigen::VectorXd& z2, ProductsMemo* memo,
                                    Products& P1, Products& P2) const {
  check(z1, "z");
  check(z2, "z");
  if (recalled(z1, memo) || recalled(z2, memo) || z1 == z2) {
    P1 = products(z1, memo);
    P2 = products(z2, memo);
    return;
  }
  P1 = recorded(z1, memo);
  P2 = recorded(z2, memo);
  compute_products<2>({&z1, &z2}, {P1.p_.get(), P2.p_.get()});
}

void FloatingFrameInertia::check(const Eigen::VectorXd& d, const char* name) const {
  if (d.size() != num_dofs())
    throw std::invalid_argument(std::string(name) + " has wrong size: expected " +
                                std::to_string(num_dofs()) + ", got " + std::to_string(d.size()));
}

Eigen::Vector3d FloatingFrameInertia::first_moment(const Eigen::VectorXd& d) const {
  check(d, "d");
  return S0_ + S1_ * d;
}

Eigen::Matrix3d FloatingFrameInertia::inertia_tensor(const Eigen::VectorXd& d, ProductsMemo* memo) const {
  return inertia_tensor(d, products(d, memo));
}

Eigen::Matrix3d FloatingFrameInertia::inertia_tensor(const Eigen::VectorXd& d, const Products& Pd) const {
  check(d, "d");
  // E(d) = E0 + c + c^T + q with c_ij = int rho P_i u_j, q_ij = int rho u_i u_j.
  Eigen::Matrix3d E = E0_;
  const Eigen::Matrix<double, 9, 1> c = C_ * d;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) E(i, j) += c(3 * i + j) + c(3 * j + i) + d.dot(Pd[3 * i + j]);
  return E.trace() * Eigen::Matrix3d::Identity() - E;
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::rotation_coupling(const Eigen::VectorXd& d,
                                                                       ProductsMemo* memo) const {
  return rotation_coupling(products(d, memo));
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::rotation_coupling(const Products& Pd) const {
  check(Pd[0], "Pd");
  // (P + u)~ N row-wise: x: P_y N_z - P_z N_y (and cyclic), the u-part from M_ij.
  Matrix3X H(3, num_dofs());
  fill_rotation_coupling(Pd, H);
  return H;
}

void FloatingFrameInertia::fill_rotation_coupling(const Products& Pd, Matrix3X& H) const {
  // Row i = C_(jk) - C_(kj) + (M_kj d - M_jk d)^T, (i, j, k) cyclic.
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    H.row(i) = C_.row(3 * j + k) - C_.row(3 * k + j) + (Pd[3 * k + j] - Pd[3 * j + k]).transpose();
  }
}

double FloatingFrameInertia::kinetic_energy(const Eigen::Vector3d& V, const Eigen::Vector3d& w,
                                            const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                            ProductsMemo* memo) const {
  check(dd, "dd");
  const Products Pd = products(d, memo);
  return 0.5 * m_ * V.dot(V) + V.dot(w.cross(first_moment(d))) + V.dot(S1_ * dd) +
         0.5 * w.dot(inertia_tensor(d, Pd) * w) + w.dot(rotation_coupling(Pd) * dd) + 0.5 * dd.dot(mass_product(dd));
}

Eigen::Matrix3d FloatingFrameInertia::inertia_tensor_rate(const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                                          ProductsMemo* memo) const {
  check(d, "d");
  check(dd, "dd");
  // Edot = c(dd) + c(dd)^T + int rho (u'_i u_j + u_i u'_j).
  Eigen::Matrix3d Edot;
  const Eigen::Matrix<double, 9, 1> c = C_ * dd;
  const Products Pd = products(d, memo), Pdd = products(dd, memo);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      Edot(i, j) = c(3 * i + j) + c(3 * j + i) + dd.dot(Pd[3 * i + j]) + d.dot(Pdd[3 * i + j]);
  return Edot.trace() * Eigen::Matrix3d::Identity() - Edot;
}

Eigen::Matrix<double, 9, 1> FloatingFrameInertia::centrifugal_weights(const Eigen::Vector3d& w) {
  // int rho N_i^T (w_i (w.P) - |w|^2 P_i) = sum_ij (w_i w_j - delta_ij |w|^2) C.row(3 j + i)^T,
  // with int rho N_i^T P_j = C.row(3 j + i)^T; the weights are symmetric in i, j.
  Eigen::Matrix<double, 9, 1> c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c(3 * j + i) = w(i) * w(j) - (i == j ? w.squaredNorm() : 0.0);
  return c;
}

Eigen::VectorXd FloatingFrameInertia::centrifugal_load(const Eigen::Vector3d& w) const {
  return C_.transpose() * centrifugal_weights(w);
}

FloatingFrameInertia::SparseMatrix FloatingFrameInertia::centrifugal_stiffness(const Eigen::Vector3d& w) const {
  SparseMatrix G(num_dofs(), num_dofs());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) G += (w(i) * w(j) - (i == j ? w.squaredNorm() : 0.0)) * Mij(i, j);
  return G;
}

FloatingFrameInertia::SparseMatrix FloatingFrameInertia::gyroscopic(const Eigen::Vector3d& w) const {
  // (w x u')_i = eps_ijk w_j u'_k: G_y = sum eps_ijk w_j M_ik.
  SparseMatrix G(num_dofs(), num_dofs());
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    G += w(j) * Mij(i, k) - w(k) * Mij(i, j);
  }
  return G;
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::contract_inertia(const Products& P, bool with_C,
                                                                     const Eigen::Vector3d& x) const {
  // E_ij(d) = E0_ij + C_(ij) d + C_(ji) d + d^T M_ij d, so dE_ij/dd = C_(ij) + C_(ji) + z^T (M_ij + M_ji)
  // with z = d (M_ij^T z = M_ji z); (J x) = tr(E) x - E x.
  // Row l: x_l tr(g) - sum_j x_j g_lj, g_lj = (M_jl z + M_lj z)^T [+ C_(lj) + C_(jl)], summed in
  // place, row by row (D's rows are contiguous), one expression each: no temporaries (these run
  // four times a Newton matrix).
  const Eigen::Index n = num_dofs();
  Matrix3X D(3, n);
  const Eigen::Vector3d x2 = 2.0 * x;
  for (int l = 0; l < 3; ++l) {
    auto row = D.row(l).transpose();
    row = x2(l) * (P[0] + P[4] + P[8]);
    for (int j = 0; j < 3; ++j) row -= x(j) * (P[3 * j + l] + P[3 * l + j]);
    if (!with_C) continue;
    row += x2(l) * (C_.row(0) + C_.row(4) + C_.row(8)).transpose();
    for (int j = 0; j < 3; ++j) row -= x(j) * (C_.row(3 * l + j) + C_.row(3 * j + l)).transpose();
  }
  return D;
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::rotation_coupling_jacobian(const Products& P) {
  // Row i = (M_jk y - M_kj y)^T, (i, j, k) cyclic.
  Matrix3X D(3, P[0].size());
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    D.row(i) = (P[3 * j + k] - P[3 * k + j]).transpose();
  }
  return D;
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::inertia_tensor_jacobian(const Eigen::VectorXd& d,
                                                                             const Eigen::Vector3d& x,
                                                                             ProductsMemo* memo) const {
  check(d, "d");
  return contract_inertia(products(d, memo), true, x);
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::inertia_rate_jacobian(const Eigen::VectorXd& dd,
                                                                           const Eigen::Vector3d& x,
                                                                           ProductsMemo* memo) const {
  check(dd, "dd");
  return contract_inertia(products(dd, memo), false, x);
}

FloatingFrameInertia::Matrix3X FloatingFrameInertia::rotation_coupling_jacobian(const Eigen::VectorXd& y,
                                                                                ProductsMemo* memo) const {
  check(y, "y");
  return rotation_coupling_jacobian(products(y, memo));
}

FloatingFrameInertia::StateIntegrals FloatingFrameInertia::state_integrals(
    const Eigen::Vector3d& w, const Eigen::VectorXd& d, const Eigen::VectorXd& dd, const Products& Pd,
    const Products& Pdd) const {
  const Eigen::Matrix<double, 9, 1> cd = C_ * d, cdd = C_ * dd;
  Eigen::Matrix3d E = E0_, Edot;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int ij = 3 * i + j, ji = 3 * j + i;
      E(i, j) += cd(ij) + cd(ji) + d.dot(Pd[ij]);
      Edot(i, j) = cdd(ij) + cdd(ji) + dd.dot(Pd[ij]) + d.dot(Pdd[ij]);
    }
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  StateIntegrals g;
  g.s = S0_ + S1_ * d;
  g.J = E.trace() * I3 - E;
  g.Jdot = Edot.trace() * I3 - Edot;
  g.H.resize(3, num_dofs());
  g.Gd = Eigen::VectorXd::Zero(num_dofs());
  g.Gdd = Eigen::VectorXd::Zero(num_dofs());
  fill_rotation_coupling(Pd, g.H);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    g.Gdd += w(j) * Pdd[3 * i + k] - w(k) * Pdd[3 * i + j];  // G_y(w) dd
    for (int l = 0; l < 3; ++l) g.Gd += (w(i) * w(l) - (i == l ? w.squaredNorm() : 0.0)) * Pd[3 * i + l];
  }
  return g;
}

FloatingFrameInertia::InertialForces FloatingFrameInertia::forces(
    const StateIntegrals& g, const Eigen::Vector3d& a, const Eigen::Vector3d& al, const Eigen::Vector3d& w,
    const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd, double damping) const {
  const Eigen::Vector3d S1dd = S1_ * dd, Hdd = g.H * dd;
  InertialForces f;
  f.F = m_ * a + al.cross(g.s) + S1_ * ddd + w.cross(w.cross(g.s)) + 2.0 * w.cross(S1dd);
  f.M = g.s.cross(a) + g.J * al + g.H * ddd + w.cross(g.J * w) + g.Jdot * w + w.cross(Hdd);
  // Term by term into f.Q: one allocation, no temporaries.
  f.Q.noalias() = S1_.transpose() * a;
  f.Q.noalias() += g.H.transpose() * al;
  if (damping != 0.0) mass_product_add(ddd + damping * dd, f.Q);  // and the damping force (header)
  else mass_product_add(ddd, f.Q);
  f.Q.noalias() += C_.transpose() * centrifugal_weights(w);  // centrifugal_load(w)
  f.Q += g.Gd + 2.0 * g.Gdd;
  return f;
}

FloatingFrameInertia::InertialForces FloatingFrameInertia::inertial_forces(
    const Eigen::Vector3d& a, const Eigen::Vector3d& al, const Eigen::Vector3d& w,
    const Eigen::VectorXd& d, const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd, ProductsMemo* memo,
    double damping) const {
  check(d, "d");
  check(dd, "dd");
  check(ddd, "ddd");
  if (!std::isfinite(damping)) throw std::invalid_argument("inertial_forces: damping must be finite");
  // Every d-dependent integral is built from the 18 products M_ij d and M_ij dd, formed once
  // (M_ij^T = M_ji).
  Products Pd, Pdd;
  products(d, dd, memo, Pd, Pdd);
  return forces(state_integrals(w, d, dd, Pd, Pdd), a, al, w, dd, ddd, damping);
}

FloatingFrameInertia::ForceJacobians FloatingFrameInertia::inertial_force_jacobians(
    const Eigen::Vector3d& a, const Eigen::Vector3d& al, const Eigen::Vector3d& w,
    const Eigen::VectorXd& d, const Eigen::VectorXd& dd, const Eigen::VectorXd& ddd, ProductsMemo* memo) const {
  check(d, "d");
  check(dd, "dd");
  check(ddd, "ddd");
  const int n = num_dofs();
  const Products Pd = products(d, memo), Pdd = products(dd, memo), Pddd = products(ddd, memo);
  const StateIntegrals g = state_integrals(w, d, dd, Pd, Pdd);
  ForceJacobians out;
  out.f = forces(g, a, al, w, dd, ddd);
  out.s = g.s;
  out.J = g.J;
  const Eigen::Vector3d& s = g.s;
  const Eigen::Matrix3d& J = g.J;
  const Eigen::Matrix3d& Jdot = g.Jdot;
  const Matrix3X& H = g.H;
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d S1dd = S1_ * dd, Hdd = H * dd, Jw = J * w;

  // d(F, M)/d(a, al, w): F = m a - s~ al + w x (w x s) + 2 w x (S1 dd') + ...,
  // M = s~ a + J al + w x (J w) + Jdot w + w x (H dd') + ...; d(w x (w x s))/dw = (w.s) I + w s^T - 2 s w^T.
  const Eigen::Matrix3d W = skew(w);
  out.FM_k << m_ * I3, -skew(s), w.dot(s) * I3 + w * s.transpose() - 2.0 * s * w.transpose() - 2.0 * skew(S1dd),
      skew(s), J, W * J - skew(Jw) + Jdot - skew(Hdd);
  // dQ/d(a, al, w) = (S1^T, H^T, d/dw of C_w(w) + G_w(w) d + 2 G_y(w) dd'), with C_w(w) =
  // sum_ij w_i w_j C_(j,i)^T - |w|^2 sum_i C_(i,i)^T and G_w(w) d = sum_il (w_i w_l - delta_il |w|^2) M_il d.
  out.Q_k.resize(n, 9);
  out.Q_k.leftCols<3>() = S1_.transpose();
  out.Q_k.middleCols<3>(3) = H.transpose();
  const Eigen::VectorXd trace_C = (C_.row(0) + C_.row(4) + C_.row(8)).transpose();
  const Eigen::VectorXd trace_P = Pd[0] + Pd[4] + Pd[8];
  for (int m = 0; m < 3; ++m) {
    auto col = out.Q_k.col(6 + m);
    col = -2.0 * w(m) * (trace_C + trace_P);
    for (int l = 0; l < 3; ++l) {
      col += w(l) * (C_.row(3 * l + m).transpose() + C_.row(3 * m + l).transpose());
      col += w(l) * (Pd[3 * m + l] + Pd[3 * l + m]);
    }
  }
  for (int i = 0; i < 3; ++i) {  // 2 G_y(w) dd' = 2 sum_i (w_j M_ik - w_k M_ij) dd', (i, j, k) cyclic
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    out.Q_k.col(6 + j) += 2.0 * Pdd[3 * i + k];
    out.Q_k.col(6 + k) -= 2.0 * Pdd[3 * i + j];
  }

  // d(F, M)/d(dd'', dd', d): F's d-part is (al~ + w~ w~) S1 d; M's: s~ a = -a~ S1 d, J(d) al,
  // H(d) dd'', w x (J(d) w), Jdot(d, dd') w and w x (H(d) dd').
  const Matrix3X Dw = contract_inertia(Pd, true, w);
  out.FM_ddd.resize(6, n);
  out.FM_ddd << S1_, H;
  out.FM_dd.resize(6, n);
  out.FM_dd << 2.0 * W * S1_, Dw + W * H;
  out.FM_d.resize(6, n);
  out.FM_d << (skew(al) + W * W) * S1_,
      -skew(a) * S1_ + contract_inertia(Pd, true, al) + rotation_coupling_jacobian(Pddd) + W * Dw +
          contract_inertia(Pdd, false, w) + W * rotation_coupling_jacobian(Pdd);
  return out;
}

}  // namespace deployfx::body
