#pragma once
// The principal submatrix of a Newton iteration matrix on a set of coordinates, factorized: the
// block with which GeneralizedAlpha::step relaxes a system's slaved coordinates
// (SecondOrderSystem::slaved_velocities) at each step's predictor.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <vector>

#include "deployfx/integrate/block_matrix.hpp"

namespace deployfx::integrate {

/// S(idx, idx) as a sparse matrix (its entries in the border and in the elastic block).
Eigen::SparseMatrix<double> principal_submatrix(const BlockMatrix& S, const std::vector<int>& idx);

/// S(idx, idx), kept when set() and factorized by a sparse LU on first use (it is not
/// symmetric: the floating frame's gyroscopic terms), so a Newton loop that forms many matrices
/// pays for one factorization per use.
class SlavedBlock {
 public:
  void set(const BlockMatrix& S, const std::vector<int>& idx);
  bool empty() const { return state_ == State::kEmpty; }
  void reset() { state_ = State::kEmpty; }
  /// d = S(idx, idx)^-1 r; false (d untouched) if the block is empty or singular.
  bool solve(const Eigen::VectorXd& r, Eigen::VectorXd* d);

 private:
  enum class State { kEmpty, kSet, kFactorized, kSingular };
  Eigen::SparseMatrix<double> block_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  State state_ = State::kEmpty;
};

}  // namespace deployfx::integrate
