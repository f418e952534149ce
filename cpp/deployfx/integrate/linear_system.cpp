#include "deployfx/integrate/linear_system.hpp"

#include <stdexcept>

namespace deployfx::integrate {

LinearSystem::LinearSystem(Eigen::MatrixXd M, Eigen::MatrixXd C, Eigen::MatrixXd K)
    : M_(std::move(M)), C_(std::move(C)), K_(std::move(K)) {
  const auto n = M_.rows();
  for (const Eigen::MatrixXd* A : {&M_, &C_, &K_})
    if (A->rows() != n || A->cols() != n || !A->allFinite())
      throw std::invalid_argument("LinearSystem: M, C and K must be finite square matrices of one size");
}

Eigen::VectorXd LinearSystem::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                       const Eigen::VectorXd& a, double) {
  return M_ * a + C_ * v + K_ * q;
}

BlockMatrix LinearSystem::iteration_matrix(const Eigen::VectorXd&, const Eigen::VectorXd&,
                                           const Eigen::VectorXd&, double, double c_a, double c_v,
                                           double c_q) {
  return BlockMatrix::from_dense(c_a * M_ + c_v * C_ + c_q * K_);
}

}  // namespace deployfx::integrate
