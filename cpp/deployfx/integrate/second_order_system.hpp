#pragma once
// The interface an integrator needs from a mechanical system written in residual form
//   r(q, v, a, t) = M(q) a - f(q, v, t) = 0,
// with configuration q (which may live on a manifold: retract() maps a tangent increment onto it),
// velocity v and acceleration a (both of size num_velocities()).
#include <Eigen/Core>

namespace deployfx::integrate {

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int num_positions() const = 0;
  virtual int num_velocities() const = 0;
  /// q (+) dq: the configuration reached from q by the tangent increment dq. Default q + dq.
  virtual Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const {
    return q + dq;
  }
  /// r(q, v, a, t).
  virtual Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                   const Eigen::VectorXd& a, double t) const = 0;
  /// S = c_a dr/da + c_v dr/dv + c_q dr/dq, the Newton iteration matrix of an implicit scheme
  /// (dr/dq taken along retract()).
  virtual Eigen::MatrixXd iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                           const Eigen::VectorXd& a, double t, double c_a,
                                           double c_v, double c_q) const = 0;
};

}  // namespace deployfx::integrate
