#pragma once
// Homogeneous Dirichlet constraints by elimination: the free dofs are kept, the fixed ones are
// removed from K and M, and results are scattered back to full size with zeros.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "deployfx/fem/modal.hpp"

namespace deployfx::fem {

/// The sorted dofs of [0, ndof) not in `fixed` (which may be unsorted, with repeats).
std::vector<int> free_dofs(int ndof, const std::vector<int>& fixed);
/// A restricted to the rows and columns `keep`.
Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& A, const std::vector<int>& keep);

/// Solves K u = f with u = 0 on `fixed`. Throws std::invalid_argument if the constrained K is
/// singular (the constraints leave a rigid-body motion).
Eigen::VectorXd static_solve(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                             const std::vector<int>& fixed);

/// Lowest n modes of (K, M) with u = 0 on `fixed`; modes are scattered to full size.
ModalResult constrained_modes(const Eigen::SparseMatrix<double>& K,
                              const Eigen::SparseMatrix<double>& M, int n,
                              const std::vector<int>& fixed);

}  // namespace deployfx::fem
