#pragma once
// LU with partial (row) pivoting of a small dense square matrix, P S = L U, kept in place: the
// Newton matrix of a reduced model (base, hinges and a few dozen Ritz coordinates, 37 x 37 on the
// paper's scene), factorized whole at nearly every iteration of its full Newton. Right-looking,
// one column at a time (Golub & Van Loan, Matrix Computations, 4th ed., Alg. 3.4.1), each update
// of the trailing matrix a contiguous column axpy that the compiler vectorizes. Eigen's
// PartialPivLU runs its blocked algorithm there (a GEMM call per panel): 4.5 against 2.7 us at
// n = 37 (docs/performance-history.md, session 27). The storage is kept across factorizations of
// one size: nothing is allocated after the first.
#include <Eigen/Core>
#include <vector>

namespace deployfx {

class DenseLU {
 public:
  /// Factorizes the square matrix `lu()` holds (fill it through lu() first). False if a pivot is
  /// zero, below 1e-300 in magnitude or not finite (the matrix singular or not finite); lu() is then
  /// unusable until the next factorize().
  bool factorize();
  /// The matrix to factorize (resize and fill it), then its L (unit lower) and U in place.
  Eigen::MatrixXd& lu() { return lu_; }
  const Eigen::MatrixXd& lu() const { return lu_; }
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
};

}  // namespace deployfx
