#pragma once
// The shell model's internal force in a Ritz basis, d = Phi eta, exactly. With Green strain
// (You et al. 2016 Eq. 14) the strain is quadratic in d, so the strain energy is quartic and the
// projected tangent T(eta) = Phi^T K_T(Phi eta) Phi is a quadratic polynomial in eta:
//   T(eta) = K + A(eta) + B(eta) / 2,   A(eta) = sum_k eta_k A_k,  B(eta) = sum_kl eta_k eta_l B_kl,
//   f(eta) = K eta + A(eta) eta / 2 + B(eta) eta / 6,
//   U(eta) = eta^T K eta / 2 + eta^T A(eta) eta / 6 + eta^T B(eta) eta / 24,
// the geometric stiffening of the reduced model in modal form (Mignolet et al., J. Sound Vib.
// 332, 2013: the "stiffness evaluation" of the polynomial coefficients). The coefficients are
// recovered exactly (to round-off) from symmetric pairs T(+x), T(-x): the odd part of T is A, the
// even part K + B/2. Linear strain keeps K only.
#include <Eigen/Core>

#include "deployfx/fem/shell_model.hpp"

namespace deployfx::fem {

class ModalInternalForce {
 public:
  /// Phi: (ndof x r) basis. green_strain: the nonlinear coefficients (r (r + 1) tangent
  /// assemblies, once); otherwise f = K eta.
  ModalInternalForce(const ShellModel& model, const Eigen::MatrixXd& Phi, bool green_strain);

  int size() const { return static_cast<int>(K_.rows()); }
  bool green_strain() const { return green_; }
  /// K = Phi^T K_L Phi, (r x r).
  const Eigen::MatrixXd& linear_stiffness() const { return K_; }
  /// f(eta) and/or T(eta) (either may be null).
  void evaluate(const Eigen::VectorXd& eta, Eigen::VectorXd* f, Eigen::MatrixXd* T) const;
  /// U(eta), J.
  double strain_energy(const Eigen::VectorXd& eta) const;

 private:
  // A(eta) and B(eta) as (r x r) matrices.
  void polynomial(const Eigen::VectorXd& eta, Eigen::MatrixXd* A, Eigen::MatrixXd* B) const;
  bool green_ = false;
  Eigen::MatrixXd K_;
  Eigen::MatrixXd A_;  // (r^2 x r): column k is vec(A_k)
  Eigen::MatrixXd B_;  // (r^2 x r (r + 1) / 2): column of pair k <= l is vec(B_kl)
};

}  // namespace deployfx::fem
