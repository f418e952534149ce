#pragma once
// The dense block products of the block LDL^T (math/block_ldlt.cpp), column-major: C = A B or
// C -= A B for a kBlock x kBlock A and a kBlock x kCols B (or B^T, kCols x kBlock). Eigen's own fixed-size 6 x 6 products
// run on two-lane packets (the largest packet that divides 6: SSE even on an AVX machine); for
// 6 x 6, where the CPU has AVX and FMA, rows 0-3 go in one four-lane register and rows 4-5 in a
// two-lane one, half the instructions. Every entry is formed exactly as Eigen forms it
// (ProductEvaluators.h, etor_product_packet_impl: a multiply by op(B)'s first row, five fused
// multiply-adds over k = 1..5, then the assignment or the subtraction from C), so the factor is
// bit for bit Eigen's. Other sizes, and CPUs without AVX and FMA, take Eigen's expression itself.
// C may be A (A is read whole first), or B if it has one column (read whole before C is written).
#include <Eigen/Core>

#if defined(__AVX__) && defined(__FMA__)
#include <immintrin.h>
#define DEPLOYFX_BLOCK6_AVX 1
#endif

namespace deployfx {

/// C = A op(B) (kSubtract false) or C -= A op(B) (true); op(B) = B^T if kTransposeB.
template <int kBlock, int kCols, bool kTransposeB, bool kSubtract>
inline void block_product(double* C, const double* A, const double* B) {
#ifdef DEPLOYFX_BLOCK6_AVX
  if constexpr (kBlock == 6) {
    __m256d lo[6];
    __m128d hi[6];
    for (int k = 0; k < 6; ++k) {
      lo[k] = _mm256_loadu_pd(A + 6 * k);
      hi[k] = _mm_loadu_pd(A + 6 * k + 4);
    }
    for (int c = 0; c < kCols; ++c) {
      auto b = [&](int k) { return kTransposeB ? B[c + kCols * k] : B[k + 6 * c]; };
      __m256d x = _mm256_mul_pd(lo[0], _mm256_set1_pd(b(0)));
      __m128d y = _mm_mul_pd(hi[0], _mm_set1_pd(b(0)));
      for (int k = 1; k < 6; ++k) {
        x = _mm256_fmadd_pd(lo[k], _mm256_set1_pd(b(k)), x);
        y = _mm_fmadd_pd(hi[k], _mm_set1_pd(b(k)), y);
      }
      if (kSubtract) {
        x = _mm256_sub_pd(_mm256_loadu_pd(C + 6 * c), x);
        y = _mm_sub_pd(_mm_loadu_pd(C + 6 * c + 4), y);
      }
      _mm256_storeu_pd(C + 6 * c, x);
      _mm_storeu_pd(C + 6 * c + 4, y);
    }
    return;
  }
#endif
  using Rhs = Eigen::Matrix<double, kTransposeB ? kCols : kBlock, kTransposeB ? kBlock : kCols>;
  Eigen::Map<Eigen::Matrix<double, kBlock, kCols>> c(C);
  const Eigen::Map<const Eigen::Matrix<double, kBlock, kBlock>> a(A);
  const Eigen::Map<const Rhs> b(B);
  if constexpr (kTransposeB) {
    if constexpr (kSubtract) c.noalias() -= a * b.transpose();
    else c = (a * b.transpose()).eval();
  } else {
    if constexpr (kSubtract) c.noalias() -= a * b;
    else c = (a * b).eval();
  }
}

}  // namespace deployfx
