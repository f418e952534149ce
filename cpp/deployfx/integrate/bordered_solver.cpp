#include "deployfx/integrate/bordered_solver.hpp"

#include <cmath>

#include "deployfx/math/sparse_slot.hpp"

namespace deployfx::integrate {

void BorderedSolver::analyze(const SparseMatrix& E) {
  pattern_nnz_ = E.nonZeros();
  pattern_rows_ = E.rows();
  lu_analyzed_ = false;
  // The slot of each nonzero's transpose partner, if E's pattern is structurally symmetric.
  transpose_.clear();
  const int* outer = E.outerIndexPtr();
  const int* inner = E.innerIndexPtr();
  for (int j = 0; j < E.outerSize(); ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k) {
      const Eigen::Index partner = sparse_slot(E, j, inner[k]);
      if (partner < 0) {
        transpose_.clear();  // not structurally symmetric: the exact LU only
        return;
      }
      transpose_.push_back(static_cast<int>(partner));
    }
  E_sym_ = E;
  E_skew_ = E;
  block_E_.analyze(E_sym_);
  ldlt_analyzed_ = false;  // analysed when first needed
}

const char* BorderedSolver::method() const {
  if (ne_ == 0) return "none";
  switch (method_) {
    case Method::kDense: return "dense-lu";
    case Method::kSymmetric: return block_ ? "block-ldlt" : "simplicial-ldlt";
    case Method::kExact: break;
  }
  return "sparse-lu";
}

bool BorderedSolver::factorize_symmetric_part() {
  block_ = block_E_.analyzed() && block_E_.factorize(E_sym_);
  if (block_) return true;
  if (!ldlt_analyzed_) {
    ldlt_E_.analyzePattern(E_sym_);
    ldlt_analyzed_ = true;
  }
  ldlt_E_.factorize(E_sym_);
  return ldlt_E_.info() == Eigen::Success && ldlt_E_.vectorD().cwiseAbs().minCoeff() > 0;
}

Eigen::VectorXd BorderedSolver::solve_symmetric(const Eigen::VectorXd& r) const {
  return block_ ? block_E_.solve(r) : Eigen::VectorXd(ldlt_E_.solve(r));
}

bool BorderedSolver::factorize_symmetric(const SparseMatrix& E) {
  if (transpose_.empty() || skew_tolerance_ <= 0) return false;
  // Es = (E + E^T)/2, Ek = (E - E^T)/2, written in the values' order (each partner read at random).
  const double* v = E.valuePtr();
  double* sym = E_sym_.valuePtr();
  double* skew = E_skew_.valuePtr();
  const int* t = transpose_.data();
  for (std::size_t k = 0; k < transpose_.size(); ++k) {
    const double a = v[k], b = v[t[k]];
    sym[k] = 0.5 * (a + b);
    skew[k] = 0.5 * (a - b);
  }
  if (!factorize_symmetric_part()) return false;
  // The dropped part makes the Newton iteration contract at the spectral radius of Es^-1 Ek
  // (0 for a symmetric E): estimated by two power iterations from Es^-1 1, a smooth field that
  // holds the low, mass-dominated modes the gyroscopic coupling acts on. The estimate runs 2-10x
  // below the radius (paper's scene 1e-4 against 3e-4, the spin-up beam at 20 rad/s 3e-3 against
  // 3e-2), hence the tolerance's margin; the refinement in solve() converges for any radius < 1.
  // With a border, Es^-1 1 is solved with Z = Es^-1 C, as one more column of the border's (a
  // hinge's 7 and it fill the block solve's eight: about a tenth of a solve instead of one).
  Eigen::MatrixXd Zy;
  Eigen::VectorXd y;
  if (C_.cols() > 0) {
    Eigen::MatrixXd rhs(ne_, C_.cols() + 1);
    rhs << C_, Eigen::VectorXd::Ones(ne_);
    Zy = solve_symmetric_block(rhs);
    y = Zy.rightCols<1>();
  } else {
    y = solve_symmetric(Eigen::VectorXd::Ones(ne_));
  }
  Eigen::VectorXd x = y;
  for (int k = 0; k < 2; ++k) x = solve_symmetric(skew_product(x));
  const double rate = std::sqrt(x.norm() / y.norm());
  if (!(rate <= skew_tolerance_)) return false;
  Zy.conservativeResize(ne_, C_.cols());
  Z_ = std::move(Zy);
  return Z_.allFinite();
}

Eigen::MatrixXd BorderedSolver::solve_symmetric_block(const Eigen::MatrixXd& B) const {
  if (block_) return block_E_.solve(B);  // by rows of up to eight columns (BlockLDLT::solve)
  // Es = P^T L D L^T P. Eigen's solve with a matrix right-hand side runs the triangular solves
  // column by column, streaming L once per column; here every nonzero of L updates a whole row of
  // the right-hand sides (padded to kWidth contiguous values: one fixed-size vector operation), so
  // L is streamed twice in all. The border of a hinged system has at most 7 columns.
  constexpr int kWidth = 8;
  const SparseMatrix& L = ldlt_E_.matrixL().nestedExpression();
  if (B.cols() > kWidth || !L.isCompressed()) return ldlt_E_.solve(B);
  using Block = Eigen::Matrix<double, Eigen::Dynamic, kWidth, Eigen::RowMajor>;
  const Eigen::Index n = L.cols();
  Block X = Block::Zero(n, kWidth);
  const bool permuted = ldlt_E_.permutationP().size() > 0;
  X.leftCols(B.cols()) = permuted ? Eigen::MatrixXd(ldlt_E_.permutationP() * B) : B;
  const int* outer = L.outerIndexPtr();
  const int* row = L.innerIndexPtr();
  const double* value = L.valuePtr();
  for (Eigen::Index j = 0; j < n; ++j)  // L y = P b (unit lower, by columns)
    for (int p = outer[j]; p < outer[j + 1]; ++p) X.row(row[p]) -= value[p] * X.row(j);
  X.array().colwise() /= ldlt_E_.vectorD().array();
  for (Eigen::Index j = n - 1; j >= 0; --j)  // L^T x = D^-1 y: row j of L^T is column j of L
    for (int p = outer[j]; p < outer[j + 1]; ++p) X.row(j) -= value[p] * X.row(row[p]);
  const Eigen::MatrixXd x = X.leftCols(B.cols());
  return permuted ? Eigen::MatrixXd(ldlt_E_.permutationPinv() * x) : x;
}

bool BorderedSolver::factorize_exact(const SparseMatrix& E) {
  if (!lu_analyzed_) {
    lu_E_.analyzePattern(E);
    lu_analyzed_ = true;
  }
  lu_E_.factorize(E);
  if (lu_E_.info() != Eigen::Success) return false;
  Z_ = lu_E_.solve(C_);
  return true;
}

bool BorderedSolver::factorize_dense(const BlockMatrix& S) {
  // S whole, [A B; C E]: one LU with pivoting across border and elastic rows, no Schur complement.
  auto lu = dense_lu_.matrix(nb_ + ne_);
  lu.topLeftCorner(nb_, nb_) = S.A;
  lu.topRightCorner(nb_, ne_) = S.B;
  lu.bottomLeftCorner(ne_, nb_) = S.C;
  auto E = lu.bottomRightCorner(ne_, ne_);
  E.setZero();
  for (int j = 0; j < S.E.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(S.E, j); it; ++it) E(it.row(), it.col()) = it.value();
  return dense_lu_.factorize();
}

Eigen::VectorXd BorderedSolver::solve_elastic(const Eigen::VectorXd& r) const {
  return method_ == Method::kSymmetric ? solve_symmetric(r) : Eigen::VectorXd(lu_E_.solve(r));
}

bool BorderedSolver::factorize(const BlockMatrix& S) {
  nb_ = S.border();
  ne_ = S.elastic();
  ++factorizations_;
  // Without an elastic block, or with a dense one (half full or more), S is factorized whole.
  if (ne_ == 0 || 2 * static_cast<double>(S.E.nonZeros()) >= static_cast<double>(ne_) * ne_) {
    method_ = Method::kDense;
    return factorize_dense(S);
  }
  if (!S.E.isCompressed()) return false;
  C_ = S.C;
  // The pattern of E is fixed by the mesh; re-analyse only if it changed.
  if (S.E.nonZeros() != pattern_nnz_ || S.E.rows() != pattern_rows_) analyze(S.E);
  method_ = factorize_symmetric(S.E) ? Method::kSymmetric : Method::kExact;
  if (method_ == Method::kExact && !factorize_exact(S.E)) return false;
  B_ = S.B;
  A_ = S.A;
  if (nb_ == 0) return true;
  Eigen::MatrixXd schur = A_;
  schur.noalias() -= B_ * Z_;
  lu_schur_.compute(schur);
  const double pivot = lu_schur_.matrixLU().diagonal().cwiseAbs().minCoeff();
  return pivot > 1e-300 && schur.allFinite();
}

Eigen::VectorXd BorderedSolver::solve_factorized(const Eigen::VectorXd& r) const {
  if (method_ == Method::kDense) return dense_lu_.solve(r);
  const Eigen::VectorXd y = solve_elastic(r.tail(ne_));
  if (nb_ == 0) return y;
  Eigen::VectorXd x(nb_ + ne_);
  x.head(nb_) = lu_schur_.solve(r.head(nb_) - B_ * y);
  x.tail(ne_) = y - Z_ * x.head(nb_);
  return x;
}

namespace {

// Column c of a matrix stored by columns, gathered against x with four chains of sums (a mesh
// column holds 6 to 54 entries): (P^T x)_c for P's values `value` on `pattern`.
template <class Value>
double gathered(const Eigen::SparseMatrix<double>& pattern, Eigen::Index c, const Value& value,
                const Eigen::Ref<const Eigen::VectorXd>& x) {
  const int* outer = pattern.outerIndexPtr();
  const int* row = pattern.innerIndexPtr();
  double sum[4] = {0, 0, 0, 0};
  int k = outer[c];
  for (; k + 4 <= outer[c + 1]; k += 4)
    for (int l = 0; l < 4; ++l) sum[l] += value(k + l) * x[row[k + l]];
  for (; k < outer[c + 1]; ++k) sum[0] += value(k) * x[row[k]];
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

}  // namespace

Eigen::VectorXd BorderedSolver::skew_product(const Eigen::VectorXd& x) const {
  // Ek x = -Ek^T x: gathered by columns (no scatter).
  const double* skew = E_skew_.valuePtr();
  Eigen::VectorXd y(E_skew_.cols());
  for (Eigen::Index c = 0; c < E_skew_.outerSize(); ++c) y[c] = -gathered(E_skew_, c, [&](int k) { return skew[k]; }, x);
  return y;
}

void BorderedSolver::subtract_elastic_product(const Eigen::Ref<const Eigen::VectorXd>& x,
                                              Eigen::Ref<Eigen::VectorXd> y) const {
  // E x = (Es + Ek) x = (Es - Ek)^T x: column c of Es - Ek (stored by columns) gathered against x
  // gives (E x)_c. One pass over both value arrays, no scatter (two sparse products by columns,
  // Es x and Ek x, scattered each term: 2.7 % of the nonlinear model's run).
  const double* sym = E_sym_.valuePtr();
  const double* skew = E_skew_.valuePtr();
  for (Eigen::Index c = 0; c < E_sym_.outerSize(); ++c)
    y[c] -= gathered(E_sym_, c, [&](int k) { return sym[k] - skew[k]; }, x);
}

Eigen::VectorXd BorderedSolver::solve(const Eigen::VectorXd& r, bool exact) const {
  Eigen::VectorXd x = solve_factorized(r);
  if (method_ != Method::kSymmetric || !exact) return x;
  // Iterative refinement against S itself, with the factorization of [A B; C Es] as the
  // preconditioner: each step shrinks the error by the radius of Es^-1 Ek (<= skew_tolerance), to
  // 1e-8 of x (on Newton's last increments, 1e-10 of the accelerations, an error of 1e-18):
  // Newton takes the iterates the exact LU gives. The error left after a correction dx is
  // estimated as |dx| rho / (1 - rho), rho the ratio of the last two corrections (Hairer & Wanner's
  // estimate for a linearly converging iteration), so the correction that would only confirm
  // convergence (a solve and two products) is not taken: two corrections on the paper's scene.
  double previous = 0;
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd res(nb_ + ne_);
    const auto xb = x.head(nb_);
    const auto xe = x.tail(ne_);
    res.head(nb_) = r.head(nb_) - A_ * xb - B_ * xe;
    res.tail(ne_) = r.tail(ne_) - C_ * xb;
    subtract_elastic_product(xe, res.tail(ne_));
    const Eigen::VectorXd dx = solve_factorized(res);
    x += dx;
    const double size = dx.lpNorm<Eigen::Infinity>();
    const double rho = previous > 0 ? size / previous : 1.0;
    const double error = rho < 0.5 ? size * rho / (1 - rho) : size;
    if (!(error > 1e-8 * x.lpNorm<Eigen::Infinity>())) break;
    previous = size;
  }
  return x;
}

}  // namespace deployfx::integrate
