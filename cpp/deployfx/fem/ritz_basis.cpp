#include "deployfx/fem/ritz_basis.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <stdexcept>
#include <cmath>
#include <string>

#include "deployfx/fem/constrained_solve.hpp"

namespace deployfx::fem {
namespace {

// Directions of X (columns) whose M-normalised Gram matrix has an eigenvalue below this (relative
// to its largest) repeat others and are dropped.
constexpr double kDependent = 1e-10;

Eigen::MatrixXd gather_rows(const Eigen::MatrixXd& X, const std::vector<int>& rows) {
  Eigen::MatrixXd out(rows.size(), X.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(k) = X.row(rows[k]);
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
  const SparseMatrix K = restrict(model.stiffness(), free), M = restrict(model.mass(), free);
  const ModalResult modal = lowest_modes(K, M, options.modes);

  std::vector<Eigen::VectorXd> cand;  // candidates on the free dofs
  for (int i = 0; i < options.modes; ++i) cand.push_back(modal.modes.col(i));
  Eigen::SimplicialLDLT<SparseMatrix> K_inv;
  const int n_extra = (options.static_correction ? static_cast<int>(inertial_loads.cols()) : 0) +
                      options.derivative_modes * (options.derivative_modes + 1) / 2;
  if (n_extra > 0) {
    K_inv.compute(K);
    if (K_inv.info() != Eigen::Success || !(K_inv.vectorD().minCoeff() > 0))
      throw std::runtime_error("ritz_basis: the clamped stiffness is singular (fix more dofs)");
  }
  int n_static = 0, n_deriv = 0;
  if (options.static_correction && inertial_loads.cols() > 0) {
    if (inertial_loads.rows() != model.num_dofs())
      throw std::invalid_argument("inertial_loads must have one row per dof");
    const Eigen::MatrixXd F = gather_rows(inertial_loads, free);
    for (int c = 0; c < F.cols(); ++c) cand.push_back(K_inv.solve(F.col(c))), ++n_static;
  }
  if (options.derivative_modes > 0) {
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
    for (int i = 0; i < options.derivative_modes; ++i)
      for (int j = i; j < options.derivative_modes; ++j) {
        const Eigen::VectorXd &a = modal.modes.col(i), &b = modal.modes.col(j);
        const Eigen::VectorXd dK = 0.5 * (f2(a + b) - f2(a - b));
        cand.push_back(-K_inv.solve(dK)), ++n_deriv;
      }
  }
  // Orthonormalise the span in M (dropping repeated directions), then Rayleigh-Ritz in it.
  Eigen::MatrixXd X(nf, cand.size());
  for (std::size_t c = 0; c < cand.size(); ++c) {
    const double norm = std::sqrt(cand[c].dot(M * cand[c]));
    X.col(c) = norm > 0 ? Eigen::VectorXd(cand[c] / norm) : cand[c];
  }
  const Eigen::MatrixXd MX = M * X;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(X.transpose() * MX);
  const Eigen::VectorXd& g = gram.eigenvalues();
  std::vector<int> keep;
  for (int c = 0; c < g.size(); ++c)
    if (g(c) > kDependent * g.maxCoeff()) keep.push_back(c);
  Eigen::MatrixXd Y(X.cols(), keep.size());
  for (std::size_t c = 0; c < keep.size(); ++c)
    Y.col(c) = gram.eigenvectors().col(keep[c]) / std::sqrt(g(keep[c]));
  const Eigen::MatrixXd Q = X * Y;  // Q^T M Q = I
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(Q.transpose() * (K * Q));
  const Eigen::MatrixXd Phi_free = Q * ritz.eigenvectors();

  RitzBasis basis;
  basis.Phi = Eigen::MatrixXd::Zero(model.num_dofs(), Phi_free.cols());
  for (int k = 0; k < nf; ++k) basis.Phi.row(free[k]) = Phi_free.row(k);
  basis.omega2 = ritz.eigenvalues();
  basis.modes = options.modes;
  basis.static_corrections = n_static;
  basis.modal_derivatives = n_deriv;
  return basis;
}

}  // namespace deployfx::fem
