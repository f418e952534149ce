#pragma once
// A sparse LDL^T factorization A = P^T L D L^T P over dense blocks, for a symmetric matrix whose
// dofs come in groups with one pattern: a shell mesh's elastic block, whose six dofs per node
// (fem::kNodeDofs) couple to the same neighbours, or its in-plane part (three dofs a node: the
// slaved block of integrate/slaved_block.hpp). L is unit block lower triangular and block sparse
// with dense blocks, D block diagonal; every update of the factorization and of its triangular
// solves is a fixed-size 6 x 6 (or 3 x 3, stored padded to 4 x 3) product (one vectorized kernel,
// no index per scalar),
// where a scalar sparse LDL^T (Eigen's SimplicialLDLT) reads an index and does one multiply-add
// per entry. These are the supernodes of the node graph at their narrowest (George & Liu,
// Computer Solution of Large Sparse Positive Definite Systems, 1981, Sec. 5.5, indistinguishable
// nodes; Davis, Direct Methods for Sparse Linear Systems, SIAM 2006, Ch. 4, the elimination tree
// and the left-looking column update used here). Each pivot block D_j is inverted through its own
// LDL^T with symmetric pivoting (Eigen's LDLT), so an indefinite A (a symmetric part of Newton's
// matrix under compression: measured on the paper's scene, one factorization in twenty) factorizes
// as long as no pivot block is singular: like the scalar LDL^T, with pivoting inside each node.
//
// analyze() groups consecutive dofs whose columns have the same pattern (at most six: a node),
// takes blocks of six (groups of four dofs or more on average) or of three (groups of at most
// three, two or more on average), pads a group smaller than the block with unit diagonal entries
// (a node with held dofs), orders the groups by AMD on their graph, and builds the factor's block
// pattern from the elimination tree; it is done once per pattern. factorize() and solve() then
// work on that structure.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace deployfx {

class BlockLDLT {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;  // compressed, column-major, int indices

  /// Analyses the pattern of A (square, structurally symmetric, both triangles stored). False if
  /// its dofs do not group into blocks (groups of four dofs or more, or of two to three, on
  /// average; fewer: the scalar factorization is then as good); the object is then unusable until
  /// a successful analyze.
  bool analyze(const SparseMatrix& A);
  /// Factorizes A, of the analysed pattern and symmetric (the entries of the lower block triangle
  /// in the factor's order are read). False if a pivot block is singular or not finite.
  bool factorize(const SparseMatrix& A);
  /// X = A^-1 B for the last factorized A, any number of columns.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  /// Whether the last analyze succeeded.
  bool analyzed() const { return blocks_ > 0; }
  /// The dofs a block holds (6 or 3; 0 before a successful analyze).
  int block_size() const { return block_; }

 private:
  template <int kBlock>
  bool factorize_blocks();  // the factorization proper, on values_ as loaded by factorize()
  template <int kBlock, class Rhs>
  void solve_in_place(Rhs& X) const;  // X: the padded, permuted right-hand sides
  template <class Rhs>
  void solve_padded(Rhs& X) const;  // solve_in_place for the analysed block size

  int stored_rows() const;  // rows a block is stored with: kBlockRows<block_> (math/block_product.hpp)

  int n_ = 0;       // scalar rows of A
  int block_ = 0;   // dofs per block: 6 or 3
  int blocks_ = 0;  // block rows and columns of the factor
  // Where dof d of A lives in the padded, permuted vector: stored_rows() * (its block) + its place
  // in it.
  std::vector<int> dof_slot_;
  std::vector<int> padding_;  // padded diagonal entries (indices into values_), set to 1
  // The factor, column by column (s = stored_rows() block_ values a block, column-major, the rows
  // past block_ zero): the pivot blocks D_j at
  // values_[s 2 j] and their inverses next, at values_[s (2 j + 1)]; then the blocks L_ij of
  // column j for the block rows i in off_rows_[off_begin_[j] .. off_begin_[j + 1]) (ascending),
  // block t at values_[s (2 blocks_ + t)].
  std::vector<int> off_begin_, off_rows_;
  std::vector<int> off_column_;  // the column of block t
  // The left-looking updates of column j: the blocks L_jk (k < j) of row j, by their index t in
  // the off-diagonal storage, for t in row_blocks_[row_begin_[j] .. row_begin_[j + 1]).
  std::vector<int> row_begin_, row_blocks_;
  // A's k-th stored value goes to values_[value_target_[k]], or nowhere (-1: the upper block
  // triangle, read through its transpose).
  std::vector<long> value_target_;
  std::vector<double> values_;
  std::vector<int> position_;  // factorize()'s work: block row -> its block in column j
};

}  // namespace deployfx
