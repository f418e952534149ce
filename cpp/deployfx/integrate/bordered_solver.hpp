#pragma once
// Solves S x = r for a BlockMatrix by the Schur complement on its dense border:
//   E y = r_e,  E Z = C,  (A - B Z) x_b = r_b - B y,  x_e = y - Z x_b.
// The sparse LU of E keeps its fill-reducing ordering (COLAMD) across factorizations of the same
// pattern, so a step costs one numeric factorization and nb + 1 triangular solve pairs.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseLU>

#include "deployfx/integrate/block_matrix.hpp"

namespace deployfx::integrate {

class BorderedSolver {
 public:
  /// Factorizes S; returns false if E or the Schur complement is singular (or not finite).
  bool factorize(const BlockMatrix& S);
  /// x = S^-1 r for the last factorized S.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;
  /// Numeric factorizations done so far (for cost accounting).
  long factorizations() const { return factorizations_; }

 private:
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_E_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_schur_;
  Eigen::MatrixXd B_, Z_;
  Eigen::Index pattern_nnz_ = -1, pattern_rows_ = -1;
  int nb_ = 0, ne_ = 0;
  long factorizations_ = 0;
};

}  // namespace deployfx::integrate
