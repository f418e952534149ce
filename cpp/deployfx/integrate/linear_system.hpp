#pragma once
// M a + C v + K q = 0: a linear second-order system, the reference problem for the integrators'
// accuracy and stability (Hughes, "The Finite Element Method", 1987, Ch. 9).
#include <Eigen/Core>

#include "deployfx/integrate/second_order_system.hpp"

namespace deployfx::integrate {

class LinearSystem final : public SecondOrderSystem {
 public:
  /// Throws std::invalid_argument unless M, C, K are square, finite and of one size.
  LinearSystem(Eigen::MatrixXd M, Eigen::MatrixXd C, Eigen::MatrixXd K);
  int num_positions() const override { return static_cast<int>(M_.rows()); }
  int num_velocities() const override { return static_cast<int>(M_.rows()); }
  Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& a, double t) override;
  BlockMatrix iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                   const Eigen::VectorXd& a, double t, double c_a, double c_v,
                                   double c_q) override;

 private:
  Eigen::MatrixXd M_, C_, K_;
};

}  // namespace deployfx::integrate
