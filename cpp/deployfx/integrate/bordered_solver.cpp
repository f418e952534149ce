#include "deployfx/integrate/bordered_solver.hpp"

#include <cmath>

namespace deployfx::integrate {

bool BorderedSolver::factorize(const BlockMatrix& S) {
  nb_ = S.border();
  ne_ = S.elastic();
  ++factorizations_;
  Eigen::MatrixXd schur = S.A;
  if (ne_ > 0) {
    if (!S.E.isCompressed()) return false;
    // The pattern of E is fixed by the mesh; re-analyse only if it changed.
    if (S.E.nonZeros() != pattern_nnz_ || S.E.rows() != pattern_rows_) {
      lu_E_.analyzePattern(S.E);
      pattern_nnz_ = S.E.nonZeros();
      pattern_rows_ = S.E.rows();
    }
    lu_E_.factorize(S.E);
    if (lu_E_.info() != Eigen::Success) return false;
    Z_ = lu_E_.solve(S.C);
    B_ = S.B;
    if (nb_ > 0) schur.noalias() -= B_ * Z_;
  }
  if (nb_ > 0) {
    lu_schur_.compute(schur);
    const double pivot = lu_schur_.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(pivot > 1e-300) || !schur.allFinite()) return false;
  }
  return true;
}

Eigen::VectorXd BorderedSolver::solve(const Eigen::VectorXd& r) const {
  Eigen::VectorXd x(nb_ + ne_);
  if (ne_ == 0) return lu_schur_.solve(r);
  const Eigen::VectorXd y = lu_E_.solve(r.tail(ne_));
  if (nb_ == 0) return y;
  x.head(nb_) = lu_schur_.solve(r.head(nb_) - B_ * y);
  x.tail(ne_) = y - Z_ * x.head(nb_);
  return x;
}

}  // namespace deployfx::integrate
