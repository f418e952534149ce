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

namespace {
// A block this small, or at least this dense, is factorized densely: below it a dense LU costs
// less than the sparse one's analysis and supernodes.
constexpr int kDenseSize = 128;
constexpr double kDenseFill = 0.25;
}  // namespace

void SlavedBlock::set(const BlockMatrix& S, const std::vector<int>& idx) {
  block_ = principal_submatrix(S, idx);
  const double m = static_cast<double>(block_.rows());
  dense_ = block_.rows() <= kDenseSize || static_cast<double>(block_.nonZeros()) >= kDenseFill * m * m;
  state_ = State::kSet;
}

bool SlavedBlock::solve(const Eigen::VectorXd& r, Eigen::VectorXd* d) {
  if (state_ == State::kSet) {
    if (dense_) {
      dense_block_ = Eigen::MatrixXd(block_);
      dense_lu_.compute(dense_block_);
      // PartialPivLU does not report singularity: a zero pivot shows as a non-finite solve below.
      state_ = State::kFactorized;
    } else {
      const std::vector<int> outer(block_.outerIndexPtr(), block_.outerIndexPtr() + block_.outerSize() + 1);
      const std::vector<int> inner(block_.innerIndexPtr(), block_.innerIndexPtr() + block_.nonZeros());
      if (outer != analyzed_outer_ || inner != analyzed_inner_) {
        lu_.analyzePattern(block_);
        analyzed_outer_ = outer, analyzed_inner_ = inner;
      }
      lu_.factorize(block_);
      state_ = lu_.info() == Eigen::Success ? State::kFactorized : State::kSingular;
    }
  }
  if (state_ != State::kFactorized) return false;
  Eigen::VectorXd x = dense_ ? Eigen::VectorXd(dense_lu_.solve(r)) : Eigen::VectorXd(lu_.solve(r));
  if (!x.allFinite()) return false;
  *d = std::move(x);
  return true;
}

}  // namespace deployfx::integrate
