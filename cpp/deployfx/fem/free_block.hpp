#pragma once
// The free-dof block of matrices that share one sparsity pattern (a mesh's node-block pattern):
// the restricted pattern is built once, and each matrix's entries are gathered into arrays
// aligned with it, so a linear combination is a sum of value arrays, with no sparse allocation.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace deployfx::fem {

class FreeBlock {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  /// `pattern`: a compressed full-size matrix whose pattern contains every matrix used later.
  FreeBlock(const SparseMatrix& pattern, const std::vector<int>& free);

  /// The restricted pattern (compressed, zero values).
  const SparseMatrix& matrix() const { return block_; }
  Eigen::Index nonzeros() const { return block_.nonZeros(); }
  /// A's entries on the free rows and columns, aligned with matrix()'s values. A's pattern must
  /// lie within `pattern` (throws std::logic_error otherwise).
  Eigen::VectorXd aligned(const SparseMatrix& A) const;
  /// Slots of `pattern`'s values (e.g. ShellModel::element_slots()) mapped to the block's: -1
  /// where the entry is on a fixed row or column.
  std::vector<int> block_slots(const std::vector<int>& pattern_slots) const;
  /// matrix() with the given values.
  SparseMatrix with_values(const Eigen::VectorXd& values) const;

 private:
  Eigen::Index slot(int row, int col) const;  // position in block_'s values, -1 if not free
  std::vector<int> index_;                    // full dof -> free index, -1 if fixed
  SparseMatrix block_;
  std::vector<Eigen::Index> slots_;           // pattern's k-th nonzero -> block_ slot or -1
  Eigen::Index pattern_nnz_ = 0;
};

}  // namespace deployfx::fem
