#pragma once
// The principal submatrix of a Newton iteration matrix on a set of coordinates, factorized: the
// block with which GeneralizedAlpha::relax_slaved relaxes a system's slaved coordinates
// (SecondOrderSystem::slaved_velocities) at each step's predictor.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "deployfx/integrate/block_matrix.hpp"
#include "deployfx/integrate/bordered_solver.hpp"
#include "deployfx/math/dense_lu.hpp"

namespace deployfx::integrate {

/// S(idx, idx), kept when set() and factorized on first use (it is not symmetric: the floating
/// frame's gyroscopic terms), so a Newton loop that forms many matrices pays for one
/// factorization per use. Its pattern is S's own on idx (the elastic block's stored entries, zeros
/// included, and the dense border's), so set() gathers values through slots found once per
/// pattern. A small or dense block (a reduced panel's in-plane Ritz coordinates) is factorized
/// densely; a large sparse one (a mesh's in-plane dofs, three a node) by the bordered solver
/// without a border: the block LDL^T of its symmetric part over the nodes' 3 x 3 blocks (the sparse
/// LU where the skew part is not small), its solve not refined against that part: a sweep is a
/// relaxation whose residual is evaluated after it, and a correction off by the skew part's
/// radius (its estimate below 1e-3, the radius up to ten times that) relaxes as well (the paper's 15 x 10 scene: the same iterations, 4 % less
/// CPU than refined to 1e-8; docs/performance-history.md, session 27).
class SlavedBlock {
 public:
  void set(const BlockMatrix& S, const std::vector<int>& idx);
  bool empty() const { return state_ == State::kEmpty; }
  void reset() { state_ = State::kEmpty; }
  /// S(idx, idx) as last set (the elastic block of a matrix without border; empty if none).
  BlockMatrix values() const { return empty() ? BlockMatrix() : block_; }
  /// Sets the block to `block` (values() of another run's: a checkpoint's), to be factorized on
  /// first use; std::invalid_argument unless it is square, compressed and without border.
  void restore(const BlockMatrix& block);
  /// d = S(idx, idx)^-1 r (a large sparse block's skew part dropped: above); false (d untouched)
  /// if the block is empty or singular.
  bool solve(const Eigen::VectorXd& r, Eigen::VectorXd* d);

 private:
  enum class State { kEmpty, kSet, kFactorized, kSingular };
  // Where each stored value of the block comes from: one of S's four parts, at an offset in its
  // values (column-major for the dense A, B, C; E's value array).
  enum Part { kA, kB, kC, kE };
  struct Source {
    Part part;
    Eigen::Index offset;
  };
  void analyze(const BlockMatrix& S, const std::vector<int>& idx);  // the block's pattern, sources_

  std::vector<int> idx_;                        // the coordinates sources_ was built for
  int border_ = -1;                             // and S's border, elastic size and nonzeros
  Eigen::Index elastic_ = -1, elastic_nnz_ = -1;
  std::vector<Source> sources_;                 // per stored value of block_.E
  bool dense_ = false;
  BlockMatrix block_;  // S(idx, idx) as the elastic block of a matrix without border
  DenseLU dense_lu_;
  BorderedSolver sparse_;
  State state_ = State::kEmpty;
};

}  // namespace deployfx::integrate
