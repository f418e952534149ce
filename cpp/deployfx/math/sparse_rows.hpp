#pragma once
// Sparse matrix-vector products by rows with the sums of Eigen's column-major product. Eigen's
// A z for a column-major A scatters column by column, y_r += A_rc z_c (c ascending), a
// read-modify-write through memory per term whose store-to-load latency bounds the loop; row r's
// terms in that order are row r's entries of A by rows, and gathered there each y_r is one chain
// in a register. Each term is fused where the target has FMA, as the compiler contracts Eigen's
// scatter there (its heuristics for chains in a register differ: GCC's Zen tuning leaves some
// unfused), so the results are Eigen's bit for bit.
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <vector>

namespace deployfx {

/// a b + s, fused where the target has FMA; a plain product and sum otherwise.
inline double fused(double a, double b, double s) {
#ifdef __FMA__
  return std::fma(a, b, s);
#else
  return s + a * b;
#endif
}

/// y_v = (alpha A) z_v, summed from zero (kOnto false) or onto y_v's values (kOnto true), for V
/// vectors in one pass over A's rows; z_v and y_v distinct. (Eigen forms alpha * (A * z) from
/// zero with the terms (alpha A_rc) z_c, and adds it to a vector after.)
template <int V, bool kOnto>
void rows_product(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A, const std::array<const double*, V>& z,
                  const std::array<double*, V>& y, double alpha = 1.0) {
  const int* outer = A.outerIndexPtr();
  const int* col = A.innerIndexPtr();
  const double* val = A.valuePtr();
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    std::array<double, V> sum;
    for (int v = 0; v < V; ++v) sum[v] = kOnto ? y[v][r] : 0.0;
    for (int k = outer[r]; k < outer[r + 1]; ++k)
      for (int v = 0; v < V; ++v) sum[v] = fused(alpha * val[k], z[v][col[k]], sum[v]);
    for (int v = 0; v < V; ++v) y[v][r] = sum[v];
  }
}

/// The entries of A's rows `rows` (in that order) as triplets of rows first, first + 1, ...: a
/// selection of rows to stack and build (setFromTriplets), e.g. a residual's rows formed alone.
inline void append_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A, const std::vector<int>& rows,
                        Eigen::Index first, std::vector<Eigen::Triplet<double>>& out) {
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(A, rows[i]); it; ++it)
      out.emplace_back(static_cast<int>(first + static_cast<Eigen::Index>(i)), static_cast<int>(it.col()), it.value());
}

}  // namespace deployfx
