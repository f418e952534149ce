#include "deployfx/fem/ritz_basis.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <stdexcept>
#include <cmath>
#include <string>
#include <utility>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/fem/parity.hpp"

namespace deployfx::fem {
namespace {

// A candidate that keeps less than this of its squared M-norm when M-orthogonalised against the
// ones before it repeats them and is dropped.
constexpr double kDependent = 1e-10;
// Entries of K and M between bending and in-plane dofs below this (relative to the geometric mean
// of their diagonal entries) are round-off: the paper's symmetric lay-ups leave B at 5e-17 of
// sqrt(|A| |D|) (the ply stack's z_k^2 - z_(k-1)^2 not cancelling exactly).
constexpr double kDecoupled = 1e-12;

Eigen::MatrixXd gather_rows(const Eigen::MatrixXd& X, const std::vector<int>& rows) {
  Eigen::MatrixXd out(rows.size(), X.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(k) = X.row(rows[k]);
  return out;
}

struct RitzPairs {
  Eigen::MatrixXd Phi;     // (nf x r), Phi^T M Phi = I
  Eigen::VectorXd omega2;  // ascending
};

// Orthonormalise the candidates in M, in their order, then Rayleigh-Ritz in their span. Gram-
// Schmidt with a second pass ("twice is enough", Parlett, The Symmetric Eigenvalue Problem, 1980,
// Sec. 6-9) keeps Q^T M Q = I to round-off and the first candidates' span exactly. The first
// `n_modes` candidates are eigenvectors: they are K-orthogonal to the rest of the M-orthogonal
// span (phi^T K y = lambda phi^T M y = 0), so Q^T K Q is block diagonal to the eigensolver's
// accuracy, and each mode keeps its own Rayleigh quotient, accurate relative to its own value;
// only the rest is rotated to Ritz vectors. (A dense eigensolver on all of Q^T K Q is accurate to
// eps |Q^T K Q|, the stiff in-plane directions' 1e9: on the [0, 90] laminate the second mode's
// omega^2 came 1.5e-8 below its value, and an eigen-decomposition of the Gram matrix moved the
// first by 8e-6 and left Q^T M Q = I to 4e-7.) Ascending.
RitzPairs rayleigh_ritz(const std::vector<Eigen::VectorXd>& cand, std::size_t n_modes,
                        const SparseMatrix& K, const SparseMatrix& M) {
  std::vector<Eigen::VectorXd> q, Mq;  // q_i^T M q_j = delta_ij
  std::size_t kept_modes = 0;
  for (std::size_t c = 0; c < cand.size(); ++c) {
    const Eigen::VectorXd& x = cand[c];
    const double norm = std::sqrt(x.dot(M * x));
    if (!(norm > 0)) continue;
    Eigen::VectorXd y = x / norm;
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t i = 0; i < q.size(); ++i) y -= Mq[i].dot(y) * q[i];
    Eigen::VectorXd My = M * y;
    const double kept = y.dot(My);
    if (!(kept > kDependent)) continue;
    q.push_back(y / std::sqrt(kept));
    Mq.push_back(My / std::sqrt(kept));
    if (c < n_modes) ++kept_modes;
  }
  const auto n = static_cast<Eigen::Index>(q.size()), nm = static_cast<Eigen::Index>(kept_modes);
  Eigen::MatrixXd Q(K.rows(), n);
  for (Eigen::Index i = 0; i < n; ++i) Q.col(i) = q[static_cast<std::size_t>(i)];
  RitzPairs out{Eigen::MatrixXd(K.rows(), n), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < nm; ++i) out.omega2(i) = Q.col(i).dot(K * Q.col(i));
  out.Phi.leftCols(nm) = Q.leftCols(nm);
  if (n > nm) {
    const Eigen::MatrixXd R = Q.rightCols(n - nm);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(R.transpose() * (K * R));
    out.Phi.rightCols(n - nm) = R * ritz.eigenvectors();
    out.omega2.tail(n - nm) = ritz.eigenvalues();
  }
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return out.omega2(a) < out.omega2(b); });
  RitzPairs sorted{Eigen::MatrixXd(K.rows(), n), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    sorted.Phi.col(i) = out.Phi.col(order[static_cast<std::size_t>(i)]);
    sorted.omega2(i) = out.omega2(order[static_cast<std::size_t>(i)]);
  }
  return sorted;
}

// Rayleigh-Ritz in each parity's part of the span, merged in ascending order (parity.hpp): every
// vector is then exactly bending or exactly in-plane. A candidate's part whose squared M-norm is
// below kDependent of the candidate's is the eigensolver's and the solves' round-off, and dropped.
RitzPairs rayleigh_ritz_by_parity(const std::vector<Eigen::VectorXd>& cand, std::size_t n_modes,
                                  const std::vector<int>& free, const SparseMatrix& K,
                                  const SparseMatrix& M) {
  // A mode's parity parts are modes too (K and M decouple), and come first in each list.
  std::vector<Eigen::VectorXd> bending, in_plane;
  std::size_t modes_b = 0, modes_m = 0;
  for (std::size_t c = 0; c < cand.size(); ++c) {
    const Eigen::VectorXd& x = cand[c];
    Eigen::VectorXd b = x, m = x;
    for (std::size_t k = 0; k < free.size(); ++k)
      (dof_parity(free[k]) == Parity::kBending ? m : b)(static_cast<Eigen::Index>(k)) = 0.0;
    const double total = x.dot(M * x);
    if (b.dot(M * b) > kDependent * total) bending.push_back(b), modes_b += c < n_modes;
    if (m.dot(M * m) > kDependent * total) in_plane.push_back(m), modes_m += c < n_modes;
  }
  const RitzPairs rb = rayleigh_ritz(bending, modes_b, K, M), rm = rayleigh_ritz(in_plane, modes_m, K, M);
  RitzPairs out{Eigen::MatrixXd(K.rows(), rb.Phi.cols() + rm.Phi.cols()),
                Eigen::VectorXd(rb.omega2.size() + rm.omega2.size())};
  for (Eigen::Index c = 0, ib = 0, im = 0; c < out.omega2.size(); ++c) {
    const bool take_b = im == rm.omega2.size() || (ib < rb.omega2.size() && rb.omega2(ib) <= rm.omega2(im));
    const RitzPairs& from = take_b ? rb : rm;
    Eigen::Index& i = take_b ? ib : im;
    out.Phi.col(c) = from.Phi.col(i);
    out.omega2(c) = from.omega2(i++);
  }
  return out;
}

}  // namespace

RitzBasis ritz_basis(const ShellModel& model, const std::vector<int>& fixed,
                     const RitzBasisOptions& options, const Eigen::MatrixXd& inertial_loads) {
  const std::vector<int> free = free_dofs(model.num_dofs(), fixed);
  const int nf = static_cast<int>(free.size());
  if (options.modes < 1 || options.modes > nf)
    throw std::invalid_argument("modes = " + std::to_string(options.modes) +
                                " is out of range: must be in [1, " + std::to_string(nf) + "] (the free dofs)");
  if (options.derivative_modes < 0 || options.derivative_modes > options.modes)
    throw std::invalid_argument("derivative_modes = " + std::to_string(options.derivative_modes) +
                                " is out of range: must be in [0, modes]");
  if (options.derivative_partners < 0 || options.derivative_partners > options.modes)
    throw std::invalid_argument("derivative_partners = " + std::to_string(options.derivative_partners) +
                                " is out of range: must be in [0, modes]");
  const SparseMatrix K = restrict(model.stiffness(), free), M = restrict(model.mass(), free);
  const bool by_parity = parity_decoupled(K, free, kDecoupled) && parity_decoupled(M, free, kDecoupled);
  const ModalResult modal = lowest_modes(K, M, options.modes);

  std::vector<Eigen::VectorXd> cand;  // candidates on the free dofs, the modes first
  for (int i = 0; i < options.modes; ++i) cand.push_back(modal.modes.col(i));
  const auto n_modes = static_cast<std::size_t>(options.modes);
  Eigen::SimplicialLDLT<SparseMatrix> K_inv;
  const bool derivatives = options.derivative_modes > 0 || options.derivative_partners > 0;
  if ((options.static_correction && inertial_loads.cols() > 0) || derivatives) {
    K_inv.compute(K);
    if (K_inv.info() != Eigen::Success || !(K_inv.vectorD().minCoeff() > 0))
      throw std::invalid_argument(
          "ritz_basis: fixed_dofs leave a rigid-body motion of the appendage: its clamped "
          "stiffness is singular (fix more dofs, e.g. the root edge)");
  }
  int n_static = 0, n_deriv = 0;
  if (options.static_correction && inertial_loads.cols() > 0) {
    if (inertial_loads.rows() != model.num_dofs())
      throw std::invalid_argument("inertial_loads must have one row per dof");
    const Eigen::MatrixXd F = gather_rows(inertial_loads, free);
    for (int c = 0; c < F.cols(); ++c) cand.push_back(K_inv.solve(F.col(c))), ++n_static;
  }
  if (derivatives) {
    // f(d) is cubic in d (Eq. 14: Green strain is quadratic), so its even part is exactly the
    // quadratic term f2: f2(x) = (f(x) + f(-x)) / 2, and d(K_T phi_i)/d phi_j = 2 f2(phi_i, phi_j)
    // with f2(x, y) = (f2(x + y) - f2(x - y)) / 4.
    auto f2 = [&](const Eigen::VectorXd& x_free) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_dofs()), fp, fm;
      for (int k = 0; k < nf; ++k) x(free[k]) = x_free(k);
      model.internal_force(x, &fp, nullptr);
      model.internal_force(-x, &fm, nullptr);
      const Eigen::VectorXd even = 0.5 * (fp + fm);
      Eigen::VectorXd out(nf);
      for (int k = 0; k < nf; ++k) out(k) = even(free[k]);
      return out;
    };
    // Where the span splits by parity, the derivative of two bending vectors is exactly in-plane
    // (q keeps the parity); its bending part is the round-off of f's odd part in the even part,
    // eps |K x|, which the soft bending compliance amplifies: 4e-10 of the M-norm squared for the
    // first mode with a static correction's direction beyond the modes (6 x 4, lay-up 2), above
    // kDependent, where it would join the basis as a spurious stiff bending vector. Dropped.
    auto derivative = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
      const Eigen::VectorXd dK = 0.5 * (f2(a + b) - f2(a - b));
      cand.push_back(-K_inv.solve(dK)), ++n_deriv;
      if (by_parity)
        for (int k = 0; k < nf; ++k)
          if (dof_parity(free[k]) == Parity::kBending) cand.back()(k) = 0.0;
    };
    const int nd = options.derivative_modes, np = options.derivative_partners;
    for (int i = 0; i < nd; ++i)
      for (int j = i; j < nd; ++j) derivative(modal.modes.col(i), modal.modes.col(j));
    // The partners: pairs (i, j), i < np, i <= j < modes, not among the above.
    for (int i = 0; i < np; ++i)
      for (int j = std::max(i, i < nd ? nd : 0); j < options.modes; ++j)
        derivative(modal.modes.col(i), modal.modes.col(j));
    if (np > 0) {
      // The static corrections' directions beyond the modes: their bending parts where the span
      // splits by parity (an in-plane direction's "derivative" would be a bending vector, the
      // in-plane prestress's, not the membrane relaxation sought), M-orthogonalised against the
      // modes and each other as in rayleigh_ritz (the same kept directions), M-normalised like
      // the modes: f2's even part cancels the linear force's round-off, eps |K x|, which for a
      // small x would swamp the quadratic |x|^2 (a static correction of a unit load is ~1e-5).
      std::vector<Eigen::VectorXd> dirs, Mdirs;
      for (int c = 0; c < options.modes; ++c) {
        dirs.push_back(modal.modes.col(c));
        Mdirs.push_back(M * dirs.back());
      }
      for (int c = 0; c < n_static; ++c) {
        const Eigen::VectorXd& x = cand[n_modes + static_cast<std::size_t>(c)];
        Eigen::VectorXd y = x;
        if (by_parity)
          for (int k = 0; k < nf; ++k)
            if (dof_parity(free[k]) != Parity::kBending) y(k) = 0.0;
        const double norm = std::sqrt(y.dot(M * y));
        if (!(norm * norm > kDependent * x.dot(M * x))) continue;  // as rayleigh_ritz_by_parity
        y /= norm;
        for (int pass = 0; pass < 2; ++pass)
          for (std::size_t q = 0; q < dirs.size(); ++q) y -= Mdirs[q].dot(y) * dirs[q];
        const Eigen::VectorXd My = M * y;
        const double kept = y.dot(My);
        if (!(kept > kDependent)) continue;
        dirs.push_back(y / std::sqrt(kept));
        Mdirs.push_back(My / std::sqrt(kept));
      }
      for (int i = 0; i < np; ++i)
        for (std::size_t s = n_modes; s < dirs.size(); ++s) derivative(modal.modes.col(i), dirs[s]);
    }
  }
  const RitzPairs ritz = by_parity ? rayleigh_ritz_by_parity(cand, n_modes, free, K, M)
                                   : rayleigh_ritz(cand, n_modes, K, M);
  const Eigen::MatrixXd& Phi_free = ritz.Phi;

  RitzBasis basis;
  basis.Phi = Eigen::MatrixXd::Zero(model.num_dofs(), Phi_free.cols());
  for (int k = 0; k < nf; ++k) basis.Phi.row(free[k]) = Phi_free.row(k);
  basis.omega2 = ritz.omega2;
  basis.modes = options.modes;
  basis.static_corrections = n_static;
  basis.modal_derivatives = n_deriv;
  return basis;
}

}  // namespace deployfx::fem
