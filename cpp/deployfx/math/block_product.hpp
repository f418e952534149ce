#pragma once
// The dense block products of the block LDL^T (math/block_ldlt.cpp), column-major: C = A B or
// C -= A B for a kBlock x kBlock A and a kBlock x kCols B (or B^T, B kCols x kBlock), each block
// (B and B^T's B too) stored with kBlockRows<kBlock> rows, its leading dimension (6 x 6 as it
// is; 3 x 3 padded to 4 rows with a zero row, so that a column is one four-lane register; a
// vector of kCols = 1 likewise). Eigen's own
// fixed-size 6 x 6 products run on two-lane packets (the largest packet that divides 6: SSE even
// on an AVX machine); for 6 x 6, where the CPU has AVX and FMA, rows 0-3 go in one four-lane
// register and rows 4-5 in a two-lane one, half the instructions. Every entry is formed exactly
// as Eigen forms it (ProductEvaluators.h, etor_product_packet_impl: a multiply by op(B)'s first
// row, fused multiply-adds over the rest of k, then the assignment or the subtraction from C), so
// the factor is bit for bit Eigen's. CPUs without AVX and FMA take Eigen's expression itself.
// Without kSubtract C may be A (A is read whole first), or B if it has one column (read whole
// before C is written); with it C must be neither (Eigen's path subtracts without a temporary).
#include <Eigen/Core>

#if defined(__AVX__) && defined(__FMA__)
#include <immintrin.h>
#define DEPLOYFX_BLOCK6_AVX 1
#endif

namespace deployfx {

/// Rows a block of kBlock dofs is stored with: 3 padded to 4 (one AVX register a column), else kBlock.
template <int kBlock>
constexpr int kBlockRows = kBlock == 3 ? 4 : kBlock;

/// C = A op(B) (kSubtract false) or C -= A op(B) (true); op(B) = B^T if kTransposeB; every block
/// (and a vector, kCols = 1) stored with kBlockRows<kBlock> rows, its padding zero.
template <int kBlock, int kCols, bool kTransposeB, bool kSubtract>
inline void block_product(double* C, const double* A, const double* B) {
  constexpr int R = kBlockRows<kBlock>;
#ifdef DEPLOYFX_BLOCK6_AVX
  if constexpr (kBlock == 3) {
    const __m256d a0 = _mm256_loadu_pd(A), a1 = _mm256_loadu_pd(A + 4), a2 = _mm256_loadu_pd(A + 8);
    for (int c = 0; c < kCols; ++c) {
      auto b = [&](int k) { return _mm256_set1_pd(kTransposeB ? B[c + R * k] : B[k + R * c]); };
      const __m256d b0 = b(0), b1 = b(1), b2 = b(2);
      __m256d x = _mm256_fmadd_pd(a2, b2, _mm256_fmadd_pd(a1, b1, _mm256_mul_pd(a0, b0)));
      if (kSubtract) x = _mm256_sub_pd(_mm256_loadu_pd(C + R * c), x);
      _mm256_storeu_pd(C + R * c, x);
    }
    return;
  }
  if constexpr (kBlock == 6) {
    __m256d lo[6];
    __m128d hi[6];
    for (int k = 0; k < 6; ++k) {
      lo[k] = _mm256_loadu_pd(A + 6 * k);
      hi[k] = _mm_loadu_pd(A + 6 * k + 4);
    }
    for (int c = 0; c < kCols; ++c) {
      auto b = [&](int k) { return kTransposeB ? B[c + R * k] : B[k + R * c]; };
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
  // op(B) from B's stored (R x kBlock) or (R x kCols) rows.
  Eigen::Map<Eigen::Matrix<double, R, kCols>> c(C);
  const Eigen::Map<const Eigen::Matrix<double, R, kBlock>> a(A);
  if constexpr (kTransposeB) {
    const auto b = Eigen::Map<const Eigen::Matrix<double, R, kBlock>>(B).template topRows<kCols>();
    if constexpr (kSubtract) c.noalias() -= a * b.transpose();
    else c = (a * b.transpose()).eval();
  } else {
    const auto b = Eigen::Map<const Eigen::Matrix<double, R, kCols>>(B).template topRows<kBlock>();
    if constexpr (kSubtract) c.noalias() -= a * b;
    else c = (a * b).eval();
  }
}

}  // namespace deployfx
