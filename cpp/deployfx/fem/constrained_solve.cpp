#include "deployfx/fem/constrained_solve.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace deployfx::fem {

std::vector<int> free_dofs(int ndof, const std::vector<int>& fixed) {
  std::vector<char> is_fixed(ndof, 0);
  for (int d : fixed) {
    if (d < 0 || d >= ndof)
      throw std::invalid_argument("fixed dof " + std::to_string(d) + " is out of range: must be in [0, " +
                                  std::to_string(ndof - 1) + "]");
    is_fixed[d] = 1;
  }
  std::vector<int> keep;
  keep.reserve(ndof);
  for (int d = 0; d < ndof; ++d)
    if (!is_fixed[d]) keep.push_back(d);
  return keep;
}

Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& A, const std::vector<int>& keep) {
  std::vector<int> map(A.rows(), -1);
  for (std::size_t k = 0; k < keep.size(); ++k) map[keep[k]] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(A.nonZeros());
  for (int c = 0; c < A.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it)
      if (map[it.row()] >= 0 && map[it.col()] >= 0) t.emplace_back(map[it.row()], map[it.col()], it.value());
  Eigen::SparseMatrix<double> R(keep.size(), keep.size());
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

Eigen::VectorXd static_solve(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                             const std::vector<int>& fixed) {
  if (f.size() != K.rows())
    throw std::invalid_argument("load has wrong size: expected " + std::to_string(K.rows()) +
                                ", got " + std::to_string(f.size()));
  const std::vector<int> keep = free_dofs(static_cast<int>(K.rows()), fixed);
  if (keep.empty()) return Eigen::VectorXd::Zero(K.rows());
  Eigen::VectorXd f_free(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) f_free(k) = f(keep[k]);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(restrict(K, keep));
  // A singular K shows as a pivot at round-off level relative to the largest.
  const Eigen::VectorXd D = ldlt.info() == Eigen::Success ? ldlt.vectorD() : Eigen::VectorXd();
  if (D.size() == 0 || !(D.minCoeff() > 1e-12 * D.cwiseAbs().maxCoeff()))
    throw std::invalid_argument(
        "static solve: fixed_dofs (the boundary) leave a rigid-body motion: the stiffness of the "
        "free dofs is singular (fix more dofs or edges)");
  const Eigen::VectorXd u_free = ldlt.solve(f_free);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(K.rows());
  for (std::size_t k = 0; k < keep.size(); ++k) u(keep[k]) = u_free(k);
  return u;
}

ModalResult constrained_modes(const Eigen::SparseMatrix<double>& K,
                              const Eigen::SparseMatrix<double>& M, int n,
                              const std::vector<int>& fixed) {
  const std::vector<int> keep = free_dofs(static_cast<int>(K.rows()), fixed);
  if (n < 1 || n > static_cast<int>(keep.size()))
    throw std::invalid_argument("n = " + std::to_string(n) + " is out of range: must be in [1, " +
                                std::to_string(keep.size()) + "] (the free dofs)");
  ModalResult r = lowest_modes(restrict(K, keep), restrict(M, keep), n);
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(K.rows(), r.modes.cols());
  for (std::size_t k = 0; k < keep.size(); ++k) full.row(keep[k]) = r.modes.row(k);
  r.modes = std::move(full);
  return r;
}

}  // namespace deployfx::fem
