#include "deployfx/integrate/anderson.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace deployfx::integrate {

void AndersonMixing::update(Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  if (m_ <= 0) {
    x += f;
    return;
  }
  const Eigen::Index n = x.size();
  if (x_.rows() != n) {  // a new system size: new storage, no history
    x_.resize(n, m_ + 1), f_.resize(n, m_ + 1);
    dX_.resize(n, m_), dF_.resize(n, m_), Q_.resize(n, m_), R_.resize(m_, m_);
    gamma_.resize(m_), c_.resize(m_), r_.resize(n);
    perm_.resize(static_cast<std::size_t>(m_));
    count_ = 0;
  }
  newest_ = count_ == 0 ? 0 : (newest_ + 1) % (m_ + 1);
  x_.col(newest_) = x, f_.col(newest_) = f;
  count_ = std::min(count_ + 1, m_ + 1);
  const int k = count_ - 1;
  if (k == 0) {
    x += f;
    return;
  }
  // The differences of consecutive pairs, oldest first.
  for (int j = 0; j < k; ++j) {
    const int a = (newest_ - k + j + 2 * (m_ + 1)) % (m_ + 1), b = (a + 1) % (m_ + 1);
    dX_.col(j) = x_.col(b) - x_.col(a);
    dF_.col(j) = f_.col(b) - f_.col(a);
  }
  x += f;
  if (!least_squares(k, f)) {
    reset();
    return;
  }
  for (int j = 0; j < k; ++j) x -= gamma_(j) * (dX_.col(j) + dF_.col(j));
}

bool AndersonMixing::least_squares(int k, const Eigen::VectorXd& f) {
  // Modified Gram-Schmidt with column pivoting, f carried along as one more column (Bjorck,
  // Numerical Methods for Least Squares Problems, 1996, Sec. 2.4.3: backward stable so). The
  // increments of a converging iteration grow parallel: a column whose remaining norm is at or
  // below eps k times the first pivot's is dropped and its gamma set to zero (a basic solution,
  // as a column-pivoted Householder QR with Eigen's default threshold gives), not blown up.
  Q_.leftCols(k) = dF_.leftCols(k);
  r_ = f;
  for (int j = 0; j < k; ++j) perm_[static_cast<std::size_t>(j)] = j;
  const double threshold = std::numeric_limits<double>::epsilon() * k;
  int rank = 0;
  double first = 0;
  for (int i = 0; i < k; ++i) {
    int p = i;
    double best = Q_.col(i).squaredNorm();
    for (int j = i + 1; j < k; ++j)
      if (const double s = Q_.col(j).squaredNorm(); s > best) best = s, p = j;
    if (p != i) {  // the column and its coefficients so far trade places with column i
      Q_.col(i).swap(Q_.col(p));
      R_.col(i).head(i).swap(R_.col(p).head(i));
      std::swap(perm_[static_cast<std::size_t>(i)], perm_[static_cast<std::size_t>(p)]);
    }
    const double rii = std::sqrt(best);
    if (i == 0) first = rii;
    if (!(rii > threshold * first)) break;  // also a zero or non-finite first column
    R_(i, i) = rii;
    Q_.col(i) /= rii;
    for (int j = i + 1; j < k; ++j) {
      R_(i, j) = Q_.col(i).dot(Q_.col(j));
      Q_.col(j) -= R_(i, j) * Q_.col(i);
    }
    c_(i) = Q_.col(i).dot(r_);
    r_ -= c_(i) * Q_.col(i);
    rank = i + 1;
  }
  gamma_.head(k).setZero();
  for (int i = rank - 1; i >= 0; --i) {  // R y = c, y in pivoted order
    double y = c_(i);
    for (int j = i + 1; j < rank; ++j) y -= R_(i, j) * c_(j);
    c_(i) = y / R_(i, i);
  }
  for (int i = 0; i < rank; ++i) gamma_(perm_[static_cast<std::size_t>(i)]) = c_(i);
  return gamma_.head(k).allFinite();
}

}  // namespace deployfx::integrate
