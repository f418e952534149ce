#include "deployfx/math/dense_lu.hpp"

#include <cmath>
#include <utility>

namespace deployfx {

Eigen::Block<Eigen::MatrixXd> DenseLU::matrix(Eigen::Index n) {
  const Eigen::Index ld = (n + kChunk - 1) / kChunk * kChunk;
  if (lu_.rows() != ld || lu_.cols() != n) lu_.resize(ld, n);  // the same size keeps the storage
  n_ = n;
  lu_.bottomRows(ld - n).setZero();
  return lu_.topRows(n);
}

// Column k's pivot: the largest entry at or below the diagonal (the first of equals), its row
// swapped with row k across the whole matrix, the multipliers below it scaled.
bool DenseLU::pivot_column(Eigen::Index k) {
  const Eigen::Index n = n_, ld = lu_.rows();
  double* a = lu_.data();
  double* ck = a + k * ld;
  Eigen::Index p = k;
  double largest = std::abs(ck[k]);
  for (Eigen::Index i = k + 1; i < n; ++i)
    if (std::abs(ck[i]) > largest) largest = std::abs(ck[i]), p = i;
  if (!(largest > 1e-300) || !std::isfinite(largest)) return false;
  pivot_[static_cast<std::size_t>(k)] = static_cast<int>(p);
  if (p != k)
    for (Eigen::Index j = 0; j < n; ++j) std::swap(a[k + j * ld], a[p + j * ld]);
  const double inverse = 1.0 / ck[k];
  for (Eigen::Index i = k + 1; i < n; ++i) ck[i] *= inverse;  // column k of L
  return true;
}

bool DenseLU::factorize() {
  const Eigen::Index n = n_, ld = lu_.rows();
  if (lu_.cols() != n) return false;
  blocked_ = n > kUnblocked;
  if (blocked_) {
    blocked_lu_.compute(lu_.topRows(n));
    const Eigen::MatrixXd& f = blocked_lu_.matrixLU();
    return f.diagonal().cwiseAbs().minCoeff() > 1e-300 && f.allFinite();
  }
  using Chunk = Eigen::Map<Eigen::Vector4d>;
  using ConstChunk = Eigen::Map<const Eigen::Vector4d>;
  static_assert(kChunk == 4, "a chunk is one Vector4d");
  pivot_.resize(static_cast<std::size_t>(n));
  double* a = lu_.data();
  for (Eigen::Index k = 0; k < n; k += 2) {
    if (!pivot_column(k)) return false;
    if (k + 1 == n) break;
    const double* ck = a + k * ld;
    double* c1 = a + (k + 1) * ld;
    {  // column k + 1 less column k's term, then its pivot
      const double u = c1[k];
      for (Eigen::Index i = k + 1; i < n; ++i) c1[i] -= ck[i] * u;
    }
    if (!pivot_column(k + 1)) return false;
    // The trailing columns j > k + 1 less both terms, a_ij - l_ik u_kj - l_i(k+1) u_(k+1)j, by
    // chunks from the one holding row k + 1 (whose new entry is u_(k+1)j: l_(k+1)(k+1) taken as
    // zero); in that chunk the rows at or above a pivot take zero multipliers, and stay.
    const Eigen::Index i0 = (k + 1) / kChunk * kChunk;  // ld >= i0 + kChunk
    alignas(32) double l0[kChunk], l1[kChunk];          // that chunk's multipliers
    for (Eigen::Index t = 0; t < kChunk; ++t) {
      l0[t] = i0 + t > k ? ck[i0 + t] : 0.0;
      l1[t] = i0 + t > k + 1 ? c1[i0 + t] : 0.0;
    }
    for (Eigen::Index j = k + 2; j < n; ++j) {
      double* cj = a + j * ld;
      const double u0 = cj[k], u1 = cj[k + 1] - ck[k + 1] * u0;
      Chunk(cj + i0) = Chunk(cj + i0) - u0 * ConstChunk(l0) - u1 * ConstChunk(l1);
      for (Eigen::Index i = i0 + kChunk; i < ld; i += kChunk)
        Chunk(cj + i) = Chunk(cj + i) - u0 * ConstChunk(ck + i) - u1 * ConstChunk(c1 + i);
    }
  }
  return lu_.topRows(n).allFinite();  // a non-finite entry off the pivots' path
}

void DenseLU::solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const {
  if (blocked_) {
    x = blocked_lu_.solve(Eigen::VectorXd(x));
    return;
  }
  for (std::size_t k = 0; k < pivot_.size(); ++k)
    if (pivot_[k] != static_cast<int>(k)) std::swap(x(static_cast<Eigen::Index>(k)), x(pivot_[k]));
  const auto f = lu_.topRows(n_);
  f.triangularView<Eigen::UnitLower>().solveInPlace(x);
  f.triangularView<Eigen::Upper>().solveInPlace(x);
}

}  // namespace deployfx
