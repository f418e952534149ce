#include "deployfx/multibody/tree_system.hpp"

#include "deployfx/multibody/events.hpp"
#include "deployfx/multibody/momentum.hpp"
#include "deployfx/multibody/newton_matrix.hpp"
#include "deployfx/multibody/residual.hpp"

namespace deployfx::multibody {

TreeSystem::TreeSystem(const Model& m, Data& d) : m_(m), d_(d) { check_data(m, d); }

Eigen::VectorXd TreeSystem::residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                                     double t) {
  return multibody::residual(m_, d_, q, v, a, t);
}

integrate::BlockMatrix TreeSystem::iteration_matrix(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                    const Eigen::VectorXd& a, double t, double c_a, double c_v,
                                                    double c_q) {
  return newton_matrix(m_, d_, q, v, a, t, c_a, c_v, c_q);
}

integrate::BlockMatrix TreeSystem::iteration_matrix_and_momentum_jacobian(const Eigen::VectorXd& q,
                                                                          const Eigen::VectorXd& v,
                                                                          const Eigen::VectorXd& a, double t,
                                                                          double c_a, double c_v, double c_q,
                                                                          Eigen::MatrixXd& momentum_jacobian) {
  return newton_matrix(m_, d_, q, v, a, t, c_a, c_v, c_q, &momentum_jacobian);
}

bool TreeSystem::refresh_elastic_blocks(integrate::BlockMatrix& S, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                        const Eigen::VectorXd& a, double t, double c_a, double c_v, double c_q) {
  return refresh_panel_blocks(m_, d_, q, v, a, t, c_a, c_v, c_q, S);
}

Eigen::VectorXd TreeSystem::momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
  return multibody::momentum(m_, d_, q, v, t);
}

Eigen::MatrixXd TreeSystem::momentum_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double c_v,
                                              double c_q) {
  return multibody::momentum_jacobian(m_, d_, q, v, c_v, c_q);
}

Eigen::MatrixXd TreeSystem::conserved_velocity_jacobian(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t) {
  return base_velocity_jacobian(m_, d_, q, v, t);
}

Eigen::VectorXd TreeSystem::gaps(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double) {
  return lock_events(m_, d_, q, v);
}

bool TreeSystem::accept(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double t, const Eigen::VectorXd& margin) {
  return multibody::accept(m_, d_, q, v, t, margin);
}

integrate::SecondOrderSystem::StepBounds TreeSystem::step_bounds() { return multibody::step_bounds(m_, d_); }

double TreeSystem::newton_step_limit(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& dv) {
  return friction_step_limit(m_, d_, q, v, dv);
}

bool TreeSystem::slaved_residual(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                                 double t, Eigen::VectorXd& rows) {
  return multibody::slaved_rows(m_, d_, q, v, a, t, rows);
}

std::vector<int> TreeSystem::slaved_velocities() const { return multibody::slaved_velocities(m_); }

}  // namespace deployfx::multibody
