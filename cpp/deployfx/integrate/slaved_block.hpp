#pragma once
// The principal submatrix of a Newton iteration matrix on a set of coordinates, factorized: the
// block with which GeneralizedAlpha::relax_slaved relaxes a system's slaved coordinates
// (SecondOrderSystem::slaved_velocities) at each step's predictor.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <vector>

#include "deployfx/integrate/block_matrix.hpp"

namespace deployfx::integrate {

/// S(idx, idx) as a sparse matrix (its entries in the border and in the elastic block).
Eigen::SparseMatrix<double> principal_submatrix(const BlockMatrix& S, const std::vector<int>& idx);

/// S(idx, idx), kept when set() and factorized on first use (it is not symmetric: the floating
/// frame's gyroscopic terms), so a Newton loop that forms many matrices pays for one
/// factorization per use. A small or dense block (a reduced panel's in-plane Ritz coordinates) is
/// factorized densely; a large sparse one (a mesh's in-plane dofs) by a sparse LU whose ordering
/// and symbolic analysis are kept while the pattern stays (it is the elastic block's).
class SlavedBlock {
 public:
  void set(const BlockMatrix& S, const std::vector<int>& idx);
  bool empty() const { return state_ == State::kEmpty; }
  void reset() { state_ = State::kEmpty; }
  /// d = S(idx, idx)^-1 r; false (d untouched) if the block is empty or singular.
  bool solve(const Eigen::VectorXd& r, Eigen::VectorXd* d);

 private:
  enum class State { kEmpty, kSet, kFactorized, kSingular };
  bool dense_ = false;
  Eigen::MatrixXd dense_block_;
  Eigen::PartialPivLU<Eigen::MatrixXd> dense_lu_;
  Eigen::SparseMatrix<double> block_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  std::vector<int> analyzed_outer_, analyzed_inner_;  // the pattern lu_ was analyzed for
  State state_ = State::kEmpty;
};

}  // namespace deployfx::integrate
