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
  Eigen::MatrixXd A_full(r * r, r);
  std::vector<Eigen::MatrixXd> even(r);  // B_kk
  for (int k = 0; k < r; ++k) {
    const Eigen::VectorXd e = s(k) * Eigen::VectorXd::Unit(r, k);
    const Eigen::MatrixXd Tp = T(e), Tm = T(-e);
    A_full.col(k) = Eigen::Map<const Eigen::VectorXd>(Eigen::MatrixXd((Tp - Tm) / (2 * s(k))).data(), r * r);
    even[k] = (Tp + Tm - 2 * K_) / (s(k) * s(k));
  }
  // T(e) + T(-e) - 2 K = s_k^2 B_kk + 2 s_k s_l B_kl + s_l^2 B_ll for e = s_k e_k + s_l e_l.
  // Stored packed: row p(i, j) (i <= j) of column k (A) or of pair column p(k, l) (B).
  const int np = r * (r + 1) / 2;
  A_.resize(np, r);
  for (int k = 0; k < r; ++k) A_.col(k) = pack(A_full.col(k), r);
  B_.resize(np, np);
  int col = 0;
  for (int k = 0; k < r; ++k)
    for (int l = k; l < r; ++l, ++col) {
      Eigen::MatrixXd Bkl = even[k];
      if (l != k) {
        const Eigen::VectorXd e = s(k) * Eigen::VectorXd::Unit(r, k) + s(l) * Eigen::VectorXd::Unit(r, l);
        Bkl = (T(e) + T(-e) - 2 * K_ - s(k) * s(k) * even[k] - s(l) * s(l) * even[l]) / (2 * s(k) * s(l));
      }
      B_.col(col) = pack(Eigen::Map<const Eigen::VectorXd>(Bkl.data(), r * r), r);
    }
  // B_kl(i, j) is a fourth derivative of the strain energy, so B_ is symmetric: keep the mean
  // of the two probe estimates of each entry (only the upper triangle is read).
  B_ = (0.5 * (B_ + B_.transpose())).eval();
}

Eigen::VectorXd ModalInternalForce::pack(const Eigen::Ref<const Eigen::VectorXd>& vec_T, int r) {
  // The symmetric part of the (r x r) matrix vec_T, upper triangle, pair order (0,0), (0,1), ...
  Eigen::VectorXd out(r * (r + 1) / 2);
  int p = 0;
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j) out(p++) = 0.5 * (vec_T(i + r * j) + vec_T(j + r * i));
  return out;
}

void ModalInternalForce::polynomial(const Eigen::VectorXd& eta, Eigen::MatrixXd* A,
                                    Eigen::MatrixXd* B) const {
  const std::lock_guard<std::mutex> lock(memo_.mutex);
  if (memo_.eta.size() == eta.size() && memo_.eta == eta) {
    *A = memo_.A;
    *B = memo_.B;
    return;
  }
  const int r = size();
  Eigen::VectorXd pairs(r * (r + 1) / 2);  // eta_k eta_l, twice for k < l (B_kl = B_lk)
  int col = 0;
  for (int k = 0; k < r; ++k)
    for (int l = k; l < r; ++l) pairs(col++) = (l == k ? 1.0 : 2.0) * eta(k) * eta(l);
  const Eigen::VectorXd a = A_ * eta;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(pairs.size());
  b.noalias() += B_.selfadjointView<Eigen::Upper>() * pairs;
  A->resize(r, r);
  B->resize(r, r);
  int p = 0;
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j, ++p) {
      (*A)(i, j) = (*A)(j, i) = a(p);
      (*B)(i, j) = (*B)(j, i) = b(p);
    }
  memo_.eta = eta;
  memo_.A = *A;
  memo_.B = *B;
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
