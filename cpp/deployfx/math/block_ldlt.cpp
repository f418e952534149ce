#include "deployfx/math/block_ldlt.hpp"

#include <Eigen/Cholesky>  // LDLT
#include <Eigen/OrderingMethods>
#include <algorithm>
#include <cstring>
#include <limits>

#include "deployfx/math/block_product.hpp"
#include "deployfx/math/block_solve.hpp"

namespace deployfx {

namespace {
constexpr int kMaxBlock = 6;  // a shell node's dofs (fem::kNodeDofs)
// D^-1 from D's pivoted LDL^T, D = P^T L diag(d) L^T P: P^T L^-T diag(d)^-1 L^-1 P, L^-1 by forward
// substitution in fixed-size loops (LDLT::solve with a matrix right-hand side takes Eigen's general
// blocked triangular solve, a tenth of the factorization at 6 x 6).
template <int kBlock>
Eigen::Matrix<double, kBlock, kBlock> pivot_inverse(const Eigen::LDLT<Eigen::Matrix<double, kBlock, kBlock>>& ldlt) {
  using Block = Eigen::Matrix<double, kBlock, kBlock>;
  const Block& L = ldlt.matrixLDLT();  // L strictly below the diagonal
  Block Li = Block::Identity();
  for (int c = 0; c < kBlock; ++c)
    for (int r = c + 1; r < kBlock; ++r) {
      double s = 0;
      for (int k = c; k < r; ++k) s += L(r, k) * Li(k, c);
      Li(r, c) = -s;
    }
  const Block X = Li.transpose() * (ldlt.vectorD().cwiseInverse().asDiagonal() * Li);
  const Block Y = ldlt.transpositionsP().transpose() * X;              // P^T X
  return (ldlt.transpositionsP().transpose() * Y.transpose()).transpose();  // (P^T (P^T X)^T)^T = P^T X P
}

// kBlockRows for a block size known at run time (6 or 3).
int block_rows(int block) { return block == 3 ? kBlockRows<3> : kBlockRows<kMaxBlock>; }

}  // namespace

int BlockLDLT::stored_rows() const { return block_rows(block_); }

bool BlockLDLT::analyze(const SparseMatrix& A) {
  blocks_ = 0;
  block_ = 0;
  n_ = 0;
  if (A.rows() != A.cols() || !A.isCompressed()) return false;
  const int n = static_cast<int>(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  auto same_pattern = [&](int c, int d) {
    const int len = outer[c + 1] - outer[c];
    return len == outer[d + 1] - outer[d] &&
           std::memcmp(inner + outer[c], inner + outer[d],
                       sizeof(int) * static_cast<std::size_t>(len)) == 0;
  };
  // Groups: runs of at most kMaxBlock consecutive dofs with one column pattern.
  std::vector<int> group(n), local(n), group_size;
  for (int d = 0; d < n; ++d) {
    if (d > 0 && local[d - 1] + 1 < kMaxBlock && same_pattern(d - 1, d)) {
      group[d] = group[d - 1];
      local[d] = local[d - 1] + 1;
      ++group_size.back();
    } else {
      group[d] = static_cast<int>(group_size.size());
      local[d] = 0;
      group_size.push_back(1);
    }
  }
  const int ng = static_cast<int>(group_size.size());
  // Blocks of six (whole nodes, some with held dofs) or of three (a node's in-plane dofs).
  const int largest = *std::max_element(group_size.begin(), group_size.end());
  const int block = 4 * ng <= n ? kMaxBlock : largest <= 3 && 2 * ng <= n ? 3 : 0;
  if (block == 0) return false;
  const int rows = block_rows(block);  // a block's stored rows
  const int kSize = rows * block;  // values stored a block
  // The groups' graph (a group's first column holds its pattern) and its AMD ordering:
  // order[new] = old (the ordering's convention, as in CSparse's cs_amd), rank[old] = new.
  std::vector<Eigen::Triplet<double>> edges;
  for (int d = 0; d < n; ++d)
    if (local[d] == 0)
      for (int p = outer[d]; p < outer[d + 1]; ++p)
        edges.emplace_back(group[inner[p]], group[d], 1.0);
  SparseMatrix graph(ng, ng);
  graph.setFromTriplets(edges.begin(), edges.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::AMDOrdering<int>()(graph, order);
  std::vector<int> rank(ng);
  for (int k = 0; k < ng; ++k) rank[order.indices()[k]] = k;
  // The factor's pattern, column by column in the new order: column j holds A's lower pattern
  // and that of its children in the elimination tree, less j itself (Davis 2006, Sec. 4.1).
  std::vector<std::vector<int>> column(ng), children(ng);
  std::vector<int> mark(ng, -1);
  for (int g = 0; g < ng; ++g)
    for (SparseMatrix::InnerIterator it(graph, g); it; ++it)
      if (rank[it.row()] > rank[g]) column[rank[g]].push_back(rank[it.row()]);
  for (int j = 0; j < ng; ++j) {
    std::vector<int>& rows = column[j];
    for (int i : rows) mark[i] = j;
    for (int c : children[j])
      for (int i : column[c])
        if (i != j && mark[i] != j) {
          mark[i] = j;
          rows.push_back(i);
        }
    std::sort(rows.begin(), rows.end());
    if (!rows.empty()) children[rows.front()].push_back(j);  // the parent: the first row below j
  }
  off_begin_.assign(1, 0);
  off_rows_.clear();
  for (int j = 0; j < ng; ++j) {
    off_rows_.insert(off_rows_.end(), column[j].begin(), column[j].end());
    off_begin_.push_back(static_cast<int>(off_rows_.size()));
  }
  // Row j's blocks L_jk, k < j, in increasing k (compressed rows of the column pattern).
  row_begin_.assign(ng + 1, 0);
  for (int i : off_rows_) ++row_begin_[i + 1];
  for (int j = 0; j < ng; ++j) row_begin_[j + 1] += row_begin_[j];
  row_blocks_.assign(off_rows_.size(), 0);
  off_column_.assign(off_rows_.size(), 0);
  std::vector<int> next(row_begin_.begin(), row_begin_.end() - 1);
  for (int k = 0; k < ng; ++k)
    for (int t = off_begin_[k]; t < off_begin_[k + 1]; ++t) {
      row_blocks_[next[off_rows_[t]]++] = t;
      off_column_[t] = k;
    }
  // Where A's dofs and values go.
  dof_slot_.resize(n);
  for (int d = 0; d < n; ++d) dof_slot_[d] = rows * rank[group[d]] + local[d];
  padding_.clear();
  for (int g = 0; g < ng; ++g)
    for (int l = group_size[g]; l < block; ++l)
      padding_.push_back(kSize * 2 * rank[g] + l * (rows + 1));
  value_target_.assign(static_cast<std::size_t>(A.nonZeros()), -1);
  for (int c = 0; c < n; ++c)
    for (int p = outer[c]; p < outer[c + 1]; ++p) {
      const int r = inner[p];
      const int I = rank[group[r]], J = rank[group[c]];
      const long within = local[r] + rows * local[c];  // column-major within the block
      if (I == J) {
        value_target_[p] = static_cast<long>(kSize) * 2 * J + within;
      } else if (I > J) {
        const auto first = off_rows_.begin() + off_begin_[J];
        const auto last = off_rows_.begin() + off_begin_[J + 1];
        const int t = static_cast<int>(std::lower_bound(first, last, I) - off_rows_.begin());
        value_target_[p] = static_cast<long>(kSize) * (2 * ng + t) + within;
      }
    }
  values_.assign(static_cast<std::size_t>(kSize) * (2 * ng + off_rows_.size()), 0.0);
  position_.assign(ng, -1);
  n_ = n;
  block_ = block;
  blocks_ = ng;
  return true;
}

bool BlockLDLT::factorize(const SparseMatrix& A) {
  if (blocks_ == 0 || A.rows() != n_ ||
      A.nonZeros() != static_cast<Eigen::Index>(value_target_.size()))
    return false;
  std::fill(values_.begin(), values_.end(), 0.0);
  for (int k : padding_) values_[k] = 1.0;
  const double* a = A.valuePtr();
  for (std::size_t p = 0; p < value_target_.size(); ++p)
    if (value_target_[p] >= 0) values_[value_target_[p]] = a[p];
  return block_ == kMaxBlock ? factorize_blocks<kMaxBlock>() : factorize_blocks<3>();
}

template <int kBlock>
bool BlockLDLT::factorize_blocks() {
  constexpr int R = kBlockRows<kBlock>, kSize = R * kBlock;  // stored rows, values a block
  using Block = Eigen::Matrix<double, kBlock, kBlock>;
  using Stored = Eigen::Matrix<double, R, kBlock>;  // padding (rows kBlock .. R - 1) zero
  using Map = Eigen::Map<Block, 0, Eigen::OuterStride<R>>;
  double* off = values_.data() + static_cast<std::size_t>(kSize) * 2 * blocks_;
  for (int j = 0; j < blocks_; ++j) {
    for (int t = off_begin_[j]; t < off_begin_[j + 1]; ++t) position_[off_rows_[t]] = t;
    Map D(values_.data() + kSize * 2 * j);
    // Left-looking: column j less L_ik D_k L_jk^T for every k < j with L_jk != 0 (the rows i >= j
    // of column k follow row j in its ascending pattern).
    for (int u = row_begin_[j]; u < row_begin_[j + 1]; ++u) {
      const int s = row_blocks_[u], k = off_column_[s];
      const double* L_jk = off + kSize * s;
      Stored Y;  // L_jk D_k
      block_product<kBlock, kBlock, false, false>(Y.data(), L_jk, values_.data() + kSize * 2 * k);
      block_product<kBlock, kBlock, true, true>(D.data(), Y.data(), L_jk);  // D -= Y L_jk^T
      for (int t = s + 1; t < off_begin_[k + 1]; ++t)  // L_ij -= L_ik Y^T
        block_product<kBlock, kBlock, true, true>(off + kSize * position_[off_rows_[t]], off + kSize * t, Y.data());
    }
    const Block D_sym = 0.5 * (D + D.transpose());
    D = D_sym;
    const Eigen::LDLT<Block> ldlt(D_sym);
    // A pivot at or below the smallest normal double (LDLT::solve took it as zero) fails the
    // factorization: its inverse would overflow.
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().cwiseAbs().minCoeff() > std::numeric_limits<double>::min()))
      return false;
    Map D_inv(values_.data() + kSize * (2 * j + 1));
    D_inv = pivot_inverse(ldlt);
    if (!D_inv.allFinite()) return false;
    for (int t = off_begin_[j]; t < off_begin_[j + 1]; ++t) {
      double* W = off + kSize * t;  // L_ij = W_ij D_j^-1
      block_product<kBlock, kBlock, false, false>(W, W, D_inv.data());
    }
  }
  return true;
}

template <int kBlock, class Rhs>
void BlockLDLT::solve_in_place(Rhs& X) const {
  constexpr int R = kBlockRows<kBlock>, kSize = R * kBlock;
  constexpr int W = Rhs::ColsAtCompileTime;  // 1, or 8 (row-major: a block row's R x 8 contiguous)
  static_assert(W == 1 || (W == 8 && Rhs::IsRowMajor), "a vector or rows of eight");
  constexpr int kPanel = R * W;  // values of X a block row
  const double* off = values_.data() + static_cast<std::size_t>(kSize) * 2 * blocks_;
  double* x = X.data();
  for (int j = 0; j < blocks_; ++j) {  // L y = b, by columns (unit diagonal)
    const ColumnSubtract<kBlock, W> subtract(x + kPanel * j);
    for (int t = off_begin_[j]; t < off_begin_[j + 1]; ++t) subtract(x + kPanel * off_rows_[t], off + kSize * t);
  }
  for (int j = blocks_ - 1; j >= 0; --j) {  // L^T x = D^-1 y: row j of L^T is column j of L
    double* x_j = x + kPanel * j;
    const double* D_inv = values_.data() + kSize * (2 * j + 1);
    if constexpr (W == 1) {
      block_product<kBlock, 1, false, false>(x_j, D_inv, x_j);
    } else {
      Eigen::Map<BlockPanel<kBlock, W>> panel(x_j);
      panel = (Eigen::Map<const StoredBlock<kBlock>>(D_inv) * panel.template topRows<kBlock>()).eval();
    }
    TransposedSum<kBlock, W> sum;
    for (int t = off_begin_[j]; t < off_begin_[j + 1]; ++t) sum.add(off + kSize * t, x + kPanel * off_rows_[t]);
    sum.subtract_from(x_j);
  }
}

template <class Rhs>
void BlockLDLT::solve_padded(Rhs& X) const {
  if (block_ == kMaxBlock)
    solve_in_place<kMaxBlock>(X);
  else
    solve_in_place<3>(X);
}

Eigen::VectorXd BlockLDLT::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(stored_rows()) * blocks_);
  for (int d = 0; d < n_; ++d) x(dof_slot_[d]) = b(d);
  solve_padded(x);
  Eigen::VectorXd out(n_);
  for (int d = 0; d < n_; ++d) out(d) = x(dof_slot_[d]);
  return out;
}

Eigen::MatrixXd BlockLDLT::solve(const Eigen::MatrixXd& B) const {
  // Up to kWidth columns at a time, as rows of kWidth contiguous values: each block update is one
  // fixed-size (6 x 6) (6 x kWidth) (or padded 3 x 3, 4 x kWidth) product.
  constexpr int kWidth = 8;
  Eigen::MatrixXd out(n_, B.cols());
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, kWidth, Eigen::RowMajor>;
  Rows X(static_cast<Eigen::Index>(stored_rows()) * blocks_, kWidth);
  for (Eigen::Index c0 = 0; c0 < B.cols(); c0 += kWidth) {
    const Eigen::Index w = std::min<Eigen::Index>(kWidth, B.cols() - c0);
    if (w == 1) {  // one column: the vector kernels (an eight-wide pass costs several of them)
      out.col(c0) = solve(Eigen::VectorXd(B.col(c0)));
      continue;
    }
    X.setZero();
    for (int d = 0; d < n_; ++d) X.row(dof_slot_[d]).head(w) = B.row(d).segment(c0, w);
    solve_padded(X);
    for (int d = 0; d < n_; ++d) out.row(d).segment(c0, w) = X.row(dof_slot_[d]).head(w);
  }
  return out;
}

}  // namespace deployfx
