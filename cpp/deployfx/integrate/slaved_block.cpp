#include "deployfx/integrate/slaved_block.hpp"

#include <stdexcept>

namespace deployfx::integrate {

Eigen::SparseMatrix<double> principal_submatrix(const BlockMatrix& S, const std::vector<int>& idx) {
  const int nb = S.border(), n = S.size(), m = static_cast<int>(idx.size());
  std::vector<int> pos(n, -1);  // idx's position of each coordinate (-1: not in idx)
  for (int i = 0; i < m; ++i) {
    if (idx[i] < 0 || idx[i] >= n) throw std::out_of_range("principal_submatrix: index out of range");
    pos[idx[i]] = i;
  }
  std::vector<Eigen::Triplet<double>> t;
  for (int jj = 0; jj < m; ++jj) {
    const int j = idx[jj];
    if (j < nb) {  // a border column: A above, C below
      for (int i = 0; i < m; ++i) {
        const double v = idx[i] < nb ? S.A(idx[i], j) : S.C(idx[i] - nb, j);
        if (v != 0.0) t.emplace_back(i, jj, v);
      }
    } else {  // an elastic column: B above, E below
      for (int i = 0; i < m; ++i)
        if (idx[i] < nb && S.B(idx[i], j - nb) != 0.0) t.emplace_back(i, jj, S.B(idx[i], j - nb));
      for (Eigen::SparseMatrix<double>::InnerIterator e(S.E, j - nb); e; ++e)
        if (pos[nb + e.row()] >= 0) t.emplace_back(pos[nb + e.row()], jj, e.value());
    }
  }
  Eigen::SparseMatrix<double> out(m, m);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

void SlavedBlock::set(const BlockMatrix& S, const std::vector<int>& idx) {
  block_ = principal_submatrix(S, idx);
  state_ = State::kSet;
}

bool SlavedBlock::solve(const Eigen::VectorXd& r, Eigen::VectorXd* d) {
  if (state_ == State::kSet) {
    lu_.compute(block_);
    state_ = lu_.info() == Eigen::Success ? State::kFactorized : State::kSingular;
  }
  if (state_ != State::kFactorized) return false;
  Eigen::VectorXd x = lu_.solve(r);
  if (!x.allFinite()) return false;
  *d = std::move(x);
  return true;
}

}  // namespace deployfx::integrate
