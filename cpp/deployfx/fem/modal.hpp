#pragma once
// Lowest eigenpairs of the generalised symmetric problem K x = lambda M x of structural dynamics
// (K symmetric positive semi-definite, M symmetric positive definite, both sparse with both
// triangles stored): spectral-transformation block Lanczos with full reorthogonalisation, locking
// and a Sylvester-inertia certificate that no eigenvalue below the returned ones was missed.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <optional>

namespace deployfx::fem {

/// Lowest eigenpairs of K x = lambda M x.
struct ModalResult {
  Eigen::VectorXd eigenvalues;  ///< (n) lambda = omega^2 in (rad/s)^2, ascending
  Eigen::MatrixXd modes;        ///< (ndof x n) M-orthonormal: modes^T M modes = I
};

/// Shift-invert block Lanczos (block size 6) with full reorthogonalisation, locking of converged
/// pairs and a Sylvester inertia check (details in modal.cpp).
/// `shift` is sigma in (rad/s)^2; it must lie below the lowest eigenvalue (K - sigma M positive
/// definite). Pass std::nullopt for the automatic choice: sigma = 0 if K is safely non-singular,
/// else a small negative sigma scaled from the problem (free structures).
/// `tol` bounds the residual of each pair relative to its eigenvalue of (K - sigma M)^-1 M.
/// Eigenvalues are sigma + 1/nu and are not clamped: rigid-body modes may come out as tiny
/// negative numbers. Each mode has its largest-magnitude component positive.
/// Throws std::invalid_argument (message names the parameter, value and allowed range) for bad
/// input: n < 1 or n > ndof, non-square or mismatched sizes, non-finite entries, asymmetric K or
/// M, a non-positive diagonal of M, tol outside [1e-14, 1e-2], a non-finite shift.
/// Throws std::runtime_error if the factorisation fails (or K - shift M is not positive
/// definite) or the iteration does not converge.
ModalResult lowest_modes(const Eigen::SparseMatrix<double>& K,
                         const Eigen::SparseMatrix<double>& M, int n,
                         std::optional<double> shift = std::nullopt, double tol = 1e-10);

}  // namespace deployfx::fem
