#include "deployfx/fem/parity.hpp"

#include <cmath>
#include <stdexcept>

namespace deployfx::fem {

Parity vector_parity(const Eigen::Ref<const Eigen::VectorXd>& x) {
  bool bending = false, in_plane = false;
  for (int k = 0; k < static_cast<int>(x.size()); ++k)
    if (x(k) != 0.0) (dof_parity(k) == Parity::kBending ? bending : in_plane) = true;
  if (bending && in_plane) return Parity::kMixed;
  return bending ? Parity::kBending : Parity::kInPlane;
}

bool parity_decoupled(const Eigen::SparseMatrix<double>& A, const std::vector<int>& dofs, double tol) {
  if (A.rows() != static_cast<Eigen::Index>(dofs.size()) || A.cols() != A.rows())
    throw std::invalid_argument("parity_decoupled: A must be square with one row per dof");
  const Eigen::VectorXd diag = A.diagonal().cwiseAbs();
  for (int j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      if (dof_parity(dofs[i]) == dof_parity(dofs[j])) continue;
      if (!(std::abs(it.value()) <= tol * std::sqrt(diag(i) * diag(j)))) return false;
    }
  return true;
}

}  // namespace deployfx::fem
