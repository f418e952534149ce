#pragma once
// The block kernels of the block LDL^T's triangular solves (math/block_ldlt.cpp), on panels of
// W right-hand sides (W = 1: a vector segment; W = 8: rows of a row-major (n x 8) panel,
// contiguous) of kBlockRows<kBlock> rows a block (math/block_product.hpp: 3 dofs padded to 4,
// the padding zero), against the factor's column-major blocks A:
// - ColumnSubtract: x -= A y for one y and many (A, x) (column j of L in L y = b): y is read, and
//   for W = 1 broadcast, once for the whole column;
// - TransposedSum: sum_t A_t^T x_t (row j of L^T in L^T x = z). Each A_t^T x_t as a product of its
//   own is kBlock dot products whose sums wait on their own additions; here the products
//   accumulate lane by lane across t and are summed across lanes once at the end (W = 1), or each
//   row of the panel sum stays in registers across t (W = 8).
// Where the CPU has AVX and FMA, 6 x 6 blocks run on four- and two-lane registers (rows 0-3 and
// 4-5), padded 3 x 3 ones on one four-lane register a column; ColumnSubtract for W = 1 forms each
// entry as block_product does (a product, then the subtraction), so the forward solve is bit for
// bit the blocks' products; the sums of TransposedSum, and the W = 8 kernels, run in another order
// than Eigen's products (round-off apart). CPUs without AVX and FMA take Eigen's expressions.
#include <Eigen/Core>

#include "deployfx/math/block_product.hpp"  // DEPLOYFX_BLOCK6_AVX, <immintrin.h>

namespace deployfx {

template <int kBlock, int W>
using BlockPanel = Eigen::Matrix<double, kBlockRows<kBlock>, W, W == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
template <int kBlock>
using StoredBlock = Eigen::Matrix<double, kBlockRows<kBlock>, kBlock>;

/// x -= A y, y fixed.
template <int kBlock, int W>
class ColumnSubtract {
 public:
  explicit ColumnSubtract(const double* y) : y_(y) {}
  void operator()(double* x, const double* A) const {
    Eigen::Map<BlockPanel<kBlock, W>>(x).noalias() -=
        Eigen::Map<const StoredBlock<kBlock>>(A) *
        Eigen::Map<const BlockPanel<kBlock, W>>(y_).template topRows<kBlock>();
  }

 private:
  const double* y_;
};

/// s = sum_t A_t^T x_t, then y -= s.
template <int kBlock, int W>
class TransposedSum {
 public:
  TransposedSum() { s_.setZero(); }
  void add(const double* A, const double* x) {
    s_.noalias() += Eigen::Map<const StoredBlock<kBlock>>(A).transpose() * Eigen::Map<const BlockPanel<kBlock, W>>(x);
  }
  void subtract_from(double* y) const { Eigen::Map<BlockPanel<kBlock, W>>(y).template topRows<kBlock>() -= s_; }

 private:
  Eigen::Matrix<double, kBlock, W, W == 1 ? Eigen::ColMajor : Eigen::RowMajor> s_;
};

#ifdef DEPLOYFX_BLOCK6_AVX
template <>
class ColumnSubtract<3, 1> {
 public:
  explicit ColumnSubtract(const double* y) : y0_(_mm256_set1_pd(y[0])), y1_(_mm256_set1_pd(y[1])), y2_(_mm256_set1_pd(y[2])) {}
  void operator()(double* x, const double* A) const {
    const __m256d p = _mm256_fmadd_pd(_mm256_loadu_pd(A + 8), y2_,
                                      _mm256_fmadd_pd(_mm256_loadu_pd(A + 4), y1_, _mm256_mul_pd(_mm256_loadu_pd(A), y0_)));
    _mm256_storeu_pd(x, _mm256_sub_pd(_mm256_loadu_pd(x), p));
  }

 private:
  __m256d y0_, y1_, y2_;
};

template <>
class TransposedSum<3, 1> {
 public:
  TransposedSum() : s0_(_mm256_setzero_pd()), s1_(s0_), s2_(s0_) {}
  void add(const double* A, const double* x) {  // x's padding and A's are zero
    const __m256d v = _mm256_loadu_pd(x);
    s0_ = _mm256_fmadd_pd(_mm256_loadu_pd(A), v, s0_);
    s1_ = _mm256_fmadd_pd(_mm256_loadu_pd(A + 4), v, s1_);
    s2_ = _mm256_fmadd_pd(_mm256_loadu_pd(A + 8), v, s2_);
  }
  void subtract_from(double* y) const {
    y[0] -= lane_sum(s0_);
    y[1] -= lane_sum(s1_);
    y[2] -= lane_sum(s2_);
  }

 private:
  static double lane_sum(__m256d v) {
    const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
  }
  __m256d s0_, s1_, s2_;
};

template <>
class ColumnSubtract<6, 1> {
 public:
  explicit ColumnSubtract(const double* y) {
    for (int k = 0; k < 6; ++k) lo_[k] = _mm256_set1_pd(y[k]), hi_[k] = _mm_set1_pd(y[k]);
  }
  void operator()(double* x, const double* A) const {
    __m256d p = _mm256_mul_pd(_mm256_loadu_pd(A), lo_[0]);
    __m128d q = _mm_mul_pd(_mm_loadu_pd(A + 4), hi_[0]);
    for (int k = 1; k < 6; ++k) {
      p = _mm256_fmadd_pd(_mm256_loadu_pd(A + 6 * k), lo_[k], p);
      q = _mm_fmadd_pd(_mm_loadu_pd(A + 6 * k + 4), hi_[k], q);
    }
    _mm256_storeu_pd(x, _mm256_sub_pd(_mm256_loadu_pd(x), p));
    _mm_storeu_pd(x + 4, _mm_sub_pd(_mm_loadu_pd(x + 4), q));
  }

 private:
  __m256d lo_[6];
  __m128d hi_[6];
};

template <>
class TransposedSum<6, 1> {
 public:
  TransposedSum() {
    for (int i = 0; i < 6; ++i) lo_[i] = _mm256_setzero_pd(), hi_[i] = _mm_setzero_pd();
  }
  void add(const double* A, const double* x) {  // lanes of column i of A times x
    const __m256d xl = _mm256_loadu_pd(x);
    const __m128d xh = _mm_loadu_pd(x + 4);
    for (int i = 0; i < 6; ++i) {
      lo_[i] = _mm256_fmadd_pd(_mm256_loadu_pd(A + 6 * i), xl, lo_[i]);
      hi_[i] = _mm_fmadd_pd(_mm_loadu_pd(A + 6 * i + 4), xh, hi_[i]);
    }
  }
  void subtract_from(double* y) const {
    for (int i = 0; i < 6; ++i) {
      const __m128d s = _mm_add_pd(_mm_add_pd(_mm256_castpd256_pd128(lo_[i]), _mm256_extractf128_pd(lo_[i], 1)), hi_[i]);
      y[i] -= _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
    }
  }

 private:
  __m256d lo_[6];
  __m128d hi_[6];
};

template <>
class ColumnSubtract<6, 8> {
 public:
  explicit ColumnSubtract(const double* y) {
    for (int k = 0; k < 6; ++k) lo_[k] = _mm256_loadu_pd(y + 8 * k), hi_[k] = _mm256_loadu_pd(y + 8 * k + 4);
  }
  void operator()(double* x, const double* A) const {  // row i of x less sum_k A(i, k) row k of y
    for (int i = 0; i < 6; ++i) {
      __m256d p = _mm256_loadu_pd(x + 8 * i), q = _mm256_loadu_pd(x + 8 * i + 4);
      for (int k = 0; k < 6; ++k) {
        const __m256d a = _mm256_broadcast_sd(A + i + 6 * k);
        p = _mm256_fnmadd_pd(a, lo_[k], p);
        q = _mm256_fnmadd_pd(a, hi_[k], q);
      }
      _mm256_storeu_pd(x + 8 * i, p);
      _mm256_storeu_pd(x + 8 * i + 4, q);
    }
  }

 private:
  __m256d lo_[6], hi_[6];  // y's rows
};

template <>
class TransposedSum<6, 8> {
 public:
  TransposedSum() {
    for (int i = 0; i < 6; ++i) lo_[i] = _mm256_setzero_pd(), hi_[i] = _mm256_setzero_pd();
  }
  void add(const double* A, const double* x) {  // row i of the sum gains A(r, i) row r of x
    for (int r = 0; r < 6; ++r) {
      const __m256d xl = _mm256_loadu_pd(x + 8 * r), xh = _mm256_loadu_pd(x + 8 * r + 4);
      for (int i = 0; i < 6; ++i) {
        const __m256d a = _mm256_broadcast_sd(A + r + 6 * i);
        lo_[i] = _mm256_fmadd_pd(a, xl, lo_[i]);
        hi_[i] = _mm256_fmadd_pd(a, xh, hi_[i]);
      }
    }
  }
  void subtract_from(double* y) const {
    for (int i = 0; i < 6; ++i) {
      _mm256_storeu_pd(y + 8 * i, _mm256_sub_pd(_mm256_loadu_pd(y + 8 * i), lo_[i]));
      _mm256_storeu_pd(y + 8 * i + 4, _mm256_sub_pd(_mm256_loadu_pd(y + 8 * i + 4), hi_[i]));
    }
  }

 private:
  __m256d lo_[6], hi_[6];
};
#endif

}  // namespace deployfx
