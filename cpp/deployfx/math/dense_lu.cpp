#include "deployfx/math/dense_lu.hpp"

#include <cmath>
#include <utility>

namespace deployfx {

bool DenseLU::factorize() {
  const Eigen::Index n = lu_.rows();
  if (lu_.cols() != n) return false;
  blocked_ = n > kUnblocked;
  if (blocked_) {
    blocked_lu_.compute(lu_);
    const Eigen::MatrixXd& f = blocked_lu_.matrixLU();
    return f.diagonal().cwiseAbs().minCoeff() > 1e-300 && f.allFinite();
  }
  pivot_.resize(static_cast<std::size_t>(n));
  double* a = lu_.data();  // column-major, leading dimension n
  for (Eigen::Index k = 0; k < n; ++k) {
    double* ck = a + k * n;
    Eigen::Index p = k;
    double largest = std::abs(ck[k]);
    for (Eigen::Index i = k + 1; i < n; ++i)
      if (std::abs(ck[i]) > largest) largest = std::abs(ck[i]), p = i;
    if (!(largest > 1e-300) || !std::isfinite(largest)) return false;
    pivot_[static_cast<std::size_t>(k)] = static_cast<int>(p);
    if (p != k)
      for (Eigen::Index j = 0; j < n; ++j) std::swap(a[k + j * n], a[p + j * n]);
    const double inverse = 1.0 / ck[k];
    for (Eigen::Index i = k + 1; i < n; ++i) ck[i] *= inverse;  // column k of L
    for (Eigen::Index j = k + 1; j < n; ++j) {  // the trailing matrix less l_k u_k^T
      double* cj = a + j * n;
      const double u = cj[k];
      for (Eigen::Index i = k + 1; i < n; ++i) cj[i] -= ck[i] * u;
    }
  }
  return lu_.allFinite();  // a non-finite entry off the pivots' path
}

void DenseLU::solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const {
  if (blocked_) {
    x = blocked_lu_.solve(Eigen::VectorXd(x));
    return;
  }
  for (std::size_t k = 0; k < pivot_.size(); ++k)
    if (pivot_[k] != static_cast<int>(k)) std::swap(x(static_cast<Eigen::Index>(k)), x(pivot_[k]));
  lu_.triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu_.triangularView<Eigen::Upper>().solveInPlace(x);
}

}  // namespace deployfx
