#pragma once
// The integrator's view of one run on a model (integrate/second_order_system.hpp): the immutable
// Model and the run's Data, every evaluation one of the engine's stages.
#include "deployfx/integrate/second_order_system.hpp"
#include "deployfx/multibody/data.hpp"

namespace deployfx::multibody {

class TreeSystem final : public integrate::SecondOrderSystem {
 public:
  /// Throws std::invalid_argument unless `d` was made for `m`.
  TreeSystem(const Model& m, Data& d);
  int num_positions() const override { return m_.num_positions(); }
  int num_velocities() const override { return m_.num_velocities(); }
  Eigen::VectorXd retract(const Eigen::VectorXd& q, const Eigen::VectorXd& dq) const override {
    return m_.retract(q, dq);
  }
  Eigen::VectorXd residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                           double t) override;
  integrate::BlockMatrix iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                          const Eigen::VectorXd& a, double t, double c_a, double c_v,
                                          double c_q) override;
  integrate::BlockMatrix iteration_matrix_and_momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                                const Eigen::VectorXd& a, double t, double c_a,
                                                                double c_v, double c_q,
                                                                Eigen::MatrixXd& momentum_jacobian) override;
  bool refresh_elastic_blocks(integrate::BlockMatrix& S, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                              const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q) override;
  int num_conserved() const override { return m_.num_conserved(); }
  Eigen::VectorXd momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) override;
  Eigen::MatrixXd momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v,
                                    double c_q) override;
  Eigen::MatrixXd conserved_velocity_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) override;
  Eigen::VectorXd gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) override;
  bool accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t, const Eigen::VectorXd& margin) override;
  StepBounds step_bounds() override;
  double newton_step_limit(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& dv) override;
  /// Every Green-strain panel's in-plane coordinates (FlexibleBody::in_plane_coordinates), at its
  /// elastic block's place in the velocity ordering (Body::iv_el).
  std::vector<int> slaved_velocities() const override;
  /// Their rows by multibody::slaved_rows (mesh panels with Green strain, nothing riding on them).
  bool slaved_residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double t,
                       Eigen::VectorXd& rows) override;

 private:
  const Model& m_;
  Data& d_;
};

}  // namespace deployfx::multibody
