#pragma once
// LU with partial (row) pivoting of a small dense square matrix, P S = L U: the Newton matrix of a
// reduced model (base, hinges and a few dozen Ritz coordinates, 37 x 37 on the paper's scene),
// factorized whole at nearly every iteration of its full Newton. Up to kUnblocked rows
// right-looking and in place, one column at a time (Golub & Van Loan, Matrix Computations, 4th
// ed., Alg. 3.4.1), each update of the trailing matrix a contiguous column axpy that the compiler
// vectorizes: there Eigen's PartialPivLU runs its blocked algorithm (a GEMM call per panel) for
// 4.5 against 2.7 us at n = 37. Above it the blocked one is faster (1.25-1.8x at n = 80-600: two
// reduced wings, or 40 modes) and is taken. The storage is kept across factorizations of one
// size: the unblocked path allocates nothing after the first (docs/performance-history.md,
// session 27).
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

namespace deployfx {

class DenseLU {
 public:
  static constexpr Eigen::Index kUnblocked = 64;
  /// Factorizes the square matrix lu() holds (fill it through lu() first). False if a pivot is
  /// zero, below 1e-300 in magnitude or not finite, or an entry of the factors is not finite (the
  /// matrix singular or not finite); solve() is then unusable until the next factorize().
  bool factorize();
  /// The matrix to factorize (resize and fill it); up to kUnblocked rows, its L (unit lower) and
  /// U in place after factorize().
  Eigen::MatrixXd& lu() { return lu_; }
  /// x = S^-1 b in place, for the last successful factorize().
  void solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    Eigen::VectorXd x = b;
    solve_in_place(x);
    return x;
  }

 private:
  Eigen::MatrixXd lu_;
  std::vector<int> pivot_;  // row k was swapped with row pivot_[k] >= k at step k
  bool blocked_ = false;    // the last factorize() took Eigen's blocked LU, into blocked_lu_
  Eigen::PartialPivLU<Eigen::MatrixXd> blocked_lu_;
};

}  // namespace deployfx
