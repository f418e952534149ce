#include "deployfx/fem/modal.hpp"

// Method, with sources:
// - Spectral transformation (Ericsson & Ruhe, Math. Comp. 35, 1980, 1251-1268): the lowest lambda
//   become the dominant, well separated eigenvalues nu = 1/(lambda - sigma) of Op = (K - sigma
//   M)^-1 M, symmetric in the M inner product; K - sigma M is factored once (SimplicialLDLT, AMD).
//   Start vectors lie in the range of Op (Nour-Omid, Parlett, Ericsson & Jensen, Math. Comp. 48,
//   1987, 663-673); locked vectors are purified by one implicit Op step.
// - Block Lanczos (Golub & Underwood 1977; Grimes, Lewis & Simon, SIAM J. Matrix Anal. Appl. 15,
//   1994), block size 6, so that a multiplicity <= 6 (rigid-body modes, double modes of a square)
//   enters the Krylov space at once; full reorthogonalisation by two classical Gram-Schmidt passes
//   ("twice is enough", Parlett, The Symmetric Eigenvalue Problem, 1998, Sec. 6.9). Converged
//   pairs are locked (later Krylov spaces are M-orthogonal to them).
// - Certificate, Sylvester's law of inertia: K - s M has as many negative LDL^T pivots as there are
//   eigenvalues below s. For s just above the n-th value found, that count must equal the number
//   found below s; if larger, the missing ones are the dominant eigenvalues of Op on the
//   M-complement of the locked vectors and are searched there (any multiplicity is found).
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deployfx/math/check.hpp"

namespace deployfx::fem {
namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr int kBlock = 6;     // Lanczos block size
constexpr int kMaxRuns = 60;  // Lanczos runs (restarts, inertia-driven searches)

// Deterministic pseudo-random numbers in [-1, 1) from a counter: the splitmix64 finaliser (Steele,
// Lea & Flood, OOPSLA 2014). Start vectors then have components along the modes of every symmetry
// class of a symmetric structure, and results are the same on every run.
double uniform(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return static_cast<double>((x ^ (x >> 31)) >> 11) * 0x1.0p-52 - 1.0;
}

std::vector<int> ascending(const std::vector<double>& v) {
  std::vector<int> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return v[a] < v[b]; });
  return order;
}

template <class... Args>
[[noreturn]] void fail(const Args&... args) {
  std::ostringstream e;
  e << "lowest_modes: ";
  (e << ... << args);
  throw std::runtime_error(e.str());
}

// A Lanczos run that cannot extend its basis: every new direction is round-off of the locked
// ones, i.e. the eigenvalues still wanted lie beyond ~1e12 (lambda_1 - sigma) from the shift,
// where their nu = 1/(lambda - sigma) vanish below the round-off of the dominant ones (a free
// plate's rotary-inertia and drilling modes: Plate(2.0, 1.3, lam, 3, 2), n = 58 of 72, "FFFF").
struct Stalled {};

struct Pivots {
  bool ok = false;     // the LDL^T exists (no zero pivot)
  int negative = 0;    // = number of eigenvalues below the shift (Sylvester)
  double min_rel = 0;  // min_i D_i / |A_ii|, A in elimination order
};

struct Locked {
  std::vector<double> lam, unc;  // eigenvalues sigma + 1/theta, their round-off uncertainty
  MatrixXd X, MX;                // (ndof x L) eigenvectors, M-orthonormal, and M X
};

class Solver {
 public:
  // Exact zeros are pruned: flat shell regions store many (membrane-bending decoupling), and
  // dropping them halves the fill of the LDL^T.
  Solver(const SpMat& K, const SpMat& M)
      : K_(K.pruned()), M_(M.pruned()), kd_(K.diagonal()), ndof_(static_cast<int>(K.rows())) {
    F_.analyzePattern(SpMat(K_ - 0.0 * M_));  // the union pattern, that of K - s M for every s
  }

  Pivots factor(double s) {  // F <- LDL^T of K - s M
    const SpMat A = K_ - s * M_;
    F_.factorize(A);
    Pivots p;
    const VectorXd& D = F_.vectorD();
    if (!(p.ok = F_.info() == Eigen::Success && D.allFinite())) return p;
    const VectorXd d = F_.permutationP() * VectorXd(A.diagonal());
    p.min_rel = (D.array() / d.array().abs().max(std::numeric_limits<double>::min())).minCoeff();
    p.negative = static_cast<int>((D.array() < 0).count());
    return p;
  }

  // With F = LDL^T of K - sigma M: locks pairs until Sylvester's law certifies the n lowest.
  void solve(double sigma, int n, double tol, Locked& lk) {
    int need = n;
    MatrixXd start;  // best unconverged Ritz vectors of the last run
    for (int r = 0; r < kMaxRuns; ++r) {
      const int L = static_cast<int>(lk.X.cols());
      if (L < need) {
        if (L >= ndof_) throw Stalled{};  // the inertia counts more eigenvalues than dofs
        const int b = std::min(ndof_ - L, std::max(kBlock, static_cast<int>(start.cols())));
        const int keep = std::min(b, static_cast<int>(start.cols()));
        MatrixXd S = random(b);
        if (keep > 0) S.leftCols(keep) = start.leftCols(keep);
        start = run(sigma, S, std::min(need - L, ndof_ - L), tol, lk);
        continue;
      }
      // s above the cluster of the n-th value found, below the next value. Values closer than
      // their uncertainty are one cluster: the Ritz error (10 tol (lambda - sigma)) plus the
      // round-off of the LDL^T, whose backward error |E_ij| <~ c eps sqrt(K_ii K_jj) (Higham,
      // Accuracy and Stability of Numerical Algorithms, 2002, Thm. 10.5) moves an eigenvalue by
      // <~ c eps x^T diag(K) x (M-normalised x); rigid-body modes spread over ~eps x^T diag(K) x.
      const std::vector<int> o = ascending(lk.lam);
      std::vector<double> mu(L), du(L);
      const double scale = lk.lam[o[n - 1]] - sigma;
      for (int i = 0; i < L; ++i)
        mu[i] = lk.lam[o[i]], du[i] = std::max(1e-8, 10 * tol) * scale + lk.unc[o[i]];
      int j = n - 1;
      while (j + 1 < L && mu[j + 1] - mu[j] <= du[j] + du[j + 1]) ++j;
      double s = mu[j] + std::max(0.01 * scale, 2 * du[j]);
      if (j + 1 < L) s = std::min(s, 0.5 * (mu[j] + mu[j + 1]));
      Pivots p = factor(s);
      if (!p.ok) p = factor(s = mu[j] + 0.7 * (s - mu[j]));
      if (!p.ok) fail("the LDL^T of K - s M failed for the inertia check, s = ", s);
      const int found = static_cast<int>(std::lower_bound(mu.begin(), mu.end(), s) - mu.begin());
      if (p.negative == found) return;
      if (p.negative < found)
        fail("inconsistent inertia check: ", found, " eigenvalues found below ", s,
             " but K - s M has ", p.negative, " negative pivots");
      need = L + (p.negative - found);  // missing ones: search the complement
      factor(sigma);
    }
    fail("no convergence to tol = ", tol, " after ", kMaxRuns, " Lanczos runs (", lk.X.cols(),
         " of ", n, " pairs converged)");
  }

 private:
  MatrixXd random(int cols) {
    MatrixXd R(ndof_, cols);
    for (int j = 0; j < cols; ++j)
      for (int i = 0; i < ndof_; ++i) R(i, j) = uniform(counter_++);
    return R;
  }

  // W <- (I - Q Q^T M) W for Q = [X, V(:, from:m)] by two Gram-Schmidt passes with the stored
  // M Q. Returns the V coefficients of the W passed in; adds the squared coefficients to *c2.
  MatrixXd project(const Locked& lk, const MatrixXd& V, const MatrixXd& MV, int from, int m,
                   MatrixXd& W, VectorXd* c2 = nullptr) const {
    MatrixXd H = MatrixXd::Zero(m - from, W.cols());
    for (int pass = 0; pass < 2; ++pass) {
      if (lk.X.cols() > 0) {
        const MatrixXd C = lk.MX.transpose() * W;
        W.noalias() -= lk.X * C;
        if (c2) *c2 += C.colwise().squaredNorm().transpose();
      }
      if (m > from) {
        const MatrixXd C = MV.middleCols(from, m - from).transpose() * W;
        W.noalias() -= V.middleCols(from, m - from) * C;
        H += C;
      }
    }
    if (c2) *c2 += H.colwise().squaredNorm().transpose();
    return H;
  }

  // Appends the columns of W (M-orthogonal to [X, V(:, 0:m)], squared M-norms ref2 before any
  // projection) to the basis, each M-orthogonalised against those appended before it. A column
  // with nothing new above round-off (1e-12 of its norm) is replaced by a pseudo-random vector in
  // the range of Op, so blocks keep their size until the whole space is spanned.
  void add_block(const Locked& lk, MatrixXd& V, MatrixXd& MV, int& m, const MatrixXd& W,
                 const VectorXd& ref2) {
    const int m0 = m;
    for (int j = 0; j < W.cols() && m < V.cols(); ++j) {
      MatrixXd w = W.col(j);
      double r2 = ref2(j);
      for (int attempt = 0; attempt < 2; ++attempt) {
        project(lk, V, MV, attempt == 0 ? m0 : 0, m, w);
        const VectorXd mw = M_ * w.col(0);
        const double q = w.col(0).dot(mw);
        if (q > 1e-24 * r2) {
          V.col(m) = w.col(0) / std::sqrt(q);
          MV.col(m++) = mw / std::sqrt(q);
          break;
        }
        if (lk.X.cols() + m >= ndof_) break;
        w = F_.solve(M_ * random(1));
        r2 = w.col(0).dot(M_ * w.col(0));
      }
    }
  }

  // One block Lanczos run on Op restricted to the M-complement of the locked vectors, from the
  // start block Op S, until the `want` largest Ritz values have converged or the basis is full.
  // Locks converged Ritz pairs; returns the best unconverged Ritz vectors.
  MatrixXd run(double sigma, const MatrixXd& S, int want, double tol, Locked& lk) {
    const int b = static_cast<int>(S.cols());
    const int cap = std::min(ndof_ - static_cast<int>(lk.X.cols()),
                             std::max({3 * want, 2 * want + 10 * kBlock, 3 * b}));
    MatrixXd V(ndof_, cap), MV(ndof_, cap), T = MatrixXd::Zero(cap, cap);
    int m = 0;
    MatrixXd W = F_.solve(M_ * S);
    VectorXd ref2 = VectorXd::Zero(b);
    project(lk, V, MV, 0, 0, W, &ref2);
    add_block(lk, V, MV, m, W, ref2 + W.cwiseProduct(M_ * W).colwise().sum().transpose());
    if (m == 0) throw Stalled{};  // (an empty T would also be out of the eigensolver's bounds)
    Eigen::SelfAdjointEigenSolver<MatrixXd> es;
    for (int b0 = 0;;) {
      const int b1 = m, nb = b1 - b0;
      W = F_.solve(MV.middleCols(b0, nb));
      ref2.setZero(nb);
      const MatrixXd H = project(lk, V, MV, 0, b1, W, &ref2);
      T.block(0, b0, b1, nb) = H;
      T.block(b0, 0, nb, b1) = H.transpose();
      T.block(b0, b0, nb, nb) = 0.5 * (H.bottomRows(nb) + H.bottomRows(nb).transpose());
      es.compute(T.topLeftCorner(b1, b1));
      // Krylov relation Op V = V T + W E^T: the Ritz pair (theta, V y) has the residual
      // ||Op V y - theta V y||_M = ||W y_last||_M, y_last = the rows of y of the newest block.
      const MatrixXd MW = M_ * W, G = W.transpose() * MW;
      if ((G.diagonal().array() < 0).any()) fail("M is not positive definite (x^T M x < 0)");
      ref2 += G.diagonal();  // Pythagoras: |w|^2 = |coefficients|^2 + |remainder|^2
      const VectorXd& theta = es.eigenvalues();  // ascending
      const auto Yl = es.eigenvectors().middleRows(b0, nb).transpose();
      const VectorXd res2 = (Yl * G).cwiseProduct(Yl).rowwise().sum();
      auto converged = [&](int i) { return theta(i) > 0 && std::sqrt(res2(i)) <= tol * theta(i); };
      bool done = b1 >= want;
      for (int i = b1 - 1; done && i >= b1 - want; --i) done = converged(i);
      // Early locking: converged Ritz values above a gap of 1e3 (rigid-body modes at a tiny
      // shift, nu = 1/alpha) would limit the others to an absolute accuracy ~eps theta_max in the
      // eigensolver of T. They are locked alone and the run restarted.
      int top = b1;  // [top, b1) is locked alone
      for (int i = b1 - 1; i > 0 && converged(i) && top == b1; --i)
        if (theta(i) > 1e3 * theta(i - 1)) top = i;
      if (top == b1 && !done && m + nb <= cap) add_block(lk, V, MV, m, W, ref2);
      if (top == b1 && m > b1) {
        b0 = b1;
        continue;
      }
      // Only Ritz vectors with theta >= 1e-3 theta_max are carried to the next run: the others
      // are accurate to ~eps theta_max / theta only.
      std::vector<int> lock, carry;
      const std::size_t ncarry = std::max(kBlock, want);
      for (int i = b1 - 1; i >= 0; --i) {
        if (converged(i) && (top == b1 || i >= top))
          lock.push_back(i);
        else if (theta(i) >= 1e-3 * theta(b1 - 1) && carry.size() < ncarry)
          carry.push_back(i);
      }
      // Purification (Ericsson & Ruhe 1980, Sec. 4): Op x / theta = V y + W y_last / theta needs
      // no solve and damps the high-mode error of x by nu_high / theta. The purified vectors have
      // the M-Gram matrix I + Z^T G Z (W is M-orthogonal to V): orthonormalise symmetrically.
      const int L = static_cast<int>(lk.X.cols()), nl = static_cast<int>(lock.size());
      if (nl > 0) {
        MatrixXd Y(b1, nl), Z(nb, nl);
        for (int k = 0; k < nl; ++k) {
          Y.col(k) = es.eigenvectors().col(lock[k]);
          Z.col(k) = Y.col(k).segment(b0, nb) / theta(lock[k]);
          lk.lam.push_back(sigma + 1.0 / theta(lock[k]));
        }
        const MatrixXd gram = MatrixXd::Identity(nl, nl) + Z.transpose() * G * Z;
        const MatrixXd C = Eigen::SelfAdjointEigenSolver<MatrixXd>(gram).operatorInverseSqrt();
        lk.X.conservativeResize(ndof_, L + nl);
        lk.MX.conservativeResize(ndof_, L + nl);
        lk.X.rightCols(nl) = (V.leftCols(b1) * Y + W * Z) * C;
        lk.MX.rightCols(nl) = (MV.leftCols(b1) * Y + MW * Z) * C;
        for (int k = 0; k < nl; ++k) lk.unc.push_back(1e-13 * kd_.dot(lk.X.col(L + k).cwiseAbs2()));
      }
      MatrixXd next(ndof_, carry.size());
      for (std::size_t k = 0; k < carry.size(); ++k)
        next.col(k) = V.leftCols(b1) * es.eigenvectors().col(carry[k]);
      return next;
    }
  }

  const SpMat K_, M_;
  const VectorXd kd_;  // diagonal of K
  const int ndof_;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>> F_;
  std::uint64_t counter_ = 0;  // position in the pseudo-random sequence
};

// The dense path's size limit: ndof^2 doubles for each of K, M and the eigenvectors (200 MB).
constexpr int kMaxDense = 3000;

// Dense Cholesky-QR on the problem equilibrated by S = diag(M)^-1/2 (S K S y = lambda S M S y,
// x = S y): a shell's rotary inertia is ~1e-6 of its translational mass, and without the scaling
// the lowest eigenvalues lose ~3 more digits (5e-7 against 1e-10 relative for the 3 x 2 plate).
ModalResult dense_modes(const SpMat& K, const SpMat& M, int n) {
  const int ndof = static_cast<int>(K.rows());
  const VectorXd s = M.diagonal().cwiseSqrt().cwiseInverse();
  const MatrixXd Kd = s.asDiagonal() * MatrixXd(K) * s.asDiagonal();
  const MatrixXd Md = s.asDiagonal() * MatrixXd(M) * s.asDiagonal();
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> dense(Kd, Md);
  if (dense.info() != Eigen::Success) fail("the dense eigensolver failed: M must be positive definite");
  ModalResult r;
  r.eigenvalues = dense.eigenvalues().head(n);
  r.modes.resize(ndof, n);
  for (int j = 0; j < n; ++j) {
    const VectorXd x = s.asDiagonal() * dense.eigenvectors().col(j);
    Eigen::Index imax = 0;
    x.cwiseAbs().maxCoeff(&imax);
    r.modes.col(j) = x(imax) < 0 ? VectorXd(-x) : x;
  }
  if (!r.eigenvalues.allFinite() || !r.modes.allFinite())
    fail("the dense eigensolver returned non-finite values: K and M are too ill-conditioned");
  return r;
}

void check_matrix(const SpMat& A, const std::string& name, Eigen::Index ndof) {
  std::ostringstream e;
  if (A.rows() != ndof || A.cols() != ndof || ndof < 1) {
    e << name << " is " << A.rows() << " x " << A.cols() << ": must be square and non-empty, the "
      << "size of K (" << ndof << " x " << ndof << ")";
    throw std::invalid_argument(e.str());
  }
  double amax = 0;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) {
      if (!std::isfinite(it.value()))
        throw_out_of_range(name + "(" + std::to_string(it.row()) + ", " +
                               std::to_string(it.col()) + ")", it.value(), "finite");
      amax = std::max(amax, std::abs(it.value()));
    }
  const SpMat asym = A - SpMat(A.transpose());
  const double d = asym.nonZeros() > 0 ? asym.coeffs().cwiseAbs().maxCoeff() : 0.0;
  if (d > 1e-10 * amax) {
    e << name << " is not symmetric: max |" << name << " - " << name << "^T| = " << d
      << " must be <= 1e-10 max |" << name << "| = " << 1e-10 * amax << " (store both triangles)";
    throw std::invalid_argument(e.str());
  }
}

}  // namespace

ModalResult lowest_modes(const SpMat& K, const SpMat& M, int n, std::optional<double> shift,
                         double tol) {
  check_matrix(K, "K", K.rows());
  check_matrix(M, "M", K.rows());
  const int ndof = static_cast<int>(K.rows());
  if (n < 1 || n > ndof) throw_out_of_range("n", n, "in [1, " + std::to_string(ndof) + "] (ndof)");
  if (!(tol >= 1e-14 && tol <= 1e-2)) throw_out_of_range("tol", tol, "in [1e-14, 1e-2]");
  if (shift) require_finite("shift", *shift, "(rad/s)^2");
  const VectorXd kd = K.diagonal(), md = M.diagonal();
  for (int i = 0; i < ndof; ++i)
    if (!(md(i) > 0))
      throw_out_of_range("M(" + std::to_string(i) + ", " + std::to_string(i) + ")", md(i),
                         "> 0 (M must be positive definite)");

  // Nearly all pairs wanted: a Krylov space of blocks of 6 cannot grow past ndof, so the dense
  // generalised problem answers, for the same cost class (also when Lanczos stalls, below).
  if (n > ndof - 2 * kBlock) return dense_modes(K, M, n);

  Solver solver(K, M);
  double sigma = 0;
  if (shift) {
    const Pivots p = solver.factor(sigma = *shift);
    if (!p.ok || p.negative > 0)
      fail("K - shift M is not positive definite for shift = ", *shift, " (", p.negative,
           " negative pivots, factorisation ", p.ok ? "ok" : "failed", "): the shift must lie "
           "below the lowest eigenvalue; pass std::nullopt for the automatic choice");
  } else if (const Pivots p0 = solver.factor(0.0); !(p0.ok && p0.min_rel > 1e-10)) {
    // Automatic shift. sigma = 0 if K is safely non-singular: for a positive definite A,
    // D_i / A_ii >= lambda_min(diag(A)^-1/2 A diag(A)^-1/2), while a singular K shows pivots at
    // round-off level (~1e-16 relative) or negative ones; the test is unit-invariant.
    // Otherwise (free structure) sigma = -alpha_s:
    // (a) safe trial alpha_g = 1e-8 max_i K_ii / M_ii (<= 1e-8 lambda_max), raised 100-fold until
    //     K + alpha_g M factors with positive pivots >= 1e-13 |A_ii|;
    // (b) each pivot D_i(alpha) is concave in alpha (a Schur complement) and D_i(0) >= 0 (K is
    //     semi-definite), so D_i(alpha) >= (alpha / alpha_g) D_i(alpha_g) for alpha <= alpha_g:
    //     alpha_s = 1e-10 alpha_g / min_i (D_i / |A_ii|)(alpha_g) is the smallest shift that is
    //     certified to keep every pivot >= 1e-10 |A_ii|, far above round-off. It is usually far
    //     below the first elastic eigenvalue, so the elastic nu ~ 1/lambda are as with sigma = 0,
    //     while the rigid-body nu ~ 1/alpha_s converge within two steps and are locked early.
    const double rho = (kd.array() / md.array()).maxCoeff();
    double ag = (rho > 0 ? rho : 1.0) * 1e-8;
    Pivots pg;
    for (int t = 0; !((pg = solver.factor(-ag)).ok && pg.negative == 0 && pg.min_rel > 1e-13);
         ++t, ag *= 100)
      if (t == 4) fail("K + alpha M is not positive definite for alpha = ", ag,
                       ": K must be positive semi-definite");
    double as = std::min(ag, 1e-10 * ag / pg.min_rel);
    if (as < ag) {
      const Pivots ps = solver.factor(-as);
      if (!(ps.ok && ps.negative == 0 && ps.min_rel > 1e-11)) solver.factor(-(as = ag));
    }
    sigma = -as;
  }
  Locked lk;
  try {
    solver.solve(sigma, n, tol, lk);
  } catch (const Stalled&) {
    if (ndof > kMaxDense) {
      std::ostringstream e;
      e << "n = " << n << " is out of range for this model: the " << n << " lowest eigenvalues "
        << "reach beyond 1e12 times the shift, where shift-invert Lanczos cannot resolve them, "
        << "and ndof = " << ndof << " is above " << kMaxDense << " for the dense solver; ask for "
        << "fewer modes (" << lk.X.cols() << " were resolved)";
      throw std::invalid_argument(e.str());
    }
    return dense_modes(K, M, n);
  }

  const std::vector<int> order = ascending(lk.lam);
  ModalResult r;
  r.eigenvalues.resize(n);
  r.modes.resize(ndof, n);
  for (int j = 0; j < n; ++j) {
    const VectorXd x = lk.X.col(order[j]);
    Eigen::Index imax = 0;
    x.cwiseAbs().maxCoeff(&imax);
    r.eigenvalues(j) = lk.lam[order[j]];
    r.modes.col(j) = x(imax) < 0 ? VectorXd(-x) : x;
  }
  return r;
}

}  // namespace deployfx::fem
