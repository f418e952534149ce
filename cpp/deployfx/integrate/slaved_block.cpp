#include "deployfx/integrate/slaved_block.hpp"

#include <algorithm>
#include <stdexcept>

namespace deployfx::integrate {

namespace {
// A block this small, or at least this dense, is factorized densely: below it a dense LU costs
// less than the sparse one's analysis and supernodes.
constexpr int kDenseSize = 128;
constexpr double kDenseFill = 0.25;
bool dense_block(const Eigen::SparseMatrix<double>& E) {
  const double m = static_cast<double>(E.rows());
  return m <= kDenseSize || static_cast<double>(E.nonZeros()) >= kDenseFill * m * m;
}
}  // namespace

void SlavedBlock::restore(const BlockMatrix& block) {
  if (block.border() != 0 || block.B.rows() != 0 || block.C.cols() != 0 || block.E.rows() != block.E.cols() ||
      !block.E.isCompressed())
    throw std::invalid_argument("SlavedBlock::restore: a square, compressed block without border expected");
  block_ = block;
  dense_ = dense_block(block_.E);
  idx_.clear();  // the next set() analyses its matrix's pattern
  border_ = -1;
  state_ = State::kSet;
}

void SlavedBlock::analyze(const BlockMatrix& S, const std::vector<int>& idx) {
  if (!S.E.isCompressed()) throw std::logic_error("SlavedBlock: the elastic block must be compressed");
  const int nb = S.border(), n = S.size(), m = static_cast<int>(idx.size());
  std::vector<int> pos(n, -1);  // idx's position of each coordinate (-1: not in idx)
  for (int i = 0; i < m; ++i) {
    if (idx[i] < 0 || idx[i] >= n) throw std::out_of_range("SlavedBlock: index out of range");
    pos[idx[i]] = i;
  }
  // Column by column, the block's rows and where their values come from, rows ascending.
  std::vector<std::pair<int, Source>> column;
  std::vector<int> outer(1, 0), inner;
  sources_.clear();
  for (int jj = 0; jj < m; ++jj) {
    const int j = idx[jj];
    column.clear();
    if (j < nb) {  // a border column: A above, C below
      for (int i = 0; i < m; ++i)
        column.push_back({i, idx[i] < nb ? Source{kA, idx[i] + static_cast<Eigen::Index>(j) * nb}
                                         : Source{kC, idx[i] - nb + static_cast<Eigen::Index>(j) * S.C.rows()}});
    } else {  // an elastic column: B above, E's stored entries below
      for (int i = 0; i < m; ++i)
        if (idx[i] < nb) column.push_back({i, Source{kB, idx[i] + static_cast<Eigen::Index>(j - nb) * nb}});
      const int* rows = S.E.innerIndexPtr();
      for (int p = S.E.outerIndexPtr()[j - nb]; p < S.E.outerIndexPtr()[j - nb + 1]; ++p)
        if (pos[nb + rows[p]] >= 0) column.push_back({pos[nb + rows[p]], Source{kE, p}});
    }
    std::sort(column.begin(), column.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [row, source] : column) inner.push_back(row), sources_.push_back(source);
    outer.push_back(static_cast<int>(inner.size()));
  }
  Eigen::SparseMatrix<double>& E = block_.E;
  E.resize(m, m);
  E.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), E.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), E.innerIndexPtr());
  block_.A.resize(0, 0);
  block_.B.resize(0, m);
  block_.C.resize(m, 0);
  dense_ = dense_block(E);
  idx_ = idx;
  border_ = nb;
  elastic_ = S.elastic();
  elastic_nnz_ = S.E.nonZeros();
}

void SlavedBlock::set(const BlockMatrix& S, const std::vector<int>& idx) {
  if (S.border() != border_ || S.elastic() != elastic_ || S.E.nonZeros() != elastic_nnz_ || idx != idx_)
    analyze(S, idx);
  const double* part[4] = {S.A.data(), S.B.data(), S.C.data(), S.E.valuePtr()};
  double* value = block_.E.valuePtr();
  for (std::size_t k = 0; k < sources_.size(); ++k) value[k] = part[sources_[k].part][sources_[k].offset];
  state_ = State::kSet;
}

bool SlavedBlock::solve(const Eigen::VectorXd& r, Eigen::VectorXd* d) {
  if (state_ == State::kSet) {
    bool factorized = true;
    if (dense_) {
      dense_lu_.matrix(block_.E.rows()) = block_.E;
      factorized = dense_lu_.factorize();
    } else {
      factorized = sparse_.factorize(block_);
    }
    state_ = factorized ? State::kFactorized : State::kSingular;
  }
  if (state_ != State::kFactorized) return false;
  Eigen::VectorXd x = dense_ ? Eigen::VectorXd(dense_lu_.solve(r)) : sparse_.solve(r, false);
  if (!x.allFinite()) return false;
  *d = std::move(x);
  return true;
}

}  // namespace deployfx::integrate
