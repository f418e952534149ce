// FloatingFrameInertia's generalized inertial force Q at a few of its dofs alone (the header's
// RowSelection): what a Newton sweep on a flat panel's in-plane rows reads
// (multibody::slaved_rows), each product restricted to those rows.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "deployfx/body/floating_frame_inertia.hpp"
#include "deployfx/math/sparse_rows.hpp"

namespace deployfx::body {

FloatingFrameInertia::RowSelection FloatingFrameInertia::select_rows(const std::vector<int>& dofs) const {
  if (dense_) throw std::invalid_argument("select_rows: a Ritz basis's inertial force is formed whole");
  const Eigen::Index n = num_dofs(), m = static_cast<Eigen::Index>(dofs.size());
  for (int r : dofs)
    if (r < 0 || r >= n)
      throw std::invalid_argument("select_rows: dof " + std::to_string(r) + " is out of range [0, " + std::to_string(n) + ")");
  RowSelection out;
  out.dofs_ = dofs;
  // Rows of a column-major matrix: its row-major copy's (the same entries, columns ascending).
  using RowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  std::vector<Eigen::Triplet<double>> t;
  out.by_nodes_ = !node_mass_.empty() && std::all_of(dofs.begin(), dofs.end(), [](int r) {
    const int type = r % fem::kNodeDofs;
    return type == 0 || type == 1 || type == 5;
  });
  if (!out.by_nodes_) {
    for (int k = 0; k < 9; ++k) append_rows(RowMajor(Mij_[k]), dofs, k * m, t);
    out.Mij_.resize(9 * m, n);
    out.Mij_.setFromTriplets(t.begin(), t.end());
    t.clear();
  }
  append_rows(RowMajor(M_), dofs, 0, t);
  out.M_.resize(m, n);
  out.M_.setFromTriplets(t.begin(), t.end());
  out.S1_.resize(3, m);
  out.C_.resize(9, m);
  for (Eigen::Index i = 0; i < m; ++i) out.S1_.col(i) = S1_.col(dofs[i]), out.C_.col(i) = C_.col(dofs[i]);
  return out;
}

Eigen::VectorXd FloatingFrameInertia::inertial_force_rows(const RowSelection& rows, const Eigen::Vector3d& a,
                                                          const Eigen::Vector3d& al, const Eigen::Vector3d& w,
                                                          const Eigen::VectorXd& d, const Eigen::VectorXd& dd,
                                                          const Eigen::VectorXd& ddd, double damping) const {
  check(d, "d");
  check(dd, "dd");
  check(ddd, "ddd");
  if (rows.M_.cols() != num_dofs() || (rows.by_nodes_ ? node_mass_.empty() : rows.Mij_.cols() != num_dofs()))
    throw std::invalid_argument("inertial_force_rows: a selection of another body");
  const Eigen::Index m = static_cast<Eigen::Index>(rows.dofs_.size());
  // forces()' Q = S1^T a + H(d)^T al + L_c (dd'' + damping dd') + C^T c(w) + G_w(w) d +
  // 2 G_y(w) dd' at the rows, from the row products P_k = (M_k d)_rows, R_k = (M_k dd')_rows
  // (state_integrals()' formulas), each term a weighted sum over k = 3 i + j: H(d)^T al =
  // sum_k h_k (C_k^T - P_k) with h_(3j+l) = al_i, h_(3l+j) = -al_i ((i, j, l) cyclic); G_w(w) d =
  // sum_k c_k P_k (c symmetric); G_y(w) dd' = sum_k g_k R_k with g_(3i+l) = w_j, g_(3i+j) = -w_l.
  Eigen::VectorXd P(9 * m), R(9 * m), Q(m);
  if (rows.by_nodes_) node_row_products(rows, d, dd, P, R);
  else rows_product<2, false>(rows.Mij_, {d.data(), dd.data()}, {P.data(), R.data()});
  if (damping != 0.0) {  // L_c (dd'' + alpha_M dd'): the damping force with the inertial term
    const Eigen::VectorXd x = ddd + damping * dd;
    rows_product<1, false>(rows.M_, {x.data()}, {Q.data()});
  } else {
    rows_product<1, false>(rows.M_, {ddd.data()}, {Q.data()});
  }
  const Eigen::Matrix<double, 9, 1> c = centrifugal_weights(w);
  Eigen::Matrix<double, 9, 1> h = Eigen::Matrix<double, 9, 1>::Zero(), g = Eigen::Matrix<double, 9, 1>::Zero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    h(3 * j + l) += al(i);
    h(3 * l + j) -= al(i);
    g(3 * i + l) += w(j);
    g(3 * i + j) -= w(l);
  }
  Q.noalias() += rows.S1_.transpose() * a;
  Q.noalias() += rows.C_.transpose() * (h + c);
  for (int k = 0; k < 9; ++k) Q += (c(k) - h(k)) * P.segment(k * m, m) + (2.0 * g(k)) * R.segment(k * m, m);
  return Q;
}

}  // namespace deployfx::body
