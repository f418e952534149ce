#pragma once
// Solves S x = r for a BlockMatrix: with a sparse elastic block E, by the Schur complement on the
// dense border,
//   E y = r_e,  E Z = C,  (A - B Z) x_b = r_b - B y,  x_e = y - Z x_b;
// a dense or absent E (below), by one LU of S whole.
//
// The elastic block E = c_a M + c_v (2 G_y(w) + damping) + c_q (K_T + ...) is symmetric but for the
// floating frame's gyroscopic terms G_y (hinged_system_jacobians.cpp), which are skew. Where they
// are small, E is factorized by a sparse LDL^T of its symmetric part Es: over the mesh nodes'
// 6 x 6 blocks (math/block_ldlt.hpp: 1.5x faster runs of the paper's 15 x 10 scene than Eigen's
// scalar SimplicialLDLT, which is kept, AMD-ordered, for dofs that do not group into nodes or a
// singular pivot block; either is 3x cheaper than the sparse LU there, with half its triangular
// solve), and the solve refines against S (each step shrinks the error by the spectral radius of
// Es^-1 Ek, below 3e-4 on the paper's deployment: G_y couples a mode with the in-plane,
// membrane-stiff ones), so the Newton iteration sees S^-1 to 1e-8 where it asks for the exact
// solve (a fresh matrix; an old one's step is inexact anyway). That radius is estimated at each
// factorization; above `skew_tolerance` (a fast spin) E is factorized exactly by the sparse LU
// (COLAMD). All keep their fill-reducing ordering across factorizations of one pattern. Where E is
// dense (half full or more: a reduced model's modal block) or absent, S is small and factorized
// whole by one dense LU (math/dense_lu.hpp), exact and cheaper than any sparse path at that size.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <utility>
#include <vector>

#include "deployfx/integrate/block_matrix.hpp"
#include "deployfx/math/block_ldlt.hpp"
#include "deployfx/math/dense_lu.hpp"

namespace deployfx::integrate {

class BorderedSolver {
 public:
  /// Largest estimated contraction rate of the dropped skew part for which E's symmetric part is
  /// factorized instead of E (0: always the exact LU).
  explicit BorderedSolver(double skew_tolerance = 1e-3) : skew_tolerance_(skew_tolerance) {}
  /// Factorizes S; returns false if S (dense), E or the Schur complement is singular (or not finite).
  bool factorize(const BlockMatrix& S);
  /// x = S^-1 r for the last factorized S. With `exact` false, an E factorized by its symmetric
  /// part is not refined against S: x then solves S with E's skew part dropped, off by the
  /// spectral radius of Es^-1 Ek (<= skew_tolerance) relative. That is the solve a modified-Newton
  /// step with an old matrix needs: its matrix is already off by more, and its next iteration
  /// corrects both errors together, without the refinement's two extra solves (measured on the
  /// paper's 15 x 10 scene: docs/engine-design.md, "The elastic block's factorization").
  Eigen::VectorXd solve(const Eigen::VectorXd& r, bool exact = true) const;
  /// Whether the last S was dense throughout (no elastic block, or one half full or more): its
  /// factorization then costs about a residual (the integrator's reuse policy reads this).
  bool dense() const { return method_ == Method::kDense; }
  /// Numeric factorizations done so far (for cost accounting).
  long factorizations() const { return factorizations_; }
  /// How the last S was factorized: "none" (no elastic block: S whole by the dense LU), "dense-lu"
  /// (a dense E: S whole), or how its sparse E was: "block-ldlt", "simplicial-ldlt" (both of the
  /// symmetric part) or "sparse-lu".
  const char* method() const;

 private:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  void analyze(const SparseMatrix& E);
  bool factorize_symmetric(const SparseMatrix& E);  // false: E's skew part is not small, or Es singular
  bool factorize_symmetric_part();                  // Es = E_sym_: by blocks, else the scalar LDL^T
  Eigen::VectorXd solve_symmetric(const Eigen::VectorXd& r) const;  // Es^-1 r
  bool factorize_exact(const SparseMatrix& E);
  bool factorize_dense(const BlockMatrix& S);  // S whole (Method::kDense)
  Eigen::MatrixXd solve_symmetric_block(const Eigen::MatrixXd& B) const;  // Es^-1 B, all columns at once
  Eigen::VectorXd solve_factorized(const Eigen::VectorXd& r) const;  // with Es for E if kSymmetric
  Eigen::VectorXd solve_elastic(const Eigen::VectorXd& r) const;     // E^-1 r (Es^-1 r if kSymmetric), sparse E
  Eigen::VectorXd skew_product(const Eigen::VectorXd& x) const;  // E_skew_ x
  // y -= E x for kSymmetric's E = E_sym_ + E_skew_ (the refinement's residual)
  void subtract_elastic_product(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const;

  // How the last S was factorized: whole (kDense), or its sparse E by its symmetric part or exactly.
  enum class Method { kDense, kSymmetric, kExact };

  double skew_tolerance_;
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu_E_;
  DenseLU dense_lu_;  // Method::kDense: S whole
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_E_;
  BlockLDLT block_E_;
  bool ldlt_analyzed_ = false;
  bool block_ = false;  // kSymmetric: Es in block_E_ (else in ldlt_E_)
  SparseMatrix E_sym_, E_skew_;           // E's pattern, (E + E^T)/2 and (E - E^T)/2
  // For each of E's nonzeros (i, j) the slot of (j, i); empty: not structurally symmetric
  std::vector<int> transpose_;
  bool lu_analyzed_ = false;
  Method method_ = Method::kExact;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_schur_;  // sparse E: the Schur complement A - B Z
  Eigen::MatrixXd A_, B_, C_, Z_;  // S's border, kept for the refinement; Z = E^-1 C
  Eigen::Index pattern_nnz_ = -1, pattern_rows_ = -1;
  int nb_ = 0, ne_ = 0;
  long factorizations_ = 0;
};

}  // namespace deployfx::integrate
