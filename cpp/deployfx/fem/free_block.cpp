#include "deployfx/fem/free_block.hpp"

#include <algorithm>
#include <stdexcept>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/math/sparse_slot.hpp"

namespace deployfx::fem {

FreeBlock::FreeBlock(const SparseMatrix& pattern, const std::vector<int>& free)
    : index_(pattern.rows(), -1) {
  if (!pattern.isCompressed()) throw std::logic_error("FreeBlock: the pattern must be compressed");
  for (int k = 0; k < static_cast<int>(free.size()); ++k) index_[free[k]] = k;
  block_ = restrict(pattern, free);
  block_.makeCompressed();
  std::fill(block_.valuePtr(), block_.valuePtr() + block_.nonZeros(), 0.0);
  pattern_nnz_ = pattern.nonZeros();
  slots_.reserve(pattern_nnz_);
  for (int c = 0; c < pattern.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(pattern, c); it; ++it) slots_.push_back(slot(it.row(), it.col()));
}

Eigen::Index FreeBlock::slot(int row, int col) const {
  const int r = index_[row], c = index_[col];
  if (r < 0 || c < 0) return -1;
  const Eigen::Index s = sparse_slot(block_, r, c);
  if (s < 0) throw std::logic_error("FreeBlock: entry outside the pattern");
  return s;
}

Eigen::VectorXd FreeBlock::aligned(const SparseMatrix& A) const {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(nonzeros());
  for (int c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it) {
      const Eigen::Index s = slot(it.row(), it.col());
      if (s >= 0) v(s) += it.value();
    }
  return v;
}

std::vector<int> FreeBlock::block_slots(const std::vector<int>& pattern_slots) const {
  std::vector<int> out(pattern_slots.size());
  for (std::size_t k = 0; k < pattern_slots.size(); ++k) {
    const int p = pattern_slots[k];
    if (p < 0 || p >= pattern_nnz_) throw std::logic_error("FreeBlock::block_slots: slot outside the pattern");
    out[k] = static_cast<int>(slots_[static_cast<std::size_t>(p)]);
  }
  return out;
}

FreeBlock::SparseMatrix FreeBlock::with_values(const Eigen::VectorXd& values) const {
  SparseMatrix S = block_;
  std::copy(values.data(), values.data() + values.size(), S.valuePtr());
  return S;
}

}  // namespace deployfx::fem
