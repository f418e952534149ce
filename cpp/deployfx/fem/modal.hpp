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

/// Shift-invert block Lanczos (block size 6) with full reorthogonalisation and locking; every
/// result is certified by Sylvester's law of inertia (the LDL^T of K - s M, s just above the n-th
/// eigenvalue, has as many negative pivots as eigenvalues were found below s), so repeated
/// eigenvalues (rigid-body modes, double modes of symmetric structures) come with their full
/// multiplicity. Deterministic: fixed pseudo-random start vectors. Method notes in modal.cpp.
/// `shift` is sigma in (rad/s)^2 and must lie below the lowest eigenvalue (K - sigma M positive
/// definite); std::nullopt chooses sigma = 0 when K is safely non-singular, else the smallest
/// negative sigma certified safe for the LDL^T (free structures).
/// `tol` bounds each pair's residual ||Op x - nu x||_M <= tol nu, Op = (K - sigma M)^-1 M.
/// Eigenvalues are sigma + 1/nu and are not clamped: rigid-body modes come out at round-off, of
/// either sign. Each mode has its largest-magnitude component positive. When the Lanczos basis
/// would span the whole space (max(3 n, 2 n + 60) >= ndof), or when it cannot grow because the
/// eigenvalues still wanted lie beyond ~1e12 times the shift (round-off), the dense generalised
/// solver answers (up to ndof = 3000; beyond, std::invalid_argument naming n).
/// Throws std::invalid_argument (message names the parameter, value and allowed range) for bad
/// input: n < 1 or n > ndof, non-square or mismatched sizes, non-finite entries, asymmetric K or
/// M, a non-positive diagonal of M, tol outside [1e-14, 1e-2], a non-finite shift.
/// Throws std::runtime_error if a factorisation fails, K - shift M is not positive definite, M is
/// found indefinite, or the iteration does not converge.
ModalResult lowest_modes(const Eigen::SparseMatrix<double>& K,
                         const Eigen::SparseMatrix<double>& M, int n,
                         std::optional<double> shift = std::nullopt, double tol = 1e-10);

}  // namespace deployfx::fem
