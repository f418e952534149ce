#pragma once
// Where an entry lives in a compressed column-major sparse matrix: the index of (row, col) in its
// value array, or -1 if the pattern has no such entry. Assembly maps (element entries, the free
// block, a transpose partner) are built from it once per pattern.
#include <Eigen/SparseCore>
#include <algorithm>

namespace deployfx {

inline Eigen::Index sparse_slot(const Eigen::SparseMatrix<double>& A, int row, int col) {
  const int* inner = A.innerIndexPtr();
  const int* begin = inner + A.outerIndexPtr()[col];
  const int* end = inner + A.outerIndexPtr()[col + 1];
  const int* p = std::lower_bound(begin, end, row);
  return p == end || *p != row ? -1 : p - inner;
}

}  // namespace deployfx
