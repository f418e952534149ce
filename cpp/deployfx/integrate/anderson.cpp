#include "deployfx/integrate/anderson.hpp"

#include <Eigen/QR>

namespace deployfx::integrate {

Eigen::VectorXd AndersonMixing::next(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  if (m_ <= 0) return x + f;
  if (!x_.empty() && x_.back().size() != x.size()) reset();
  x_.push_back(x), f_.push_back(f);
  if (static_cast<int>(x_.size()) > m_ + 1) x_.erase(x_.begin()), f_.erase(f_.begin());
  const int k = static_cast<int>(x_.size()) - 1;
  if (k == 0) return x + f;
  Eigen::MatrixXd dX(x.size(), k), dF(x.size(), k);
  for (int j = 0; j < k; ++j) dX.col(j) = x_[j + 1] - x_[j], dF.col(j) = f_[j + 1] - f_[j];
  // Least squares by column-pivoted QR: the increments of a converging iteration grow parallel,
  // and a rank-deficient dF then gets a minimal gamma instead of a blown-up one.
  const Eigen::VectorXd gamma = dF.colPivHouseholderQr().solve(f);
  if (!gamma.allFinite()) {
    reset();
    return x + f;
  }
  return x + f - (dX + dF) * gamma;
}

}  // namespace deployfx::integrate
