#pragma once
// LU with partial (row) pivoting of a small dense square matrix, P S = L U: the Newton matrix of a
// reduced model (base, hinges and a few dozen Ritz coordinates, 37 x 37 on the paper's scene),
// factorized whole at nearly every iteration of its full Newton. Up to kUnblocked rows
// right-looking and in place (Golub & Van Loan, Matrix Computations, 4th ed., Alg. 3.4.1), two
// pivot columns at a time: the trailing matrix takes both rank-1 terms in one pass (half the
// stores), over columns padded to whole 4-double chunks (no remainder loops; the multipliers'
// first chunk zero above the pivots), each entry by the same two fused multiply-adds in the same
// order as one column at a time: the same bits. There Eigen's PartialPivLU runs its blocked
// algorithm (a GEMM call per panel), slower at n = 37; above kUnblocked the blocked one is taken.
// The storage is kept across factorizations of one size: nothing is allocated after the first
// (docs/performance-history.md, sessions 27 and 31).
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

namespace deployfx {

class DenseLU {
 public:
  static constexpr Eigen::Index kUnblocked = 64;
  /// The n x n matrix to factorize, to be filled before factorize(); its L (unit lower) and U in
  /// place after it. The storage is padded to whole chunks of rows (zero there) and kept while
  /// n stays.
  Eigen::Block<Eigen::MatrixXd> matrix(Eigen::Index n);
  /// Factorizes the matrix matrix() holds. False if a pivot is zero, below 1e-300 in magnitude or
  /// not finite, or an entry of the factors is not finite (the matrix singular or not finite);
  /// solve() is then unusable until the next factorize().
  bool factorize();
  /// x = S^-1 b in place, for the last successful factorize().
  void solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    Eigen::VectorXd x = b;
    solve_in_place(x);
    return x;
  }

 private:
  static constexpr Eigen::Index kChunk = 4;  // doubles a padded column chunk holds (an AVX vector)
  bool pivot_column(Eigen::Index k);
  Eigen::MatrixXd lu_;      // n_ x n_ in the first rows of ld >= n_ (a multiple of kChunk), zero below
  Eigen::Index n_ = 0;
  std::vector<int> pivot_;  // row k was swapped with row pivot_[k] >= k at step k
  bool blocked_ = false;    // the last factorize() took Eigen's blocked LU, into blocked_lu_
  Eigen::PartialPivLU<Eigen::MatrixXd> blocked_lu_;
};

}  // namespace deployfx
