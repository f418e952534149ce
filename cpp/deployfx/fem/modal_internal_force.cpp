#include "deployfx/fem/modal_internal_force.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace deployfx::fem {

ModalInternalForce::ModalInternalForce(const ShellModel& model, const Eigen::MatrixXd& Phi,
                                       bool green_strain)
    : green_(green_strain) {
  if (Phi.rows() != model.num_dofs() || Phi.cols() < 1 || !Phi.allFinite())
    throw std::invalid_argument("ModalInternalForce: the basis must be finite with one row per dof (" +
                                std::to_string(model.num_dofs()) + ") and at least one column");
  const int r = static_cast<int>(Phi.cols());
  K_ = Phi.transpose() * (model.stiffness() * Phi);
  K_ = 0.5 * (K_ + K_.transpose()).eval();
  if (!green_) return;
  auto T = [&](const Eigen::VectorXd& eta) {
    SparseMatrix KT;
    model.internal_force(Phi * eta, nullptr, &KT);
    return Eigen::MatrixXd(Phi.transpose() * (KT * Phi));
  };
  // Probe amplitudes: exact for any, but round-off scales with the largest entry of T(probe).
  // Each coordinate is probed at the same strain energy (1/2 K_kk s_k^2 = that of a unit probe of
  // the most flexible one, a large deflection), so stiff in-plane vectors are probed at small
  // strains instead of unit amplitude (which would bury the bending block under their membrane
  // forces).
  const Eigen::VectorXd k_diag = K_.diagonal().cwiseMax(1e-300);
  Eigen::VectorXd s(r);
  for (int k = 0; k < r; ++k) s(k) = std::sqrt(k_diag.minCoeff() / k_diag(k));
  A_.resize(r * r, r);
  std::vector<Eigen::MatrixXd> even(r);  // B_kk
  for (int k = 0; k < r; ++k) {
    const Eigen::VectorXd e = s(k) * Eigen::VectorXd::Unit(r, k);
    const Eigen::MatrixXd Tp = T(e), Tm = T(-e);
    A_.col(k) = Eigen::Map<const Eigen::VectorXd>(Eigen::MatrixXd((Tp - Tm) / (2 * s(k))).data(), r * r);
    even[k] = (Tp + Tm - 2 * K_) / (s(k) * s(k));
  }
  // T(e) + T(-e) - 2 K = s_k^2 B_kk + 2 s_k s_l B_kl + s_l^2 B_ll for e = s_k e_k + s_l e_l.
  B_.resize(r * r, r * (r + 1) / 2);
  int col = 0;
  for (int k = 0; k < r; ++k)
    for (int l = k; l < r; ++l, ++col) {
      Eigen::MatrixXd Bkl = even[k];
      if (l != k) {
        const Eigen::VectorXd e = s(k) * Eigen::VectorXd::Unit(r, k) + s(l) * Eigen::VectorXd::Unit(r, l);
        Bkl = (T(e) + T(-e) - 2 * K_ - s(k) * s(k) * even[k] - s(l) * s(l) * even[l]) / (2 * s(k) * s(l));
      }
      B_.col(col) = Eigen::Map<const Eigen::VectorXd>(Bkl.data(), r * r);
    }
}

void ModalInternalForce::polynomial(const Eigen::VectorXd& eta, Eigen::MatrixXd* A,
                                    Eigen::MatrixXd* B) const {
  const int r = size();
  Eigen::VectorXd pairs(r * (r + 1) / 2);  // eta_k eta_l, twice for k < l (B_kl = B_lk)
  int col = 0;
  for (int k = 0; k < r; ++k)
    for (int l = k; l < r; ++l) pairs(col++) = (l == k ? 1.0 : 2.0) * eta(k) * eta(l);
  const Eigen::VectorXd a = A_ * eta, b = B_ * pairs;
  *A = Eigen::Map<const Eigen::MatrixXd>(a.data(), r, r);
  *B = Eigen::Map<const Eigen::MatrixXd>(b.data(), r, r);
}

void ModalInternalForce::evaluate(const Eigen::VectorXd& eta, Eigen::VectorXd* f, Eigen::MatrixXd* T) const {
  if (eta.size() != size())
    throw std::invalid_argument("eta has wrong size: expected " + std::to_string(size()) + ", got " +
                                std::to_string(eta.size()));
  if (!green_) {
    if (f) *f = K_ * eta;
    if (T) *T = K_;
    return;
  }
  Eigen::MatrixXd A, B;
  polynomial(eta, &A, &B);
  if (f) *f = K_ * eta + (0.5 * A + B / 6.0) * eta;
  if (T) *T = K_ + A + 0.5 * B;
}

double ModalInternalForce::strain_energy(const Eigen::VectorXd& eta) const {
  if (eta.size() != size())
    throw std::invalid_argument("eta has wrong size: expected " + std::to_string(size()));
  double U = 0.5 * eta.dot(K_ * eta);
  if (green_) {
    Eigen::MatrixXd A, B;
    polynomial(eta, &A, &B);
    U += eta.dot(A * eta) / 6.0 + eta.dot(B * eta) / 24.0;
  }
  return U;
}

}  // namespace deployfx::fem
